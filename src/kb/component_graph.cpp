#include "kb/component_graph.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>

#include "kb/owl/node_iri.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb {
namespace {

// An application URI or a name as one IRI segment: RFC 3986 unreserved characters stay,
// every other byte becomes %XX. These IRIs are stored, so the encoding must never change.
std::string percentEncode(std::string_view text) {
    static constexpr std::string_view kHex = "0123456789ABCDEF";
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const bool unreserved = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                (c >= '0' && c <= '9') || c == '-' || c == '.' || c == '_' ||
                                c == '~';
        if (unreserved) {
            out += c;
        } else {
            const auto u = static_cast<unsigned char>(c);
            out += '%';
            out += kHex[u >> 4U];
            out += kHex[u & 0x0fU];
        }
    }
    return out;
}

std::string proc(std::string_view local) {
    return std::string(kProcessVocabulary) + std::string(local);
}
std::string rdfType() {
    return std::string(rdf::vocab::kRdf) + "type";
}
rdf::Term boolean(bool b) {
    return rdf::literal(b ? "true" : "false", std::string(rdf::vocab::kXsd) + "boolean");
}
rdf::Term decimal(double v) {
    return rdf::decimalLiteral(v);
}
std::string lowerCase(std::string text) {
    for (char& ch : text) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return text;
}

}  // namespace

skills::GlobalNodeId gripPointTypeEnumeration() {
    return {"http://skillcell.dev/UA/GripperSkills/", 3001};
}

std::string skillTypeIri(const skills::SkillTypeRef& t) {
    ua::NodeId id;
    std::visit([&](const auto& v) { id = ua::NodeId(0, v); }, t.id.identifier);
    return owl::nodeIri(t.id.namespaceUri, id, ua::NodeClass::ObjectType, t.browseName);
}

std::string componentIri(const std::string& applicationUri) {
    return "urn:skillcell:component:" + percentEncode(applicationUri);
}

std::string componentGraphIri(const std::string& applicationUri) {
    return "urn:skillcell:kb:component:" + percentEncode(applicationUri);
}

GraphData ComponentGraphs::update(const std::string& applicationUri,
                                  const std::vector<skills::SkillInstance>& live,
                                  const SkillParameterValues& values) {
    Component& c = components_[applicationUri];
    std::set<std::string> present;
    for (const auto& s : live) {
        const std::string key = s.nodeId.toString();
        c.skills[key] = s;
        c.endpointUrl = s.endpointUrl;
        present.insert(key);
        const auto v = values.find(s.nodeId);
        if (v != values.end()) {
            c.values[key] = v->second;
        } else {
            c.values.erase(key);  // not read now: what was read before may no longer hold
        }
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
        const rdf::Term skill = rdf::iri(componentIri(applicationUri) + "/" + percentEncode(key));
        add(component, proc("offers"), skill);
        add(skill, rdfType(), rdf::iri(proc("SkillInstance")));
        if (!s.types.empty()) add(skill, rdfType(), rdf::iri(skillTypeIri(s.type())));
        add(skill, proc("skillNodeId"), rdf::literal(key));
        add(skill, proc("skillName"), rdf::literal(s.browsePathString()));
        add(skill, proc("available"), boolean(present.count(key) != 0));
        const auto v = c.values.find(key);
        if (v == c.values.end()) continue;
        for (const ParameterValue& p : v->second) {
            const std::string parameterIri = skill.value + "/parameter/" + percentEncode(p.name);
            const rdf::Term parameter = rdf::iri(parameterIri);
            add(skill, proc("hasParameterValue"), parameter);
            add(parameter, rdfType(), rdf::iri(proc("Parameter")));
            add(parameter, proc("parameterName"), rdf::literal(p.name));
            if (const auto* text = std::get_if<std::string>(&p.value)) {
                add(parameter, proc("textValue"), rdf::literal(*text));
                if (p.dataType == gripPointTypeEnumeration()) {
                    add(skill, proc("gripType"), rdf::literal(lowerCase(*text)));
                }
                // The robot a gripper or a tool changer is on: the MES takes the reach of that
                // robot for it, and one robot for all a step uses.
                if (p.name == "RobotUri" && !text->empty()) {
                    add(skill, proc("onRobot"), rdf::literal(*text));
                }
            } else if (const auto* number = std::get_if<double>(&p.value)) {
                if (!std::isfinite(*number)) continue;
                add(parameter, proc("numberValue"), decimal(*number));
                // What a gripper can hold (GripperSkillType's rating), as facts of the skill
                // that the MES checks an object against.
                if (p.name == "MaxPayload") add(skill, proc("maxPayload"), decimal(*number));
                if (p.name == "MaxGripWidth") add(skill, proc("maxGripWidth"), decimal(*number));
                // How far a manipulator reaches (MoveSkillType), checked against the targets.
                if (p.name == "Reach" && *number > 0) add(skill, proc("reach"), decimal(*number));
            } else {
                const auto& pose = std::get<PoseValue>(p.value);
                const std::pair<const char*, double> parts[] = {
                    {"x", pose.x},       {"y", pose.y},         {"z", pose.z},
                    {"roll", pose.roll}, {"pitch", pose.pitch}, {"yaw", pose.yaw}};
                const bool finite =
                    std::all_of(std::begin(parts), std::end(parts),
                                [](const auto& part) { return std::isfinite(part.second); });
                if (!finite) continue;  // no decimal for it: the parameter without a value
                const rdf::Term node = rdf::iri(parameterIri + "/pose");
                add(parameter, proc("poseValue"), node);
                add(node, rdfType(), rdf::iri(proc("Pose")));
                for (const auto& [local, part] : parts) add(node, proc(local), decimal(part));
                if (p.name == "ReachCentre") {
                    add(skill, proc("reachCentreX"), decimal(pose.x));
                    add(skill, proc("reachCentreY"), decimal(pose.y));
                    add(skill, proc("reachCentreZ"), decimal(pose.z));
                }
            }
        }
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

const std::vector<std::string>& recordedSkillProperties() {
    static const std::vector<std::string> properties = {
        proc("available"), proc("gripType"),     proc("maxGripWidth"), proc("maxPayload"),
        proc("reach"),     proc("reachCentreX"), proc("reachCentreY"), proc("reachCentreZ"),
        proc("onRobot"),   proc("skillName"),    proc("skillNodeId")};
    return properties;
}

}  // namespace skillcell::kb
