#include "kb/component_graph.hpp"

#include "kb/http/http_message.hpp"
#include "kb/owl/node_iri.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb {
namespace {

std::string proc(std::string_view local) {
    return std::string(kProcessVocabulary) + std::string(local);
}
std::string rdfType() {
    return std::string(rdf::vocab::kRdf) + "type";
}
rdf::Term boolean(bool b) {
    return rdf::literal(b ? "true" : "false", std::string(rdf::vocab::kXsd) + "boolean");
}

}  // namespace

std::string skillTypeIri(const skills::SkillTypeRef& t) {
    ua::NodeId id;
    std::visit([&](const auto& v) { id = ua::NodeId(0, v); }, t.id.identifier);
    return owl::nodeIri(t.id.namespaceUri, id, ua::NodeClass::ObjectType, t.browseName);
}

std::string componentIri(const std::string& applicationUri) {
    return "urn:skillcell:component:" + http::percentEncode(applicationUri);
}

std::string componentGraphIri(const std::string& applicationUri) {
    return "urn:skillcell:kb:component:" + http::percentEncode(applicationUri);
}

GraphData ComponentGraphs::update(const std::string& applicationUri,
                                  const std::vector<skills::SkillInstance>& live) {
    Component& c = components_[applicationUri];
    std::set<std::string> present;
    for (const auto& s : live) {
        const std::string key = s.nodeId.toString();
        c.skills[key] = s;
        c.endpointUrl = s.endpointUrl;
        present.insert(key);
    }
    GraphData g{componentGraphIri(applicationUri), {}};
    const rdf::Term component = rdf::iri(componentIri(applicationUri));
    const auto add = [&g](rdf::Term s, std::string p, rdf::Term o) {
        g.triples.push_back({std::move(s), rdf::iri(std::move(p)), std::move(o)});
    };
    add(component, rdfType(), rdf::iri(proc("Component")));
    add(component, proc("applicationUri"), rdf::literal(applicationUri));
    if (!c.endpointUrl.empty()) add(component, proc("discoveryUrl"), rdf::literal(c.endpointUrl));
    add(component, proc("available"), boolean(!present.empty()));
    for (const auto& [key, s] : c.skills) {
        const rdf::Term skill =
            rdf::iri(componentIri(applicationUri) + "/" + http::percentEncode(key));
        add(component, proc("offers"), skill);
        add(skill, rdfType(), rdf::iri(proc("SkillInstance")));
        if (!s.types.empty()) add(skill, rdfType(), rdf::iri(skillTypeIri(s.type())));
        add(skill, proc("skillNodeId"), rdf::literal(key));
        add(skill, proc("skillName"), rdf::literal(s.browsePathString()));
        add(skill, proc("available"), boolean(present.count(key) != 0));
    }
    return g;
}

std::set<std::string> ComponentGraphs::typeNamespaces() const {
    std::set<std::string> out;
    for (const auto& [uri, c] : components_) {
        for (const auto& [key, s] : c.skills) {
            for (const auto& t : s.types) out.insert(t.id.namespaceUri);
        }
    }
    return out;
}

}  // namespace skillcell::kb
