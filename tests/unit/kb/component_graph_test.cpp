// ComponentGraphs: a component's skills as RDF, kept (marked unavailable) when they go.
#include <gtest/gtest.h>

#include <algorithm>

#include "kb/component_graph.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb {
namespace {

const std::string kProc = kProcessVocabulary;
const std::string kType = std::string(rdf::vocab::kRdf) + "type";

skills::SkillInstance skill(const std::string& name, const std::string& typeName,
                            std::uint32_t typeId) {
    skills::SkillInstance s;
    s.componentUri = "urn:test:gripper";
    s.endpointUrl = "opc.tcp://127.0.0.1:4842";
    s.nodeId = ua::NodeId(2, ua::String("Skills/" + name));
    s.browsePath = {{"urn:test:gripper", "Skills"}, {"urn:test:gripper", name}};
    s.types = {{{"http://skillcell.dev/UA/GripperSkills/", typeId}, typeName},
               {{"http://skillcell.dev/UA/Skills/", 1002}, "SkillType"}};
    return s;
}

bool has(const GraphData& g, const std::string& s, const std::string& p, const rdf::Term& o) {
    return std::find(g.triples.begin(), g.triples.end(),
                     rdf::Triple{rdf::iri(s), rdf::iri(p), o}) != g.triples.end();
}

rdf::Term boolean(bool b) {
    return rdf::literal(b ? "true" : "false", std::string(rdf::vocab::kXsd) + "boolean");
}

TEST(ComponentGraphs, DescribeAComponentAndItsSkillsTypedAsTheNodeSetOntologyNamesThem) {
    ComponentGraphs graphs;
    const auto g =
        graphs.update("urn:test:gripper", {skill("Grasp", "GraspGripperSkillType", 1002),
                                           skill("Release", "ReleaseGripperSkillType", 1003)});
    EXPECT_EQ(g.iri, componentGraphIri("urn:test:gripper"));
    const std::string c = componentIri("urn:test:gripper");
    EXPECT_EQ(c, "urn:skillcell:component:urn%3Atest%3Agripper");
    EXPECT_TRUE(has(g, c, kType, rdf::iri(kProc + "Component")));
    EXPECT_TRUE(has(g, c, kProc + "available", boolean(true)));
    EXPECT_TRUE(has(g, c, kProc + "discoveryUrl", rdf::literal("opc.tcp://127.0.0.1:4842")));
    const std::string grasp = c + "/ns%3D2%3Bs%3DSkills%2FGrasp";
    EXPECT_TRUE(has(g, c, kProc + "offers", rdf::iri(grasp)));
    EXPECT_TRUE(has(g, grasp, kType,
                    rdf::iri("http://skillcell.dev/UA/GripperSkills/GraspGripperSkillType")));
    EXPECT_TRUE(has(g, grasp, kProc + "available", boolean(true)));
    EXPECT_TRUE(has(g, grasp, kProc + "skillName", rdf::literal("Skills/Grasp")));
    EXPECT_EQ(graphs.typeNamespaces(),
              (std::set<std::string>{"http://skillcell.dev/UA/GripperSkills/",
                                     "http://skillcell.dev/UA/Skills/"}));
    // The graph is valid RDF for a store: it serializes and reads back.
    auto back = rdf::readTurtle(rdf::writeNTriples(g.triples));
    ASSERT_TRUE(back) << back.error();
}

TEST(ComponentGraphs, KeepSkillsThatWentAwayMarkedUnavailable) {
    ComponentGraphs graphs;
    (void)graphs.update("urn:test:gripper", {skill("Grasp", "GraspGripperSkillType", 1002),
                                             skill("Release", "ReleaseGripperSkillType", 1003)});
    const std::string c = componentIri("urn:test:gripper");
    const std::string grasp = c + "/ns%3D2%3Bs%3DSkills%2FGrasp";
    const std::string release = c + "/ns%3D2%3Bs%3DSkills%2FRelease";

    auto g = graphs.update("urn:test:gripper", {skill("Grasp", "GraspGripperSkillType", 1002)});
    EXPECT_TRUE(has(g, grasp, kProc + "available", boolean(true)));
    EXPECT_TRUE(has(g, release, kProc + "available", boolean(false)));
    EXPECT_FALSE(has(g, release, kProc + "available", boolean(true)));
    EXPECT_TRUE(has(g, c, kProc + "available", boolean(true)));

    g = graphs.update("urn:test:gripper", {});  // gone
    EXPECT_TRUE(has(g, grasp, kProc + "available", boolean(false)));
    EXPECT_TRUE(has(g, release, kProc + "available", boolean(false)));
    EXPECT_TRUE(has(g, c, kProc + "available", boolean(false)));
    EXPECT_TRUE(has(g, c, kProc + "offers", rdf::iri(grasp)));  // not forgotten

    g = graphs.update("urn:test:gripper", {skill("Grasp", "GraspGripperSkillType", 1002)});
    EXPECT_TRUE(has(g, grasp, kProc + "available", boolean(true)));  // back
}

}  // namespace
}  // namespace skillcell::kb
