#include "mes/process_check.hpp"

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <regex>
#include <set>

#include "kb/component_graph.hpp"
#include "kb/owl/nodeset_ontology.hpp"
#include "kb/rdf/turtle.hpp"
#include "mes/process_description.hpp"

namespace skillcell::mes {

using kb::rdf::Term;
using kb::rdf::Triple;

namespace {

constexpr std::string_view kUa = "http://opcfoundation.org/UA/";
constexpr std::string_view kOpc = "http://skillcell.dev/ontology/opcua#";
constexpr std::string_view kSkillType = "http://skillcell.dev/UA/Skills/SkillType";
const std::string kRdfType = std::string(kb::rdf::vocab::kRdf) + "type";
const std::string kSubClassOf = std::string(kb::rdf::vocab::kRdfs) + "subClassOf";

std::string procIri(std::string_view local) {
    return std::string(kProcessNs) + std::string(local);
}
std::string uaIri(std::string_view local) {
    return std::string(kUa) + std::string(local);
}
std::string opcIri(std::string_view local) {
    return std::string(kOpc) + std::string(local);
}

/// Subject -> predicate -> objects, in the order the triples came.
class TripleIndex {
public:
    explicit TripleIndex(const std::vector<Triple>& triples) {
        for (const auto& t : triples) {
            index_[key(t.subject)][t.predicate.value].push_back(t.object);
        }
    }
    static std::string key(const Term& t) {
        return (t.kind == Term::Kind::Blank ? "_:" : "") + t.value;
    }
    [[nodiscard]] const std::vector<Term>& objects(const std::string& subject,
                                                   const std::string& predicate) const {
        static const std::vector<Term> none;
        const auto s = index_.find(subject);
        if (s == index_.end()) return none;
        const auto p = s->second.find(predicate);
        return p == s->second.end() ? none : p->second;
    }
    [[nodiscard]] const Term* object(const std::string& subject,
                                     const std::string& predicate) const {
        const auto& o = objects(subject, predicate);
        return o.empty() ? nullptr : &o.front();
    }
    [[nodiscard]] bool has(const std::string& subject, const std::string& predicate) const {
        return !objects(subject, predicate).empty();
    }
    [[nodiscard]] bool isA(const std::string& subject, const std::string& type) const {
        const auto& types = objects(subject, kRdfType);
        return std::any_of(types.begin(), types.end(),
                           [&](const Term& t) { return t.value == type; });
    }
    /// Every subject of type `type`, sorted.
    [[nodiscard]] std::vector<std::string> subjectsOf(const std::string& type) const {
        std::vector<std::string> out;
        for (const auto& [s, predicates] : index_) {
            if (isA(s, type)) out.push_back(s);
        }
        return out;
    }

private:
    std::map<std::string, std::map<std::string, std::vector<Term>>> index_;
};

std::size_t nameDistance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

std::string tailOfIri(const std::string& iri) {
    const auto cut = iri.find_last_of("/#");
    return cut == std::string::npos ? iri : iri.substr(cut + 1);
}

/// A data type for messages: "Double", "3DFrame", or its IRI when it is no ns=0 type. (The
/// models name ns=0's types by their BrowseName; 3DFrame, which starts with a digit, by id.)
std::string dataTypeName(const std::string& iri) {
    if (iri == uaIri("i=18814")) return "3DFrame";
    if (iri.compare(0, kUa.size(), kUa) == 0) return iri.substr(kUa.size());
    return iri;
}

// The data types each kind of value can be written to: the MES's StepBinding converts
// exactly these (step_binding.cpp).
bool isNumberType(const std::string& iri) {
    return iri == uaIri("Int32") || iri == uaIri("UInt32") || iri == uaIri("Float") ||
           iri == uaIri("Double");
}
bool isTextType(const std::string& iri) {
    return iri == uaIri("String");
}
bool isFrameType(const std::string& iri) {
    return iri == uaIri("i=18814");
}

}  // namespace

// --- SkillModels ----------------------------------------------------------------------------

SkillModels SkillModels::fromTriples(const std::vector<Triple>& triples) {
    const TripleIndex g(triples);
    SkillModels m;
    const std::string browseName = opcIri("browseName");
    for (const auto& type : g.subjectsOf(opcIri("ObjectTypeNode"))) {
        TypeModel t;
        t.iri = type;
        if (const Term* n = g.object(type, browseName)) t.name = n->value;
        for (const auto& s : g.objects(type, kSubClassOf)) t.supertypes.push_back(s.value);
        for (const auto& child : g.objects(type, uaIri("HasComponent"))) {
            const Term* name = g.object(TripleIndex::key(child), browseName);
            if (name == nullptr || name->value != "ParameterSet") continue;
            for (const char* reference : {"HasComponent", "HasProperty"}) {
                for (const auto& p : g.objects(TripleIndex::key(child), uaIri(reference))) {
                    const Term* pName = g.object(TripleIndex::key(p), browseName);
                    if (pName == nullptr) continue;
                    const Term* dataType = g.object(TripleIndex::key(p), opcIri("dataType"));
                    t.parameters.push_back({pName->value, dataType ? dataType->value : ""});
                }
            }
        }
        m.types_.emplace(type, std::move(t));
    }
    return m;
}

kb::Expected<SkillModels> SkillModels::embedded() {
    auto ontologies = kb::owl::embeddedModelOntologies();
    if (!ontologies) return ontologies.failure();
    std::vector<Triple> all;
    for (auto& o : *ontologies) {
        all.insert(all.end(), std::make_move_iterator(o.triples.begin()),
                   std::make_move_iterator(o.triples.end()));
    }
    return fromTriples(all);
}

std::string SkillModels::query() {
    // What fromTriples reads, and little else: the types with their names, supertypes and
    // components; their ParameterSets; the parameters' names and data types. Plain UNION
    // branches, no property paths (docs/knowledge_base.md on Virtuoso).
    const std::string type = "<" + opcIri("ObjectTypeNode") + ">";
    const std::string name = "<" + opcIri("browseName") + ">";
    const std::string component = "<" + uaIri("HasComponent") + ">";
    const std::string parameterSet = "?t <" + kRdfType + "> " + type + " . ?t " + component +
                                     " ?ps . ?ps " + name + " \"ParameterSet\" . ";
    return "CONSTRUCT { ?a ?b ?c } WHERE {\n"
           "  { ?a <" +
           kRdfType + "> " + type + " . ?a ?b ?c . FILTER(?b IN (<" + kRdfType + ">, " + name +
           ", <" + kSubClassOf + ">, " + component +
           ")) }\n"
           "  UNION { ?t <" +
           kRdfType + "> " + type + " . ?t " + component + " ?a . ?a " + name +
           " \"ParameterSet\" . ?a ?b ?c . FILTER(?b IN (" + name + ", " + component + ", <" +
           uaIri("HasProperty") +
           ">)) }\n"
           "  UNION { " +
           parameterSet + "?ps ?r ?a . ?a ?b ?c . FILTER(?b IN (" + name + ", <" +
           opcIri("dataType") +
           ">)) }\n"
           "}";
}

kb::Expected<SkillModels> SkillModels::fromStore(kb::SparqlStore& store) {
    auto triples = constructTriples(store, query());
    if (!triples) return triples.failure();
    return fromTriples(*triples);
}

const TypeModel* SkillModels::find(const std::string& iri) const {
    const auto it = types_.find(iri);
    return it == types_.end() ? nullptr : &it->second;
}

bool SkillModels::isSkillType(const std::string& iri) const {
    std::set<std::string> seen;
    std::vector<std::string> todo = {iri};
    while (!todo.empty()) {
        const std::string t = todo.back();
        todo.pop_back();
        if (t == kSkillType) return true;
        if (!seen.insert(t).second) continue;
        if (const TypeModel* m = find(t))
            todo.insert(todo.end(), m->supertypes.begin(), m->supertypes.end());
    }
    return false;
}

std::vector<ParameterModel> SkillModels::parameters(const std::string& iri) const {
    std::vector<ParameterModel> out;
    std::set<std::string> seen;
    // Breadth first from the type: the nearest declaration of a name wins.
    std::vector<std::string> level = {iri};
    std::set<std::string> visited;
    while (!level.empty()) {
        std::vector<std::string> next;
        for (const auto& t : level) {
            if (!visited.insert(t).second) continue;
            const TypeModel* m = find(t);
            if (m == nullptr) continue;
            for (const auto& p : m->parameters) {
                if (seen.insert(p.name).second) out.push_back(p);
            }
            next.insert(next.end(), m->supertypes.begin(), m->supertypes.end());
        }
        level = std::move(next);
    }
    return out;
}

std::string SkillModels::nearestSkillType(const std::string& iri) const {
    const std::string wanted = tailOfIri(iri);
    std::string best;
    std::size_t bestDistance = std::max<std::size_t>(3, wanted.size() / 4) + 1;
    for (const auto& [typeIri, t] : types_) {
        if (!isSkillType(typeIri)) continue;
        const std::size_t d = nameDistance(wanted, t.name);
        if (d < bestDistance) {
            bestDistance = d;
            best = typeIri;
        }
    }
    return best;
}

// --- TurtleLocator --------------------------------------------------------------------------

TurtleLocator::TurtleLocator(std::string_view text) {
    std::size_t start = 0;
    while (start <= text.size()) {
        const auto end = text.find('\n', start);
        lines_.emplace_back(
            text.substr(start, end == std::string_view::npos ? text.npos : end - start));
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    // @prefix name: <iri> .   and SPARQL's PREFIX name: <iri>
    static const std::regex prefix(
        R"(^\s*(?:@prefix|PREFIX|prefix)\s+([A-Za-z0-9_.-]*):\s*<([^>]*)>)");
    for (const auto& line : lines_) {
        std::smatch m;
        if (std::regex_search(line, m, prefix)) prefixes_.emplace_back(m[1].str(), m[2].str());
    }
}

std::vector<std::string> TurtleLocator::spellings(const std::string& iri) const {
    std::vector<std::string> out = {"<" + iri + ">"};
    for (const auto& [name, ns] : prefixes_) {
        if (iri.size() > ns.size() && iri.compare(0, ns.size(), ns) == 0) {
            out.push_back(name + ":" + iri.substr(ns.size()));
        }
    }
    return out;
}

namespace {

bool isNameChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == ':' ||
           c == '.';
}

/// Where `token` stands in `line` as a whole term (not inside a longer name); npos if not.
std::size_t findTerm(const std::string& line, const std::string& token) {
    std::size_t at = line.find(token);
    while (at != std::string::npos) {
        const bool startOk = at == 0 || !isNameChar(line[at - 1]) || token.front() == '<';
        const std::size_t end = at + token.size();
        // A prefixed name may end with '.', the statement's end: "demo:step5 ."
        const bool endOk = end >= line.size() || !isNameChar(line[end]) || line[end] == '.' ||
                           token.front() == '<';
        if (startOk && endOk) return at;
        at = line.find(token, at + 1);
    }
    return std::string::npos;
}

}  // namespace

int TurtleLocator::subjectLine(const std::string& iri) const {
    const auto names = spellings(iri);
    for (std::size_t i = 0; i < lines_.size(); ++i) {
        const auto& line = lines_[i];
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        for (const auto& n : names) {
            if (findTerm(line, n) == first) return static_cast<int>(i + 1);
        }
    }
    return iriLine(iri, 1);
}

int TurtleLocator::iriLine(const std::string& iri, int from) const {
    const auto names = spellings(iri);
    for (std::size_t i = std::max(from, 1) - 1; i < lines_.size(); ++i) {
        if (lines_[i].find_first_not_of(" \t") != std::string::npos &&
            lines_[i][lines_[i].find_first_not_of(" \t")] == '#') {
            continue;
        }
        for (const auto& n : names) {
            if (findTerm(lines_[i], n) != std::string::npos) return static_cast<int>(i + 1);
        }
    }
    return 0;
}

int TurtleLocator::textLine(std::string_view text, int from) const {
    for (std::size_t i = std::max(from, 1) - 1; i < lines_.size(); ++i) {
        if (lines_[i].find(text) != std::string::npos) return static_cast<int>(i + 1);
    }
    return 0;
}

// --- the check ------------------------------------------------------------------------------

const std::vector<std::string>& recordedSkillProperties() {
    return kb::recordedSkillProperties();
}

namespace {

class ProcessChecker {
public:
    ProcessChecker(const TripleIndex& g, const SkillModels& models, const TurtleLocator& where)
        : g_(g), models_(models), where_(where) {}

    void problem(int line, std::string message) { problems_.push_back({line, std::move(message)}); }
    std::vector<ProcessProblem> take() {
        std::stable_sort(problems_.begin(), problems_.end(),
                         [](const auto& a, const auto& b) { return a.line < b.line; });
        return std::move(problems_);
    }

    void process(const std::string& p) {
        const int line = where_.subjectLine(p);
        const std::string name = "process " + tailOfIri(p);
        // The steps: those it lists, and those its chain reaches.
        std::set<std::string> steps;
        for (const auto& s : g_.objects(p, procIri("hasStep"))) steps.insert(TripleIndex::key(s));
        const auto& firsts = g_.objects(p, procIri("firstStep"));
        if (firsts.empty()) {
            problem(line, name + " has no proc:firstStep");
        } else if (firsts.size() > 1) {
            problem(line, name + " has " + std::to_string(firsts.size()) +
                              " proc:firstStep values; it needs one");
        }
        std::vector<std::string> order;  // the chain from firstStep
        if (!firsts.empty()) {
            std::set<std::string> visited;
            std::string at = TripleIndex::key(firsts.front());
            steps.insert(at);
            while (!at.empty()) {
                if (!visited.insert(at).second) {
                    problem(where_.subjectLine(at),
                            name + ": proc:next makes a cycle back to step " + tailOfIri(at));
                    break;
                }
                order.push_back(at);
                const auto& next = g_.objects(at, procIri("next"));
                if (next.size() > 1) {
                    problem(where_.subjectLine(at), "step " + tailOfIri(at) + " has " +
                                                        std::to_string(next.size()) +
                                                        " proc:next values; it needs one");
                }
                at = next.empty() ? std::string() : TripleIndex::key(next.front());
                if (!at.empty() && !steps.count(at) && !g_.isA(at, procIri("Step"))) {
                    problem(where_.iriLine(at, where_.subjectLine(order.back())),
                            "step " + tailOfIri(order.back()) + ": proc:next " + tailOfIri(at) +
                                " is not a step (no proc:Step, not in " + name +
                                "'s proc:hasStep)");
                    break;
                }
                if (!at.empty()) steps.insert(at);
            }
        }
        if (steps.empty()) problem(line, name + " has no steps");
        // How long its steps wait for a skill: seconds, 0 to kMaxSkillWaitSeconds.
        if (const Term* w = g_.object(p, procIri("skillWaitSeconds"))) {
            const auto v = parseNumber(w->value);
            if (w->kind != Term::Kind::Literal || !v || !(*v >= 0) || *v > kMaxSkillWaitSeconds) {
                const int at = where_.textLine("proc:skillWaitSeconds", line);
                problem(at != 0 ? at : line, name + ": proc:skillWaitSeconds \"" + w->value +
                                                 "\" is not a number of seconds from 0 to 3600");
            }
        }
        for (const auto& s : steps) {
            if (std::find(order.begin(), order.end(), s) == order.end() && !firsts.empty()) {
                problem(where_.subjectLine(s), "step " + tailOfIri(s) + " of " + name +
                                                   " is never reached from proc:firstStep "
                                                   "through proc:next");
            }
        }
        for (std::size_t i = 0; i < order.size(); ++i) step(order[i], name, steps, order, i);
        for (const auto& s : steps) {
            if (std::find(order.begin(), order.end(), s) == order.end()) {
                step(s, name, steps, order, order.size());
            }
        }
    }

private:
    void step(const std::string& s, const std::string& processName,
              const std::set<std::string>& steps, const std::vector<std::string>& order,
              std::size_t position) {
        const int line = where_.subjectLine(s);
        const std::string label = "step " + tailOfIri(s);
        std::string typeIri;
        if (const Term* t = g_.object(s, procIri("requiresSkillType"))) typeIri = t->value;
        bool typeKnown = false;
        if (typeIri.empty()) {
            problem(line, label + " has no proc:requiresSkillType");
        } else if (models_.find(typeIri) == nullptr) {
            const std::string near = models_.nearestSkillType(typeIri);
            problem(where_.iriLine(typeIri, line),
                    label + ": unknown skill type <" + typeIri + ">" +
                        (near.empty() ? "; no skill model defines it"
                                      : "; did you mean <" + near + ">?"));
        } else if (!models_.isSkillType(typeIri)) {
            problem(where_.iriLine(typeIri, line),
                    label + ": <" + typeIri + "> is not a skill type (no subtype of SkillType)");
        } else {
            typeKnown = true;
        }
        // Dependencies: steps of this process, earlier in the order.
        for (const auto& d : g_.objects(s, procIri("dependsOn"))) {
            const std::string dep = TripleIndex::key(d);
            const int at = where_.iriLine(dep, line);
            if (!steps.count(dep)) {
                std::string message = label;
                message += ": proc:dependsOn " + tailOfIri(dep) + ", which is not a step of ";
                message += processName;
                problem(at, std::move(message));
                continue;
            }
            const auto it = std::find(order.begin(), order.end(), dep);
            if (it != order.end() && static_cast<std::size_t>(it - order.begin()) >= position) {
                problem(at, label + ": proc:dependsOn " + tailOfIri(dep) +
                                ", which does not come before it");
            }
        }
        // Retries: a whole number from 0 to kMaxRetries.
        if (const Term* r = g_.object(s, procIri("retries"))) {
            const auto v = parseNumber(r->value);
            if (r->kind != Term::Kind::Literal || !v || *v < 0 || *v > kMaxRetries ||
                *v != static_cast<double>(static_cast<int>(*v))) {
                const int at = where_.textLine("proc:retries", line);
                problem(at != 0 ? at : line, label + ": proc:retries \"" + r->value +
                                                 "\" is not a whole number from 0 to " +
                                                 std::to_string(kMaxRetries));
            }
        }
        // Requirements.
        std::set<std::string> cellRequirements;  // those with proc:ofSkillType
        for (const auto& r : g_.objects(s, procIri("requiresFact"))) {
            requirement(TripleIndex::key(r), label, line);
            if (g_.has(TripleIndex::key(r), procIri("ofSkillType")))
                cellRequirements.insert(TripleIndex::key(r));
        }
        // Parameters.
        const auto declared =
            typeKnown ? models_.parameters(typeIri) : std::vector<ParameterModel>{};
        for (const auto& p : g_.objects(s, procIri("hasParameter"))) {
            parameter(TripleIndex::key(p), label, line, typeKnown, typeIri, declared,
                      cellRequirements);
        }
    }

    void requirement(const std::string& r, const std::string& label, int stepLine) {
        const int line = where_.iriLine(r, 1) != 0 ? where_.subjectLine(r) : stepLine;
        const std::string name = label + ", requirement " + tailOfIri(r);
        const Term* property = g_.object(r, procIri("factProperty"));
        const Term* type = g_.object(r, procIri("ofSkillType"));
        if (property == nullptr && type != nullptr) {
            // On the cell by type alone: any available instance of it.
            if (g_.has(r, procIri("factValue"))) {
                problem(line, name + " has a proc:factValue but no proc:factProperty");
            }
        } else if (property == nullptr) {
            problem(line, name + " has neither a proc:factProperty nor a proc:ofSkillType");
        } else {
            const auto& recorded = recordedSkillProperties();
            if (std::find(recorded.begin(), recorded.end(), property->value) == recorded.end()) {
                std::string list;
                for (const auto& p : recorded) list += (list.empty() ? "" : ", ") + tailOfIri(p);
                problem(where_.textLine(property->value, line) != 0
                            ? where_.textLine(property->value, line)
                            : line,
                        name + ": nothing records the property <" + property->value +
                            "> for a skill; the knowledge base records " + list);
            }
        }
        if (property != nullptr && !g_.has(r, procIri("factValue"))) {
            problem(line, name + " has no proc:factValue");
        }
        if (const Term* of = type) {
            if (!models_.isSkillType(of->value)) {
                problem(where_.iriLine(of->value, line),
                        name + ": proc:ofSkillType <" + of->value + "> is no known skill type");
            }
        }
    }

    void parameter(const std::string& p, const std::string& label, int stepLine, bool typeKnown,
                   const std::string& typeIri, const std::vector<ParameterModel>& declared,
                   const std::set<std::string>& cellRequirements) {
        const Term* nameTerm = g_.object(p, procIri("parameterName"));
        if (nameTerm == nullptr) {
            problem(stepLine, label + ": a parameter without proc:parameterName");
            return;
        }
        const std::string& name = nameTerm->value;
        const int line = std::max(where_.textLine("\"" + name + "\"", stepLine), stepLine);
        const std::string what = label + ", parameter " + name;
        const ParameterModel* model = nullptr;
        for (const auto& d : declared) {
            if (d.name == name) model = &d;
        }
        if (typeKnown && model == nullptr) {
            std::string names;
            for (const auto& d : declared) names += (names.empty() ? "" : ", ") + d.name;
            problem(line,
                    what + ": the ParameterSet of " + tailOfIri(typeIri) +
                        " has no such parameter" +
                        (names.empty() ? std::string(" (it has none)") : "; it has " + names));
        }
        const char* kinds[] = {"textValue", "numberValue", "poseValue", "derivedFrom",
                               "endpointOf"};
        std::vector<std::string> given;
        for (const char* k : kinds) {
            if (g_.has(p, procIri(k))) given.emplace_back(k);
        }
        if (given.empty()) {
            problem(line, what +
                              " has no value (proc:textValue, numberValue, poseValue, "
                              "derivedFrom or endpointOf)");
            return;
        }
        if (given.size() > 1) {
            problem(line, what + " has two values: proc:" + given[0] + " and proc:" + given[1]);
            return;
        }
        const std::string dataType = model != nullptr ? model->dataTypeIri : std::string();
        const std::string typeName = dataTypeName(dataType);
        const auto wrongType = [&](const std::string& valueKind) {
            problem(line,
                    what + ": " + valueKind + ", but the parameter's data type is " + typeName);
        };
        const std::string& kind = given.front();
        if (kind == "textValue") {
            if (model != nullptr && !isTextType(dataType)) wrongType("a text (proc:textValue)");
        } else if (kind == "numberValue") {
            const Term* v = g_.object(p, procIri("numberValue"));
            if (!parseNumber(v->value)) {
                problem(line, what + ": proc:numberValue \"" + v->value + "\" is not a number");
            } else if (model != nullptr && !isNumberType(dataType)) {
                wrongType("a number (proc:numberValue)");
            }
        } else if (kind == "poseValue") {
            if (model != nullptr && !isFrameType(dataType)) wrongType("a pose (proc:poseValue)");
            pose(TripleIndex::key(*g_.object(p, procIri("poseValue"))), what, line);
        } else if (kind == "endpointOf") {
            if (model != nullptr && !isTextType(dataType))
                wrongType("an endpoint (proc:endpointOf)");
            const std::string r = TripleIndex::key(*g_.object(p, procIri("endpointOf")));
            if (!cellRequirements.count(r)) {
                problem(line, what + ": proc:endpointOf " + tailOfIri(r) +
                                  ", which is no requirement of this step with proc:ofSkillType");
            }
        } else {
            const std::string from = TripleIndex::key(*g_.object(p, procIri("derivedFrom")));
            derived(from, what, line, model != nullptr ? dataType : std::string());
        }
    }

    void pose(const std::string& node, const std::string& what, int line) {
        // All six, as the MES reads a pose (process_description.cpp).
        for (const char* axis : {"x", "y", "z", "roll", "pitch", "yaw"}) {
            const Term* v = g_.object(node, procIri(axis));
            if (v == nullptr || !parseNumber(v->value)) {
                problem(line, what + ": the pose has no number proc:" + std::string(axis));
            }
        }
    }

    // What the MES derives (step_binding.cpp): a 3DFrame from an object's target pose or a
    // resource's pose; a String from an object's id or a component's application URI.
    void derived(const std::string& from, const std::string& what, int line,
                 const std::string& dataType) {
        const int at = where_.iriLine(from, line) != 0 ? where_.iriLine(from, line) : line;
        const std::string source = tailOfIri(from);
        const bool hasPose = g_.has(from, procIri("pose")) || g_.has(from, procIri("targetPose"));
        const bool hasText =
            g_.has(from, procIri("objectId")) || g_.has(from, procIri("applicationUri"));
        if (!hasPose && !hasText && !g_.has(from, kRdfType)) {
            problem(at, what + ": proc:derivedFrom " + source +
                            ", which nothing describes (a resource of a cell? check with "
                            "--cell FILE or --kb URL)");
            return;
        }
        for (const char* local : {"pose", "targetPose"}) {
            if (const Term* node = g_.object(from, procIri(local))) {
                std::string where = what;
                where += " (" + source + "'s proc:" + local + ")";
                pose(TripleIndex::key(*node), where, at);
            }
        }
        if (dataType.empty()) return;  // the parameter is unknown: reported already
        if (isFrameType(dataType)) {
            if (!hasPose) {
                problem(at, what + ": a 3DFrame, but " + source +
                                " has neither proc:pose nor proc:targetPose");
            }
        } else if (isTextType(dataType)) {
            if (!hasText) {
                problem(at, what + ": a String, but " + source +
                                " has neither proc:objectId nor proc:applicationUri");
            }
        } else {
            problem(at, what + ": nothing derives a value of data type " + dataTypeName(dataType) +
                            " from " + source);
        }
    }

    const TripleIndex& g_;
    const SkillModels& models_;
    const TurtleLocator& where_;
    std::vector<ProcessProblem> problems_;
};

}  // namespace

std::vector<ProcessProblem> checkProcesses(const std::vector<Triple>& triples,
                                           const SkillModels& models, const TurtleLocator& where) {
    const TripleIndex g(triples);
    ProcessChecker c(g, models, where);
    const auto processes = g.subjectsOf(procIri("Process"));
    if (processes.empty()) c.problem(0, "no proc:Process in it");
    for (const auto& p : processes) c.process(p);
    return c.take();
}

std::vector<ProcessProblem> checkProcessText(std::string_view text, const SkillModels& models,
                                             std::vector<Triple>* triples,
                                             const std::vector<Triple>& context) {
    auto read = kb::rdf::readTurtle(text, "file:///process");
    if (!read) {
        // The reader says "line L, column C: ...".
        int line = 0;
        const std::string& e = read.error();
        if (const auto at = e.find("line "); at != std::string::npos) {
            line = std::atoi(e.c_str() + at + 5);
        }
        return {{line, "Turtle syntax: " + e}};
    }
    std::vector<Triple> all = *read;
    all.insert(all.end(), context.begin(), context.end());
    auto problems = checkProcesses(all, models, TurtleLocator(text));
    if (triples != nullptr) *triples = std::move(*read);
    return problems;
}

kb::Expected<ProcessDescription> readCheckedProcess(kb::SparqlStore& store,
                                                    const std::string& processIri) {
    auto query = processQuery(processIri);
    if (!query) return query.failure();
    auto triples = constructTriples(store, *query);
    if (!triples) return triples.failure();
    const bool described = std::any_of(triples->begin(), triples->end(), [&](const Triple& t) {
        return t.subject.value == processIri && t.predicate.value == kRdfType;
    });
    if (described) {
        auto models = SkillModels::fromStore(store);
        if (!models) return models.failure();
        const auto problems = checkProcesses(*triples, *models);
        if (!problems.empty()) {
            std::string text = std::to_string(problems.size()) + " problem" +
                               (problems.size() == 1 ? "" : "s") +
                               " in the process (`skillcell "
                               "process check` shows where): ";
            for (std::size_t i = 0; i < problems.size(); ++i) {
                text += (i == 0 ? "" : "; ") + problems[i].message;
            }
            return kb::badInput(text);
        }
    }
    return parseProcess(processIri, *triples);
}

std::string resourceQuery() {
    const std::string type = "<" + kRdfType + ">";
    const std::string kinds = "FILTER(?k IN (<" + procIri("ToolDock") + ">, <" + procIri("Tool") +
                              ">, <" + procIri("PhysicalObject") + ">))";
    return "CONSTRUCT { ?a ?b ?c } WHERE {\n"
           "  { ?a " +
           type + " ?k . " + kinds +
           " ?a ?b ?c }\n"
           "  UNION { ?r " +
           type + " ?k . " + kinds + " ?r ?p ?a . FILTER(?p IN (<" + procIri("pose") + ">, <" +
           procIri("targetPose") +
           ">)) ?a ?b ?c }\n"
           "}";
}

}  // namespace skillcell::mes
