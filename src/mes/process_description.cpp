#include "mes/process_description.hpp"

#include <algorithm>
#include <charconv>
#include <map>
#include <set>
#include <tuple>

#include "kb/knowledge_base.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::mes {
namespace {

using kb::rdf::Term;
using kb::rdf::Triple;

std::string p(const char* local) {
    return std::string(kProcessNs) + local;
}

// The triples by subject, for walking the description.
class Graph {
public:
    explicit Graph(const std::vector<Triple>& triples) {
        for (const auto& t : triples) bySubject_[t.subject].push_back(&t);
    }
    [[nodiscard]] std::vector<const Term*> objects(const Term& subject,
                                                   const std::string& predicate) const {
        std::vector<const Term*> out;
        const auto it = bySubject_.find(subject);
        if (it == bySubject_.end()) return out;
        for (const Triple* t : it->second) {
            if (t->predicate.value == predicate) out.push_back(&t->object);
        }
        return out;
    }
    [[nodiscard]] const Term* object(const Term& subject, const std::string& predicate) const {
        const auto all = objects(subject, predicate);
        return all.empty() ? nullptr : all.front();
    }
    /// Every (predicate, value) of `subject` whose object is a literal.
    [[nodiscard]] std::vector<std::pair<std::string, std::string>> literals(
        const Term& subject) const {
        std::vector<std::pair<std::string, std::string>> out;
        const auto it = bySubject_.find(subject);
        if (it == bySubject_.end()) return out;
        for (const Triple* t : it->second) {
            if (t->object.kind == Term::Kind::Literal) {
                out.emplace_back(t->predicate.value, t->object.value);
            }
        }
        return out;
    }
    [[nodiscard]] std::optional<std::string> literal(const Term& subject,
                                                     const std::string& predicate) const {
        const Term* o = object(subject, predicate);
        if (o == nullptr || o->kind != Term::Kind::Literal) return std::nullopt;
        return o->value;
    }

private:
    std::map<Term, std::vector<const Triple*>> bySubject_;
};

std::string name(const Term& t) {
    return t.kind == Term::Kind::Blank ? "_:" + t.value : "<" + t.value + ">";
}

kb::Expected<devices::Pose6> pose(const Graph& g, const Term& node, const std::string& what) {
    devices::Pose6 out;
    const std::pair<const char*, double*> parts[] = {{"x", &out.x},     {"y", &out.y},
                                                     {"z", &out.z},     {"roll", &out.a},
                                                     {"pitch", &out.b}, {"yaw", &out.c}};
    for (const auto& [local, field] : parts) {
        const auto text = g.literal(node, p(local));
        const auto v = text ? parseNumber(*text) : std::nullopt;
        if (!v)
            return kb::badInput(what + ": the pose " + name(node) + " has no number proc:" + local);
        *field = *v;
    }
    return out;
}

kb::Expected<DerivationSource> source(const Graph& g, const Term& node, const std::string& what) {
    DerivationSource s;
    s.iri = node.value;
    for (const auto& [local, field] :
         {std::pair{"pose", &s.pose}, std::pair{"targetPose", &s.targetPose}}) {
        if (const Term* n = g.object(node, p(local))) {
            auto v = pose(g, *n, what);
            if (!v) return v.failure();
            *field = *v;
        }
    }
    s.objectId = g.literal(node, p("objectId")).value_or("");
    s.applicationUri = g.literal(node, p("applicationUri")).value_or("");
    s.gripType = g.literal(node, p("gripType")).value_or("");
    // The heaviest mass said of it, should the process and the cell both say one.
    for (const auto& [predicate, value] : g.literals(node)) {
        const auto v = parseNumber(value);
        if (predicate == p("mass") && v && *v > 0 && (!s.mass || *v > *s.mass)) s.mass = v;
    }
    // Its size only when all three edges are numbers.
    std::array<double, 3> size{};
    std::size_t edges = 0;
    for (const char* edge : {"sizeX", "sizeY", "sizeZ"}) {
        const auto text = g.literal(node, p(edge));
        const auto v = text ? parseNumber(*text) : std::nullopt;
        if (!v) break;
        size[edges++] = *v;
    }
    if (edges == size.size()) s.size = size;
    for (const Term* held : g.objects(node, p("holds"))) {
        for (const auto& [predicate, value] : g.literals(*held))
            s.held.emplace_back(predicate, value);
    }
    if (!s.pose && !s.targetPose && s.objectId.empty() && s.applicationUri.empty()) {
        return kb::badInput(what + ": " + name(node) +
                            " has no facts to derive a value from (proc:pose, proc:targetPose, "
                            "proc:objectId, proc:applicationUri)");
    }
    return s;
}

// The step's requirements, by the node that names them in the description.
using RequirementNodes = std::map<Term, std::size_t>;

kb::Expected<StepParameter> parameter(const Graph& g, const Term& node, const std::string& step,
                                      const RequirementNodes& requirements,
                                      const std::vector<FactRequirement>& stepRequirements) {
    StepParameter out;
    const auto parameterName = g.literal(node, p("parameterName"));
    if (!parameterName || parameterName->empty()) {
        return kb::badInput(step + ": the parameter " + name(node) + " has no proc:parameterName");
    }
    out.name = *parameterName;
    const std::string what = step + ", parameter " + out.name;
    if (const auto text = g.literal(node, p("textValue"))) {
        out.value = *text;
    } else if (const auto num = g.literal(node, p("numberValue"))) {
        const auto v = parseNumber(*num);
        if (!v) return kb::badInput(what + ": proc:numberValue '" + *num + "' is not a number");
        out.value = *v;
    } else if (const Term* pv = g.object(node, p("poseValue"))) {
        auto v = pose(g, *pv, what);
        if (!v) return v.failure();
        out.value = *v;
    } else if (const Term* from = g.object(node, p("derivedFrom"))) {
        auto v = source(g, *from, what);
        if (!v) return v.failure();
        out.value = *v;
    } else if (const Term* of = g.object(node, p("endpointOf"))) {
        const auto it = requirements.find(*of);
        if (it == requirements.end() || stepRequirements[it->second].skillTypeIri.empty()) {
            return kb::badInput(
                what + ": proc:endpointOf " + name(*of) +
                " is not one of the step's requirements on the cell (proc:requiresFact "
                "with proc:ofSkillType)");
        }
        out.value = RequirementEndpoint{it->second};
    } else {
        return kb::badInput(
            what +
            ": no value (proc:textValue, proc:numberValue, proc:poseValue) and nothing "
            "to derive it from (proc:derivedFrom, proc:endpointOf)");
    }
    return out;
}

kb::Expected<FactRequirement> requirement(const Graph& g, const Term& node,
                                          const std::string& step) {
    FactRequirement out;
    // The property by its IRI: an xsd:anyURI literal (what process.ttl declares), or an IRI.
    if (const Term* property = g.object(node, p("factProperty"));
        property != nullptr && property->kind != Term::Kind::Blank) {
        out.propertyIri = property->value;
    }
    if (const Term* type = g.object(node, p("ofSkillType"))) {
        if (type->kind != Term::Kind::Iri) {
            return kb::badInput(step + ": the requirement " + name(node) +
                                " has a proc:ofSkillType that is not an IRI");
        }
        out.skillTypeIri = type->value;
    }
    const auto value = g.literal(node, p("factValue"));
    if (out.propertyIri.empty()) {
        // A requirement on the cell may name a type alone: any available instance of it (a
        // robot for a pick, whose endpoint the pick then takes).
        if (out.skillTypeIri.empty()) {
            return kb::badInput(step + ": the requirement " + name(node) +
                                " has neither a proc:factProperty nor a proc:ofSkillType");
        }
        if (value) {
            return kb::badInput(step + ": the requirement " + name(node) +
                                " has a proc:factValue but no proc:factProperty");
        }
        return out;
    }
    if (!value) {
        return kb::badInput(step + ": the requirement " + name(node) + " on " +
                            shortName(out.propertyIri) + " has no proc:factValue");
    }
    out.value = *value;
    return out;
}

}  // namespace

std::optional<double> parseNumber(const std::string& text) {
    double v = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (ec != std::errc() || ptr != end) return std::nullopt;
    return v;
}

std::string FactRequirement::describe() const {
    if (propertyIri.empty()) return "an available " + shortName(skillTypeIri);
    const std::string fact = shortName(propertyIri) + " \"" + value + "\"";
    return skillTypeIri.empty() ? fact
                                : "an available " + shortName(skillTypeIri) + " with " + fact;
}

std::string shortName(const std::string& iri) {
    const auto cut = iri.find_last_of("/#");
    return cut == std::string::npos || cut + 1 == iri.size() ? iri : iri.substr(cut + 1);
}

std::string ProcessStep::label() const {
    return "step " + std::to_string(index) + " (" + shortName(skillTypeIri) + ")";
}

kb::Expected<std::string> processQuery(const std::string& processIri) {
    auto iri = kb::sparqlIri(processIri);
    if (!iri) return iri.failure();
    const std::string P = *iri;
    const std::string hasStep = "<" + p("hasStep") + ">";
    const std::string hasParameter = "<" + p("hasParameter") + ">";
    const std::string derivedFrom = "<" + p("derivedFrom") + ">";
    // One response: parameters, poses and requirements are blank nodes, whose labels hold
    // within it only.
    // Plain UNION branches (no property paths: see docs/knowledge_base.md on Virtuoso).
    return "CONSTRUCT { ?a ?b ?c } WHERE {\n"
           "  { " +
           P + " ?b ?c . BIND(" + P +
           " AS ?a) }\n"
           "  UNION { " +
           P + " " + hasStep +
           " ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter +
           " ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s <" + p("requiresFact") +
           "> ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q <" + p("poseValue") +
           "> ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?r . ?r <" + p("pose") +
           "> ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?r . ?r <" + p("targetPose") +
           "> ?a . ?a ?b ?c }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?r . ?r <" + p("holds") +
           "> ?a . ?a ?b ?c }\n"
           // An object's mass and size, from the cell's object of the same id (the scene):
           // given to the process's object, which names it by its id only.
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?a . ?a <" + p("objectId") + "> ?id . ?o <" + p("objectId") +
           "> ?id . ?o ?b ?c . FILTER(?b = <" + p("mass") + "> || ?b = <" + p("sizeX") +
           "> || ?b = <" + p("sizeY") + "> || ?b = <" + p("sizeZ") +
           ">) }\n"
           // And its pose in the cell (where a robot must reach to pick it), with its parts.
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?a . ?a <" + p("objectId") + "> ?id . ?o <" + p("objectId") + "> ?id . ?o <" +
           p("pose") + "> ?c . BIND(<" + p("pose") +
           "> AS ?b) FILTER(?o != ?a) }\n"
           "  UNION { " +
           P + " " + hasStep + " ?s . ?s " + hasParameter + " ?q . ?q " + derivedFrom +
           " ?r . ?r <" + p("objectId") + "> ?id . ?o <" + p("objectId") + "> ?id . ?o <" +
           p("pose") +
           "> ?a . ?a ?b ?c }\n"
           "}";
}

kb::Expected<ProcessDescription> parseProcess(const std::string& processIri,
                                              const std::vector<Triple>& triples) {
    const Graph g(triples);
    const Term process = kb::rdf::iri(processIri);
    const auto steps = g.objects(process, p("hasStep"));
    if (steps.empty()) {
        return kb::badInput("the knowledge base has no process <" + processIri +
                            "> with steps (proc:hasStep)");
    }
    // The order: proc:firstStep, then proc:next; every step exactly once.
    const Term* first = g.object(process, p("firstStep"));
    if (first == nullptr) {
        if (steps.size() != 1)
            return kb::badInput("the process <" + processIri + "> has no proc:firstStep");
        first = steps.front();
    }
    std::set<Term> members;
    for (const Term* s : steps) members.insert(*s);
    ProcessDescription out;
    out.iri = processIri;
    if (const auto wait = g.literal(process, p("skillWaitSeconds"))) {
        const auto v = parseNumber(*wait);
        if (!v || !(*v >= 0) || *v > kMaxSkillWaitSeconds) {
            return kb::badInput("the process <" + processIri + ">: proc:skillWaitSeconds '" +
                                *wait + "' is not a number of seconds from 0 to 3600");
        }
        out.skillWait = std::chrono::milliseconds(static_cast<std::int64_t>(*v * 1000));
    }
    std::map<std::string, int> position;
    for (const Term* s = first; s != nullptr; s = g.object(*s, p("next"))) {
        if (!members.contains(*s)) {
            return kb::badInput("the process <" + processIri + ">: " + name(*s) +
                                " follows in the proc:next chain but is not one of its steps");
        }
        if (position.contains(s->value)) {
            return kb::badInput("the process <" + processIri + ">: the proc:next chain loops at " +
                                name(*s));
        }
        ProcessStep step;
        step.iri = s->value;
        step.index = static_cast<int>(out.steps.size()) + 1;
        position[step.iri] = step.index;
        const Term* type = g.object(*s, p("requiresSkillType"));
        if (type == nullptr || type->kind != Term::Kind::Iri) {
            return kb::badInput("step " + std::to_string(step.index) + " " + name(*s) +
                                " has no proc:requiresSkillType");
        }
        step.skillTypeIri = type->value;
        if (const auto declared = g.literal(*s, p("stepIndex"))) {
            const auto v = parseNumber(*declared);
            if (!v || *v != step.index) {
                return kb::badInput(step.label() + " " + name(*s) + ": proc:stepIndex " +
                                    *declared + " disagrees with its place in the proc:next chain");
            }
        }
        for (const Term* d : g.objects(*s, p("dependsOn"))) step.dependsOn.push_back(d->value);
        if (const auto retries = g.literal(*s, p("retries"))) {
            const auto v = parseNumber(*retries);
            if (!v || *v < 0 || *v > kMaxRetries ||
                *v != static_cast<double>(static_cast<int>(*v))) {
                return kb::badInput(step.label() + " " + name(*s) + ": proc:retries '" + *retries +
                                    "' is not a whole number from 0 to " +
                                    std::to_string(kMaxRetries));
            }
            step.retries = static_cast<int>(*v);
        }
        // Requirements first, in a stable order (the triples come in none): parameters may
        // name them (proc:endpointOf).
        std::vector<std::pair<FactRequirement, Term>> requirements;
        for (const Term* r : g.objects(*s, p("requiresFact"))) {
            auto parsed = requirement(g, *r, step.label());
            if (!parsed) return parsed.failure();
            requirements.emplace_back(std::move(*parsed), *r);
        }
        std::sort(requirements.begin(), requirements.end(), [](const auto& a, const auto& b) {
            return std::tie(a.first.skillTypeIri, a.first.propertyIri, a.first.value) <
                   std::tie(b.first.skillTypeIri, b.first.propertyIri, b.first.value);
        });
        RequirementNodes nodes;
        for (auto& [r, node] : requirements) {
            nodes.emplace(node, step.requirements.size());
            step.requirements.push_back(std::move(r));
        }
        std::set<std::string> names;
        for (const Term* pn : g.objects(*s, p("hasParameter"))) {
            auto parsed = parameter(g, *pn, step.label(), nodes, step.requirements);
            if (!parsed) return parsed.failure();
            if (!names.insert(parsed->name).second) {
                return kb::badInput(step.label() + ": the parameter " + parsed->name +
                                    " is given twice");
            }
            step.parameters.push_back(std::move(*parsed));
        }
        std::sort(step.parameters.begin(), step.parameters.end(),
                  [](const StepParameter& a, const StepParameter& b) { return a.name < b.name; });
        out.steps.push_back(std::move(step));
    }
    if (out.steps.size() != members.size()) {
        return kb::badInput(
            "the process <" + processIri + "> has " + std::to_string(members.size()) +
            " steps, but its proc:next chain reaches " + std::to_string(out.steps.size()));
    }
    for (const auto& step : out.steps) {
        for (const auto& d : step.dependsOn) {
            const auto it = position.find(d);
            if (it == position.end() || it->second >= step.index) {
                return kb::badInput(step.label() + " depends on <" + d +
                                    ">, which is not an earlier step of the process");
            }
        }
    }
    return out;
}

kb::Expected<std::vector<Triple>> constructTriples(kb::SparqlStore& store,
                                                   const std::string& query) {
    auto response = store.query(query, kb::media::kNTriples);
    if (!response) return response.failure();
    auto triples = kb::rdf::readTurtle(response->body);
    if (!triples) {
        return kb::Error{"the knowledge base's answer is not N-Triples: " + triples.error()};
    }
    return triples;
}

kb::Expected<std::vector<std::string>> processIris(kb::SparqlStore& store) {
    const std::string type = std::string(kb::rdf::vocab::kRdf) + "type";
    const std::string process = std::string(kProcessNs) + "Process";
    auto found = constructTriples(store, "CONSTRUCT { ?p <" + type + "> <" + process +
                                             "> } WHERE { ?p <" + type + "> <" + process + "> }");
    if (!found) return found.failure();
    std::vector<std::string> iris;
    iris.reserve(found->size());
    for (const auto& t : *found) iris.push_back(t.subject.value);
    std::sort(iris.begin(), iris.end());
    iris.erase(std::unique(iris.begin(), iris.end()), iris.end());
    return iris;
}

kb::Expected<ProcessDescription> readProcess(kb::SparqlStore& store,
                                             const std::string& processIri) {
    auto query = processQuery(processIri);
    if (!query) return query.failure();
    auto triples = constructTriples(store, *query);
    if (!triples) return triples.failure();
    return parseProcess(processIri, *triples);
}

}  // namespace skillcell::mes
