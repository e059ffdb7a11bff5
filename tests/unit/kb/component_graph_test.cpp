// ComponentGraphs: a component's skills as RDF, kept (marked unavailable) when they go, with
// their parameter values; ComponentReader's conversion of values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "kb/component_graph.hpp"
#include "kb/component_reader.hpp"
#include "kb/rdf/turtle.hpp"
#include "ua/encoding/binary_writer.hpp"

namespace skillcell::kb::component_graph_test {
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

TEST(ComponentGraphs, RecordParameterValuesAndTheGripTypeOfAGripperSkill) {
    const std::string xsd(rdf::vocab::kXsd);
    const skills::GlobalNodeId doubleType("http://opcfoundation.org/UA/", 11);
    const skills::GlobalNodeId stringType("http://opcfoundation.org/UA/", 12);
    const skills::GlobalNodeId frameType("http://opcfoundation.org/UA/", 18814);
    ParameterValue offset{"GripPointOffset", frameType, PoseValue{0.1, 0, -0.25, 0, 0, 1.5}};
    ParameterValue gripType{"GripPointType", gripPointTypeEnumeration(), std::string("PARALLEL")};
    ParameterValue force{"Force", doubleType, 12.5};
    ParameterValue tiny{"Tolerance", doubleType, 1e-7};  // a decimal has no exponent
    ParameterValue label{"Label", stringType, std::string("box A")};
    const auto graspSkill = skill("Grasp", "GraspGripperSkillType", 1002);
    const auto releaseSkill = skill("Release", "ReleaseGripperSkillType", 1003);
    SkillParameterValues values;
    values[graspSkill.nodeId] = {offset, gripType, force, tiny, label};
    ComponentGraphs graphs;
    auto g = graphs.update("urn:test:gripper", {graspSkill, releaseSkill}, values);

    const std::string c = componentIri("urn:test:gripper");
    const std::string grasp = c + "/ns%3D2%3Bs%3DSkills%2FGrasp";
    const std::string release = c + "/ns%3D2%3Bs%3DSkills%2FRelease";
    const std::string p = grasp + "/parameter/";
    EXPECT_TRUE(has(g, grasp, kProc + "hasParameterValue", rdf::iri(p + "GripPointOffset")));
    EXPECT_TRUE(has(g, p + "GripPointOffset", kType, rdf::iri(kProc + "Parameter")));
    EXPECT_TRUE(
        has(g, p + "GripPointOffset", kProc + "parameterName", rdf::literal("GripPointOffset")));
    const std::string pose = p + "GripPointOffset/pose";
    EXPECT_TRUE(has(g, p + "GripPointOffset", kProc + "poseValue", rdf::iri(pose)));
    EXPECT_TRUE(has(g, pose, kType, rdf::iri(kProc + "Pose")));
    EXPECT_TRUE(has(g, pose, kProc + "x", rdf::literal("0.1", xsd + "decimal")));
    EXPECT_TRUE(has(g, pose, kProc + "y", rdf::literal("0", xsd + "decimal")));
    EXPECT_TRUE(has(g, pose, kProc + "z", rdf::literal("-0.25", xsd + "decimal")));
    EXPECT_TRUE(has(g, pose, kProc + "yaw", rdf::literal("1.5", xsd + "decimal")));
    EXPECT_TRUE(has(g, p + "GripPointType", kProc + "textValue", rdf::literal("PARALLEL")));
    EXPECT_TRUE(has(g, grasp, kProc + "gripType", rdf::literal("parallel")));
    EXPECT_TRUE(has(g, p + "Force", kProc + "numberValue", rdf::literal("12.5", xsd + "decimal")));
    EXPECT_TRUE(
        has(g, p + "Tolerance", kProc + "numberValue", rdf::literal("0.0000001", xsd + "decimal")));
    EXPECT_TRUE(has(g, p + "Label", kProc + "textValue", rdf::literal("box A")));
    EXPECT_FALSE(has(g, p + "Label", kProc + "numberValue", rdf::literal("box A")));
    // A text of another data type says nothing about the grip; Release was not read.
    EXPECT_FALSE(has(g, grasp, kProc + "gripType", rdf::literal("box a")));
    for (const auto& t : g.triples) {
        EXPECT_NE(t.subject.value.rfind(release + "/parameter/", 0), 0u) << t.subject.value;
    }
    auto back = rdf::readTurtle(rdf::writeNTriples(g.triples));
    ASSERT_TRUE(back) << back.error();

    // Read again, without values for Grasp (the component could not be read): the old
    // values are gone, not kept as if they still held.
    g = graphs.update("urn:test:gripper", {graspSkill, releaseSkill});
    EXPECT_FALSE(has(g, grasp, kProc + "gripType", rdf::literal("parallel")));
    EXPECT_FALSE(has(g, grasp, kProc + "hasParameterValue", rdf::iri(p + "GripPointOffset")));
    // A skill that went away keeps the values it had when last read.
    (void)graphs.update("urn:test:gripper", {graspSkill}, values);
    g = graphs.update("urn:test:gripper", {});
    EXPECT_TRUE(has(g, grasp, kProc + "gripType", rdf::literal("parallel")));
    EXPECT_TRUE(has(g, grasp, kProc + "available", boolean(false)));
}

TEST(ComponentReader, ConvertsValuesAsTheKnowledgeBaseRecordsThem) {
    skills::SkillParameter type;
    type.browseName = {"http://skillcell.dev/UA/GripperSkills/", "GripPointType"};
    type.dataType = gripPointTypeEnumeration();
    const std::vector<std::string> names{"PARALLEL", "VACUUM", "MULTIFINGER"};
    auto v = parameterValue(type, ua::Variant(std::int32_t{1}), &names);
    ASSERT_TRUE(v);
    EXPECT_EQ(v->name, "GripPointType");
    EXPECT_EQ(v->dataType, gripPointTypeEnumeration());
    EXPECT_EQ(std::get<std::string>(v->value), "VACUUM");
    // No name for it: the number.
    v = parameterValue(type, ua::Variant(std::int32_t{7}), &names);
    ASSERT_TRUE(v);
    EXPECT_EQ(std::get<double>(v->value), 7.0);
    // A 3DFrame: six Doubles in its Default Binary encoding (i=18823).
    std::vector<std::uint8_t> body;
    ua::BinaryWriter w(body);
    for (double d : {0.5, -0.1, 0.2, 0.0, 3.0, -1.0}) w.write(d);
    ua::ExtensionObject eo;
    eo.typeId = ua::NodeId(18823);
    eo.encoding = ua::ExtensionObject::Encoding::Binary;
    eo.body = ua::ByteString(std::move(body));
    v = parameterValue(type, ua::Variant(eo), nullptr);
    ASSERT_TRUE(v);
    EXPECT_EQ(std::get<PoseValue>(v->value), (PoseValue{0.5, -0.1, 0.2, 0.0, 3.0, -1.0}));
    EXPECT_EQ(std::get<std::string>(parameterValue(type, ua::Variant("box"))->value), "box");
    EXPECT_EQ(std::get<double>(parameterValue(type, ua::Variant(2.5f))->value), 2.5);
    // Not recorded: booleans, arrays, NaN, an empty value.
    EXPECT_FALSE(parameterValue(type, ua::Variant(true)));
    EXPECT_FALSE(parameterValue(type, ua::Variant::array(std::vector<double>{1.0, 2.0})));
    EXPECT_FALSE(parameterValue(type, ua::Variant(std::nan(""))));
    EXPECT_FALSE(parameterValue(type, ua::Variant()));
}

}  // namespace
}  // namespace skillcell::kb::component_graph_test
