#include "kb/knowledge_base.hpp"

#include "kb/sparql_form.hpp"

#include <algorithm>
#include <iterator>
#include <set>

#include "kb/owl/embedded_ontologies.hpp"
#include "kb/owl/nodeset_ontology.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb {
namespace {

const std::string kRdfType = std::string(rdf::vocab::kRdf) + "type";

// The blank node scope of the n-th graph of a load or a recording: "g<n>x", which no label
// that Virtuoso writes begins with.
std::string blankScope(std::size_t n) {
    return "g" + std::to_string(n) + "x";
}

std::string registryMember() {
    return std::string(kKbVocabulary) + "Graph";
}

// One line per triple, for people: the report of a refused load.
std::string describe(const std::vector<rdf::Triple>& triples) {
    std::string out;
    for (const auto& t : triples) {
        std::string line = rdf::writeNTriples({t});
        while (!line.empty() && line.back() == '\n') line.pop_back();
        out += "\n  " + line;
    }
    return out;
}

}  // namespace

Expected<std::string> sparqlIri(const std::string& iri) {
    for (char c : iri) {
        const auto u = static_cast<unsigned char>(c);
        if (u <= 0x20 || c == '<' || c == '>' || c == '"' || c == '{' || c == '}' || c == '|' ||
            c == '^' || c == '`' || c == '\\') {
            return Error{"'" + iri + "' is not an IRI SPARQL can take", ErrorKind::BadInput};
        }
    }
    if (iri.empty()) return Error{"empty IRI", ErrorKind::BadInput};
    return "<" + iri + ">";
}

Expected<std::vector<rdf::Triple>> KnowledgeBase::everythingBut(
    const std::vector<std::string>& graphIris) {
    std::string filter;
    for (const auto& g : graphIris) {
        auto ref = sparqlIri(g);
        if (!ref) return ref.failure();
        filter += (filter.empty() ? "FILTER(?g NOT IN (" : ", ") + *ref;
    }
    if (!filter.empty()) filter += "))";
    const std::string q = "CONSTRUCT { ?s ?p ?o } WHERE { GRAPH <" + std::string(kRegistryGraph) +
                          "> { ?g a <" + registryMember() + "> } GRAPH ?g { ?s ?p ?o } " + filter +
                          " }";
    // N-Triples: Virtuoso's Turtle writes an xsd:double 2 as "2.0", which reads back as an
    // xsd:decimal (and then contradicts a range of xsd:double).
    auto r = store_.query(q, media::kNTriples);
    if (!r) return r.failure();
    return rdf::readTurtle(r->body);
}

std::vector<Status> KnowledgeBase::loadParts(const std::vector<std::vector<GraphData>>& parts) {
    std::vector<GraphData> all;
    std::set<std::string> iris;
    for (const auto& part : parts) {
        for (const auto& g : part) {
            all.push_back(g);
            iris.insert(g.iri);
        }
    }
    const bool oneLoad =
        parts.size() > 1 && all.size() <= kMaxGraphsPerLoad && iris.size() == all.size();
    if (oneLoad) {
        auto together = load(all);
        if (together || together.errorKind() != ErrorKind::Refused) {
            return std::vector<Status>(parts.size(), together);
        }
    }
    std::vector<Status> each;
    each.reserve(parts.size());
    for (const auto& part : parts) each.push_back(load(part));
    return each;
}

Status KnowledgeBase::refusal(const std::vector<std::string>& names,
                              const std::vector<rdf::Triple>& rest,
                              const std::vector<rdf::Triple>& incoming) const {
    std::string what = "refused: loading ";
    for (const auto& n : names) what += "<" + n + "> ";
    what += "would make the knowledge base inconsistent";
    auto why = reasoner_->explainInconsistency(rest, incoming);
    if (!why) {
        return Error{what + " (no explanation: " + why.error() + ")", ErrorKind::Refused};
    }
    if (!why->inconsistent) {
        return Error{what +
                         " (the reasoner found no conflict in the new statements "
                         "alone; the loaded models conflict among themselves)",
                     ErrorKind::Refused};
    }
    return Error{what + "; these statements conflict" +
                     (why->runLimitHit ? " (perhaps not a minimal set)" : "") + ":" +
                     describe(why->conflict),
                 ErrorKind::Refused};
}

Status KnowledgeBase::load(const std::vector<GraphData>& graphs) {
    if (graphs.size() > kMaxGraphsPerLoad) {
        return Error{"at most " + std::to_string(kMaxGraphsPerLoad) + " graphs per load, not " +
                         std::to_string(graphs.size()),
                     ErrorKind::BadInput};
    }
    std::vector<std::string> names;
    std::vector<rdf::Triple> incoming;
    for (std::size_t i = 0; i < graphs.size(); ++i) {
        if (auto ref = sparqlIri(graphs[i].iri); !ref) return ref.failure();
        names.push_back(graphs[i].iri);
        // Each graph's blank nodes apart from the others' (and from the store's labels):
        // merged, a parameter of one graph could become a class list of another.
        auto scoped = rdf::scopeBlankNodes(graphs[i].triples, blankScope(i));
        incoming.insert(incoming.end(), std::make_move_iterator(scoped.begin()),
                        std::make_move_iterator(scoped.end()));
    }
    const std::lock_guard lock(writeMutex_);
    if (reasoner_ == nullptr) {
        auto s = commit(graphs, false, {}, {});
        ++modelsGeneration_;
        return s;
    }
    // Models change rarely and may change what any instance is: the whole KB is checked.
    auto rest = everythingBut(names);
    if (!rest) return Error{"cannot read the knowledge base: " + rest.error(), rest.errorKind()};
    std::vector<rdf::Triple> all = *rest;
    all.insert(all.end(), incoming.begin(), incoming.end());
    auto realization = reasoner_->realize(rdf::writeNTriples(all));
    if (!realization) return Error{"reasoner: " + realization.error()};
    if (!realization->consistent) return refusal(names, *rest, incoming);
    // What the reasoner adds: the types not stated anywhere.
    std::set<std::pair<std::string, std::string>> stated;
    for (const auto& t : all) {
        if (t.predicate.value == kRdfType && t.object.kind == rdf::Term::Kind::Iri) {
            stated.emplace(t.subject.value, t.object.value);
        }
    }
    std::set<rdf::Triple> now;
    for (const auto& a : realization->types) {
        // Anonymous individuals (blank nodes: a pose, a parameter) are named by the
        // reasoner's own scheme, which no query could use.
        if (a.individual.rfind("_:", 0) == 0) continue;
        if (stated.count({a.individual, a.cls}) != 0) continue;
        now.insert({rdf::iri(a.individual), rdf::iri(kRdfType), rdf::iri(a.cls)});
    }
    // The inferred graph changes by what changed: a small load stays a small request.
    if (auto s = knowInferred(); !s) return s;
    std::vector<rdf::Triple> added;
    std::vector<rdf::Triple> removed;
    std::set_difference(now.begin(), now.end(), inferred_.begin(), inferred_.end(),
                        std::back_inserter(added));
    std::set_difference(inferred_.begin(), inferred_.end(), now.begin(), now.end(),
                        std::back_inserter(removed));
    auto s = commit(graphs, false, added, removed);
    ++modelsGeneration_;
    return s;
}

Status KnowledgeBase::knowInferred() {
    if (reasoner_ == nullptr || inferredKnown_) return Done{};
    auto current = graphContent(kInferredGraph);
    if (!current) return current.failure();
    inferred_ = std::set<rdf::Triple>(current->begin(), current->end());
    inferredKnown_ = true;
    return Done{};
}

Status KnowledgeBase::commit(const std::vector<GraphData>& graphs, bool instances,
                             const std::vector<rdf::Triple>& added,
                             const std::vector<rdf::Triple>& removed) {
    // A graph is registered as a model or as an instance graph, as its last writer said.
    const std::string member = "<" + registryMember() + ">";
    const std::string instance = "<" + std::string(kKbVocabulary) + "InstanceGraph>";
    const auto registration = [&](const std::string& iri) {
        const std::string g = "GRAPH <" + std::string(kRegistryGraph) + "> { <" + iri + "> a ";
        return (instances ? "INSERT DATA { " + g + member + " , " + instance + " } } ;\n"
                          : "DELETE DATA { " + g + instance + " } } ;\nINSERT DATA { " + g +
                                member + " } } ;\n");
    };
    std::size_t size = added.size() + removed.size();
    for (const auto& g : graphs) size += g.triples.size();

    std::string u;
    if (size <= kTriplesPerRequest) {
        // One request, which Virtuoso runs as one transaction: a reader sees the old models
        // or the new ones.
        for (std::size_t i = 0; i < graphs.size(); ++i) {
            u += "DROP SILENT GRAPH <" + graphs[i].iri + "> ;\n";
            u += insertText(graphs[i].iri, graphs[i].triples, i);
            u += registration(graphs[i].iri);
        }
        if (!removed.empty()) {
            u += "DELETE DATA { GRAPH <" + std::string(kInferredGraph) + "> {\n" +
                 rdf::writeNTriples(removed) + "} } ;\n";
        }
        if (!added.empty()) u += insertText(kInferredGraph, added, graphs.size());
    } else {
        // Too big for one request (Virtuoso compiles a request to SQL and refuses one that
        // grows beyond 10000 lines): each graph goes to a staging graph first, in pieces,
        // then everything is moved in with one request. Until then the staging graphs are
        // visible to queries over every named graph (not to queries of the registered
        // graphs); a crash while staging leaves only staging graphs, which the next large
        // load clears.
        std::vector<GraphData> staged;
        for (std::size_t i = 0; i < graphs.size(); ++i) {
            staged.push_back(
                {std::string(kStagingGraphPrefix) + std::to_string(i), graphs[i].triples});
        }
        if (reasoner_ != nullptr) {
            if (auto s = knowInferred(); !s) return s;
            std::set<rdf::Triple> whole = inferred_;
            for (const auto& t : removed) whole.erase(t);
            whole.insert(added.begin(), added.end());
            staged.push_back({std::string(kStagingGraphPrefix) + "inferred",
                              std::vector<rdf::Triple>(whole.begin(), whole.end())});
        }
        for (std::size_t i = 0; i < staged.size(); ++i) {
            if (auto s = stage(staged[i], i); !s) {
                return Error{"store: " + s.error(), s.errorKind()};
            }
        }
        for (std::size_t i = 0; i < graphs.size(); ++i) {
            // DROP first: Virtuoso 7.2's MOVE adds to the target without clearing it.
            u += "DROP SILENT GRAPH <" + graphs[i].iri + "> ;\n";
            u += "MOVE SILENT GRAPH <" + staged[i].iri + "> TO GRAPH <" + graphs[i].iri + "> ;\n";
            u += registration(graphs[i].iri);
        }
        if (reasoner_ != nullptr) {
            u += "DROP SILENT GRAPH <" + std::string(kInferredGraph) + "> ;\n";
            u += "MOVE SILENT GRAPH <" + staged.back().iri + "> TO GRAPH <" +
                 std::string(kInferredGraph) + "> ;\n";
        }
    }
    if (auto s = store_.update(u); !s) {
        inferredKnown_ = false;  // the request may or may not have run: read it again
        return Error{"store: " + s.error(), s.errorKind()};
    }
    if (inferredKnown_) {
        for (const auto& t : removed) inferred_.erase(t);
        inferred_.insert(added.begin(), added.end());
    }
    return Done{};
}

Expected<std::shared_ptr<const KnowledgeBase::Models>> KnowledgeBase::models() {
    {
        const std::lock_guard lock(modelsMutex_);
        if (models_ && models_->generation == modelsGeneration_.load()) return models_;
    }
    // Read under the write lock: the models of one generation, not of a load half seen.
    const std::lock_guard write(writeMutex_);
    auto m = std::make_shared<Models>();
    m->generation = modelsGeneration_.load();
    const std::string q = "CONSTRUCT { ?s ?p ?o } WHERE { GRAPH <" + std::string(kRegistryGraph) +
                          "> { ?g a <" + registryMember() + "> FILTER NOT EXISTS { ?g a <" +
                          std::string(kKbVocabulary) + "InstanceGraph> } } GRAPH ?g { ?s ?p ?o } }";
    auto r = store_.query(q, media::kNTriples);
    if (!r) return r.failure();
    auto triples = rdf::readTurtle(r->body);
    if (!triples) return triples.failure();
    m->triples = std::move(*triples);
    m->text = rdf::writeNTriples(m->triples);
    for (const auto& t : m->triples) {
        if (t.subject.kind == rdf::Term::Kind::Iri) m->subjects.insert(t.subject.value);
    }
    const std::lock_guard lock(modelsMutex_);
    models_ = m;
    return std::shared_ptr<const Models>(std::move(m));
}

std::set<rdf::Triple> KnowledgeBase::inferredFor(const GraphData& instance, const Models& models,
                                                 const engine::Realization& realization) {
    std::set<std::string> individuals;
    std::set<std::pair<std::string, std::string>> stated;
    for (const auto& t : instance.triples) {
        if (t.subject.kind != rdf::Term::Kind::Iri) continue;
        if (models.subjects.count(t.subject.value) == 0) individuals.insert(t.subject.value);
        if (t.predicate.value == kRdfType && t.object.kind == rdf::Term::Kind::Iri) {
            stated.emplace(t.subject.value, t.object.value);
        }
    }
    std::set<rdf::Triple> out;
    for (const auto& a : realization.types) {
        if (individuals.count(a.individual) == 0 || stated.count({a.individual, a.cls}) != 0) {
            continue;
        }
        out.insert({rdf::iri(a.individual), rdf::iri(kRdfType), rdf::iri(a.cls)});
    }
    return out;
}

std::vector<Status> KnowledgeBase::record(const std::vector<GraphData>& instances) {
    std::vector<Status> out(instances.size(), Done{});
    if (instances.size() > kMaxGraphsPerLoad) {
        return std::vector<Status>(
            instances.size(),
            Error{"at most " + std::to_string(kMaxGraphsPerLoad) + " graphs per recording, not " +
                      std::to_string(instances.size()),
                  ErrorKind::BadInput});
    }
    std::set<std::string> seen;
    for (std::size_t i = 0; i < instances.size(); ++i) {
        if (auto ref = sparqlIri(instances[i].iri); !ref) {
            out[i] = ref.failure();
        } else if (!seen.insert(instances[i].iri).second) {
            out[i] = Error{"<" + instances[i].iri + "> given twice in one recording",
                           ErrorKind::BadInput};
        }
    }
    // A load of models while this one reasons makes it reason again: a few times at most.
    constexpr int kAttempts = 4;
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
        std::vector<std::size_t> pending;
        for (std::size_t i = 0; i < instances.size(); ++i) {
            if (out[i]) pending.push_back(i);
        }
        if (pending.empty()) return out;
        if (reasoner_ == nullptr) {  // nothing to check or infer: written as they are
            std::vector<GraphData> graphs;
            graphs.reserve(pending.size());
            for (auto i : pending) graphs.push_back(instances[i]);
            const std::lock_guard lock(writeMutex_);
            const auto s = commit(graphs, true, {}, {});
            for (auto i : pending) out[i] = s;
            return out;
        }
        auto models = this->models();
        if (!models) {
            for (auto i : pending) out[i] = Error{"cannot read the models: " + models.error()};
            return out;
        }
        const Models& m = **models;
        // Reasoning, without a lock: all together, since they are independent of each other;
        // when that is inconsistent, each alone, so that the one at fault is named.
        std::vector<std::set<rdf::Triple>> inferred(instances.size());
        const auto realize = [&](const std::vector<std::size_t>& which) {
            std::string text = m.text;
            for (auto i : which) {
                text +=
                    rdf::writeNTriples(rdf::scopeBlankNodes(instances[i].triples, blankScope(i)));
            }
            return reasoner_->realize(text);
        };
        auto together = realize(pending);
        if (!together) {
            for (auto i : pending) out[i] = Error{"reasoner: " + together.error()};
            return out;
        }
        if (together->consistent) {
            for (auto i : pending) inferred[i] = inferredFor(instances[i], m, *together);
        } else {
            for (auto i : pending) {
                auto alone = pending.size() == 1 ? together : realize({i});
                if (!alone) {
                    out[i] = Error{"reasoner: " + alone.error()};
                } else if (!alone->consistent) {
                    out[i] = refusal({instances[i].iri}, m.triples, instances[i].triples);
                } else {
                    inferred[i] = inferredFor(instances[i], m, *alone);
                }
            }
        }
        std::vector<std::size_t> accepted;
        for (auto i : pending) {
            if (out[i]) accepted.push_back(i);
        }
        if (accepted.empty()) return out;

        const std::lock_guard lock(writeMutex_);
        if (m.generation != modelsGeneration_.load()) continue;  // the models changed
        // The types the previous versions of these graphs brought, for their individuals
        // (those the models describe keep theirs).
        std::vector<rdf::Triple> added;
        std::vector<rdf::Triple> removed;
        std::vector<GraphData> graphs;
        std::set<rdf::Triple> now;
        for (auto i : accepted) {
            graphs.push_back(instances[i]);
            now.insert(inferred[i].begin(), inferred[i].end());
        }
        std::string in;
        for (const auto& g : graphs) in += (in.empty() ? "" : ", ") + ("<" + g.iri + ">");
        auto before =
            store_.query("CONSTRUCT { ?s a ?t } WHERE { GRAPH ?g { ?s ?p ?o } FILTER(?g IN (" + in +
                             ")) GRAPH <" + std::string(kInferredGraph) + "> { ?s a ?t } }",
                         media::kNTriples);
        auto previous = before ? rdf::readTurtle(before->body)
                               : Expected<std::vector<rdf::Triple>>(before.failure());
        if (!previous) {
            for (auto i : accepted) {
                out[i] = Error{"cannot read the inferred graph: " + previous.error(),
                               previous.errorKind()};
            }
            return out;
        }
        std::set<rdf::Triple> then;
        for (auto& t : *previous) {
            if (m.subjects.count(t.subject.value) == 0) then.insert(std::move(t));
        }
        std::set_difference(now.begin(), now.end(), then.begin(), then.end(),
                            std::back_inserter(added));
        std::set_difference(then.begin(), then.end(), now.begin(), now.end(),
                            std::back_inserter(removed));
        const auto s = commit(graphs, true, added, removed);
        for (auto i : accepted) out[i] = s;
        return out;
    }
    for (std::size_t i = 0; i < instances.size(); ++i) {
        if (out[i]) {
            out[i] = Error{"the models changed during each of " + std::to_string(kAttempts) +
                           " attempts to record it: try again"};
        }
    }
    return out;
}

std::string KnowledgeBase::insertText(const std::string& graphIri,
                                      const std::vector<rdf::Triple>& triples, std::size_t number) {
    // Blank node labels are per document, and Virtuoso takes a label as one node across a
    // request: they get a number of their own. Triples with blank nodes go in an INSERT with
    // an empty WHERE, since Virtuoso refuses blank nodes in INSERT DATA (a template's blank
    // nodes are new nodes, as loaded).
    std::vector<rdf::Triple> ground;
    std::vector<rdf::Triple> withBlanks;
    for (auto& t : rdf::scopeBlankNodes(triples, blankScope(number))) {
        const bool blank =
            t.subject.kind == rdf::Term::Kind::Blank || t.object.kind == rdf::Term::Kind::Blank;
        (blank ? withBlanks : ground).push_back(std::move(t));
    }
    std::string u;
    if (!ground.empty()) {
        u += "INSERT DATA { GRAPH <" + graphIri + "> {\n" + rdf::writeNTriples(ground) + "} } ;\n";
    }
    if (!withBlanks.empty()) {
        u += "INSERT { GRAPH <" + graphIri + "> {\n" + rdf::writeNTriples(withBlanks) +
             "} } WHERE {} ;\n";
    }
    return u;
}

Status KnowledgeBase::stage(const GraphData& graph, std::size_t number) {
    // One document, whatever its size, where the store takes whole graphs.
    if (store_.replacesGraphs())
        return store_.replaceGraph(graph.iri, rdf::writeNTriples(graph.triples));
    if (auto s = store_.update("DROP SILENT GRAPH <" + graph.iri + ">"); !s) return s;
    // Pieces of at most kTriplesPerRequest; blank-node structures stay whole (a cut would
    // make two nodes of one).
    std::vector<rdf::Triple> ground;
    std::vector<rdf::Triple> withBlanks;
    for (const auto& t : graph.triples) {
        const bool blank =
            t.subject.kind == rdf::Term::Kind::Blank || t.object.kind == rdf::Term::Kind::Blank;
        (blank ? withBlanks : ground).push_back(t);
    }
    for (std::size_t at = 0; at < ground.size(); at += kTriplesPerRequest) {
        const auto end = ground.begin() + static_cast<std::ptrdiff_t>(
                                              std::min(ground.size(), at + kTriplesPerRequest));
        const std::vector<rdf::Triple> piece(ground.begin() + static_cast<std::ptrdiff_t>(at), end);
        if (auto s = store_.update(insertText(graph.iri, piece, number)); !s) return s;
    }
    if (!withBlanks.empty()) {
        if (auto s = store_.update(insertText(graph.iri, withBlanks, number)); !s) return s;
    }
    return Done{};
}

Status KnowledgeBase::loadTurtle(const std::string& graphIri, std::string_view turtle) {
    auto triples = rdf::readTurtle(turtle, graphIri);
    if (!triples) return Error{"<" + graphIri + ">: " + triples.error(), ErrorKind::BadInput};
    return load({GraphData{graphIri, std::move(*triples)}});
}

Expected<std::vector<GraphData>> KnowledgeBase::builtInModels(bool withDemoProcess) {
    std::vector<GraphData> graphs;
    // The reasoner realizes the whole KB on every load: the OPC Foundation's DI, IA and
    // Robotics would triple its work for nothing a process queries (a component's use of
    // them loads them from --models).
    auto ontologies = owl::embeddedModelOntologies(false);
    if (!ontologies) return ontologies.failure();
    for (auto& o : *ontologies) graphs.push_back({o.iri, std::move(o.triples)});
    struct File {
        const char* name;
        const char* graph;
    };
    std::vector<File> files{{"opcua-core.ttl", "http://skillcell.dev/ontology/opcua"},
                            {"process.ttl", "http://skillcell.dev/ontology/process"}};
    if (withDemoProcess) files.push_back({"demo-process.ttl", "http://skillcell.dev/demo"});
    for (const auto& f : files) {
        auto triples = rdf::readTurtle(owl::embeddedOntology(f.name), f.graph);
        if (!triples) return Error{std::string(f.name) + ": " + triples.error()};
        graphs.push_back({f.graph, std::move(*triples)});
    }
    return graphs;
}

Status KnowledgeBase::loadBuiltInModels(bool withDemoProcess) {
    auto graphs = builtInModels(withDemoProcess);
    if (!graphs) return graphs.failure();
    return load(*graphs);
}

Expected<std::vector<std::string>> KnowledgeBase::graphs() {
    auto content = graphContent(kRegistryGraph);
    if (!content) return content.failure();
    std::vector<std::string> out;
    for (const auto& t : *content) {
        if (t.predicate.value == kRdfType && t.object.value == registryMember()) {
            out.push_back(t.subject.value);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

Expected<std::vector<rdf::Triple>> KnowledgeBase::graphContent(const std::string& graphIri) {
    auto ref = sparqlIri(graphIri);
    if (!ref) return ref.failure();
    auto r = store_.query("CONSTRUCT { ?s ?p ?o } WHERE { GRAPH " + *ref + " { ?s ?p ?o } }",
                          media::kNTriples);
    if (!r) return r.failure();
    return rdf::readTurtle(r->body);
}

Expected<SparqlResponse> KnowledgeBase::query(const std::string& sparql,
                                              const std::string& accept) {
    // A store may well run an update sent as a query (Virtuoso does): not through here.
    if (!isQuery(sparql)) {
        return badInput(
            "not a query (SELECT, CONSTRUCT, DESCRIBE or ASK after the prologue): an update "
            "is sent as an update, which needs the role Engineer");
    }
    return store_.query(sparql, accept);
}

Status KnowledgeBase::update(const std::string& sparqlUpdate) {
    const std::lock_guard lock(writeMutex_);
    // An update may touch the inferred graph and any model: the next load reads the one
    // again, the next recording the other.
    inferredKnown_ = false;
    auto s = store_.update(sparqlUpdate);
    ++modelsGeneration_;
    return s;
}

}  // namespace skillcell::kb
