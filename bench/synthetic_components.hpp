#pragma once
// Component graphs as discovery records them (kb/component_graph), made up for the KB's
// benchmarks: n components of four skills each (grasp, release and two moves), all seen
// and, but for the last, gone again (proc:available false); the odd ones grip "vacuum", the
// others and the last "parallel". Only the last one's skills fit a query for an available
// parallel gripper or move.
#include <string>
#include <vector>

#include "kb/component_graph.hpp"
#include "kb/knowledge_base.hpp"

namespace skillcell::bench {

inline const char* const kSyntheticPrefixes =
    "PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#>\n"
    "PREFIX opc: <http://skillcell.dev/ontology/opcua#>\n"
    "PREFIX ua: <http://opcfoundation.org/UA/>\n"
    "PREFIX gskill: <http://skillcell.dev/UA/GripperSkills/>\n"
    "PREFIX rskill: <http://skillcell.dev/UA/RoboticSkills/>\n"
    "PREFIX proc: <http://skillcell.dev/ontology/process#>\n";

/// What the MES asks before a pick: an available gripper skill with grip type "parallel",
/// offered by an available component, with its discovery URL, for a KB without inferred
/// types (a subclass path).
inline const std::string kSyntheticGraspQuery =
    std::string(kSyntheticPrefixes) +
    "SELECT ?skill ?url WHERE {"
    "  ?skill a ?type ; proc:available true ; proc:gripType \"parallel\" ."
    "  ?type rdfs:subClassOf* gskill:GripperSkillType ."
    "  ?component proc:offers ?skill ; proc:available true ;"
    "             proc:discoveryUrl ?url } LIMIT 1";

inline skills::SkillInstance syntheticSkill(const std::string& component, const std::string& name,
                                            const std::string& ns, const std::string& type,
                                            std::uint32_t id) {
    skills::SkillInstance s;
    s.componentUri = component;
    s.endpointUrl = "opc.tcp://198.18.0." + std::to_string(component.size()) + ":4840";
    s.nodeId = ua::NodeId(2, ua::String("Skills/" + name));
    s.browsePath = {{component, "Skills"}, {component, name}};
    s.types = {{skills::GlobalNodeId(std::string_view(ns), id), type}};
    return s;
}

// n components; only the last one's skills are available and fit the queries.
inline std::vector<kb::GraphData> syntheticComponents(std::size_t n) {
    kb::ComponentGraphs graphs;
    std::vector<kb::GraphData> out;
    for (std::size_t i = 0; i < n; ++i) {
        const std::string uri = "urn:bench:component:" + std::to_string(i);
        const bool fits = i + 1 == n;
        std::vector<skills::SkillInstance> skills{
            syntheticSkill(uri, "Grasp", "http://skillcell.dev/UA/GripperSkills/",
                           "GraspGripperSkillType", 1002),
            syntheticSkill(uri, "Release", "http://skillcell.dev/UA/GripperSkills/",
                           "ReleaseGripperSkillType", 1003),
            syntheticSkill(uri, "MoveLinear", "http://skillcell.dev/UA/RoboticSkills/",
                           "CartesianLinearMoveSkillType", 1004),
            syntheticSkill(uri, "MovePtp", "http://skillcell.dev/UA/RoboticSkills/",
                           "CartesianPtpMoveSkillType", 1005)};
        // Seen, then (for all but the last) gone: recorded with proc:available false.
        (void)graphs.update(uri, skills);
        kb::GraphData g = graphs.update(uri, fits ? skills : std::vector<skills::SkillInstance>{});
        const std::string grasp = kb::componentIri(uri) + "/ns%3D2%3Bs%3DSkills%2FGrasp";
        g.triples.push_back({kb::rdf::iri(grasp),
                             kb::rdf::iri(std::string(kb::kProcessVocabulary) + "gripType"),
                             kb::rdf::literal(i % 2 == 0 || fits ? "parallel" : "vacuum")});
        out.push_back(std::move(g));
    }
    return out;
}

}  // namespace skillcell::bench
