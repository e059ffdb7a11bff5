#include "kb/knowledge_base.hpp"

#include <algorithm>
#include <set>

#include "kb/owl/embedded_ontologies.hpp"
#include "kb/owl/nodeset_ontology.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb {
namespace {

const std::string kRdfType = std::string(rdf::vocab::kRdf) + "type";

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
            return Error{"'" + iri + "' is not an IRI SPARQL can take"};
        }
    }
    if (iri.empty()) return Error{"empty IRI"};
    return "<" + iri + ">";
}

std::string sparqlString(std::string_view text) {
    std::string out = "\"";
    for (char c : text) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\r':
                out += "\\r";
                break;
            default:
                out += c;
        }
    }
    return out + "\"";
}

Expected<std::vector<rdf::Triple>> KnowledgeBase::everythingBut(
    const std::vector<std::string>& graphIris) {
    std::string filter;
    for (const auto& g : graphIris) {
        auto ref = sparqlIri(g);
        if (!ref) return Error{ref.error()};
        filter += (filter.empty() ? "FILTER(?g NOT IN (" : ", ") + *ref;
    }
    if (!filter.empty()) filter += "))";
    const std::string q = "CONSTRUCT { ?s ?p ?o } WHERE { GRAPH <" + std::string(kRegistryGraph) +
                          "> { ?g a <" + registryMember() + "> } GRAPH ?g { ?s ?p ?o } " + filter +
                          " }";
    // N-Triples: Virtuoso's Turtle writes an xsd:double 2 as "2.0", which reads back as an
    // xsd:decimal (and then contradicts a range of xsd:double).
    auto r = store_.query(q, media::kNTriples);
    if (!r) return Error{r.error()};
    return rdf::readTurtle(r->body);
}

Status KnowledgeBase::load(const std::vector<GraphData>& graphs) {
    std::vector<std::string> names;
    std::vector<rdf::Triple> incoming;
    for (const auto& g : graphs) {
        if (auto ref = sparqlIri(g.iri); !ref) return Error{ref.error()};
        names.push_back(g.iri);
        incoming.insert(incoming.end(), g.triples.begin(), g.triples.end());
    }
    const std::lock_guard lock(writeMutex_);
    std::vector<rdf::Triple> inferred;
    if (reasoner_ != nullptr) {
        auto rest = everythingBut(names);
        if (!rest) return Error{"cannot read the knowledge base: " + rest.error()};
        std::vector<rdf::Triple> all = *rest;
        all.insert(all.end(), incoming.begin(), incoming.end());
        const std::string text = rdf::writeNTriples(all);
        auto realization = reasoner_->realize(text);
        if (!realization) return Error{"reasoner: " + realization.error()};
        if (!realization->consistent) {
            std::string what = "refused: loading ";
            for (const auto& n : names) what += "<" + n + "> ";
            what += "would make the knowledge base inconsistent";
            auto why = reasoner_->explainInconsistency(*rest, incoming);
            if (!why) return Error{what + " (no explanation: " + why.error() + ")"};
            if (!why->inconsistent) {
                return Error{what +
                             " (the reasoner found no conflict in the new statements "
                             "alone; the loaded models conflict among themselves)"};
            }
            return Error{what + "; these statements conflict" +
                         (why->runLimitHit ? " (perhaps not a minimal set)" : "") + ":" +
                         describe(why->conflict)};
        }
        // What the reasoner adds: the types not stated anywhere.
        std::set<std::pair<std::string, std::string>> stated;
        for (const auto& t : all) {
            if (t.predicate.value == kRdfType && t.object.kind == rdf::Term::Kind::Iri) {
                stated.emplace(t.subject.value, t.object.value);
            }
        }
        for (const auto& a : realization->types) {
            // Anonymous individuals (blank nodes: a pose, a parameter) are named by the
            // reasoner's own scheme, which no query could use.
            if (a.individual.rfind("_:", 0) == 0) continue;
            if (stated.count({a.individual, a.cls}) != 0) continue;
            inferred.push_back({rdf::iri(a.individual), rdf::iri(kRdfType), rdf::iri(a.cls)});
        }
    }
    // Each graph is written to a staging graph first, in pieces (Virtuoso compiles a request
    // to SQL and refuses one that grows beyond 10000 lines), then everything is moved in with
    // one request, which Virtuoso runs as one transaction: a reader sees the old models or
    // the new ones, and a crash while staging leaves only staging graphs, cleared by the
    // next load.
    std::vector<GraphData> staged;
    for (std::size_t i = 0; i < graphs.size(); ++i) {
        staged.push_back({std::string(kStagingGraphPrefix) + std::to_string(i), graphs[i].triples});
    }
    if (reasoner_ != nullptr) {
        staged.push_back({std::string(kStagingGraphPrefix) + "inferred", std::move(inferred)});
    }
    for (std::size_t i = 0; i < staged.size(); ++i) {
        if (auto s = stage(staged[i], i); !s) return Error{"store: " + s.error()};
    }
    std::string u;
    for (std::size_t i = 0; i < graphs.size(); ++i) {
        u += "MOVE SILENT GRAPH <" + staged[i].iri + "> TO GRAPH <" + graphs[i].iri + "> ;\n";
        u += "INSERT DATA { GRAPH <" + std::string(kRegistryGraph) + "> { <" + graphs[i].iri +
             "> a <" + registryMember() + "> } } ;\n";
    }
    if (reasoner_ != nullptr) {
        u += "MOVE SILENT GRAPH <" + staged.back().iri + "> TO GRAPH <" +
             std::string(kInferredGraph) + "> ;\n";
    }
    if (auto s = store_.update(u); !s) return Error{"store: " + s.error()};
    return Done{};
}

Status KnowledgeBase::stage(const GraphData& graph, std::size_t number) {
    if (auto s = store_.update("DROP SILENT GRAPH <" + graph.iri + ">"); !s) return s;
    // Blank node labels are per document, and Virtuoso takes a label as one node across a
    // request: they get the staging graph's number. Triples with blank nodes go in an INSERT
    // with an empty WHERE, since Virtuoso refuses blank nodes in INSERT DATA (a template's
    // blank nodes are new nodes, as loaded).
    std::vector<rdf::Triple> ground;
    std::vector<rdf::Triple> withBlanks;
    for (auto t : graph.triples) {
        bool blank = false;
        for (auto* term : {&t.subject, &t.object}) {
            if (term->kind == rdf::Term::Kind::Blank) {
                term->value = "g" + std::to_string(number) + "x" + term->value;
                blank = true;
            }
        }
        (blank ? withBlanks : ground).push_back(std::move(t));
    }
    constexpr std::size_t kGroundPerRequest = 1000;
    for (std::size_t at = 0; at < ground.size(); at += kGroundPerRequest) {
        const auto end = ground.begin() + static_cast<std::ptrdiff_t>(
                                              std::min(ground.size(), at + kGroundPerRequest));
        std::vector<rdf::Triple> piece(ground.begin() + static_cast<std::ptrdiff_t>(at), end);
        auto s = store_.update("INSERT DATA { GRAPH <" + graph.iri + "> {\n" +
                               rdf::writeNTriples(std::move(piece)) + "} }");
        if (!s) return s;
    }
    // Blank-node structures must not be cut apart (a cut would make two nodes of one).
    if (!withBlanks.empty()) {
        auto s = store_.update("INSERT { GRAPH <" + graph.iri + "> {\n" +
                               rdf::writeNTriples(std::move(withBlanks)) + "} } WHERE {}");
        if (!s) return s;
    }
    return Done{};
}

Status KnowledgeBase::loadTurtle(const std::string& graphIri, std::string_view turtle) {
    auto triples = rdf::readTurtle(turtle, graphIri);
    if (!triples) return Error{"<" + graphIri + ">: " + triples.error()};
    return load({GraphData{graphIri, std::move(*triples)}});
}

Status KnowledgeBase::loadBuiltInModels(bool withDemoProcess) {
    std::vector<GraphData> graphs;
    auto ontologies = owl::embeddedModelOntologies();
    if (!ontologies) return Error{ontologies.error()};
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
    return load(graphs);
}

Expected<std::vector<std::string>> KnowledgeBase::graphs() {
    auto content = graphContent(kRegistryGraph);
    if (!content) return Error{content.error()};
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
    if (!ref) return Error{ref.error()};
    auto r = store_.query("CONSTRUCT { ?s ?p ?o } WHERE { GRAPH " + *ref + " { ?s ?p ?o } }",
                          media::kNTriples);
    if (!r) return Error{r.error()};
    return rdf::readTurtle(r->body);
}

Expected<SparqlResponse> KnowledgeBase::query(const std::string& sparql,
                                              const std::string& accept) {
    return store_.query(sparql, accept);
}

Status KnowledgeBase::update(const std::string& sparqlUpdate) {
    const std::lock_guard lock(writeMutex_);
    return store_.update(sparqlUpdate);
}

}  // namespace skillcell::kb
