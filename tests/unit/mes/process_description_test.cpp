// A process from the knowledge base's triples: the paper's demo process as the KB holds it
// (models/owl/demo-process.ttl), in the proc:next order with every parameter; and broken
// descriptions refused with the step and the fault named.
#include "mes/process_description.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "cell/cell_file.hpp"
#include "cell/scene_graph.hpp"
#include "kb/owl/embedded_ontologies.hpp"
#include "kb/rdf/turtle.hpp"
#include "mes/skill_facts.hpp"

namespace skillcell::mes::process_description_test {
namespace {

constexpr const char* kDemo = "http://skillcell.dev/demo#pickAndPlaceTwoBoxes";
constexpr const char* kPrefixes =
    "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
    "@prefix t: <http://skillcell.dev/UA/ToolChangerSkills/> .\n"
    "@prefix : <http://example.org/p#> .\n";

std::vector<kb::rdf::Triple> triples(std::string_view turtle) {
    auto t = kb::rdf::readTurtle(turtle);
    EXPECT_TRUE(t) << t.error();
    return t ? *t : std::vector<kb::rdf::Triple>{};
}

std::string refusal(const std::string& turtle) {
    auto p = parseProcess("http://example.org/p#p", triples(std::string(kPrefixes) + turtle));
    EXPECT_FALSE(p);
    if (!p) {
        EXPECT_EQ(p.errorKind(), kb::ErrorKind::BadInput);
    }
    return p.error();
}

TEST(ProcessDescription, ReadsThePapersDemoProcessInOrderWithItsParameters) {
    // The process and the paper cell's scene, whose docks it names, as the KB holds them.
    auto all = triples(kb::owl::embeddedOntology("demo-process.ttl"));
    const auto cell =
        cell::readCellFile(std::string(SKILLCELL_SOURCE_DIR) + "/examples/cells/paper.toml");
    ASSERT_TRUE(cell.cell);
    const auto scene = cell::sceneTriples(*cell.cell);
    all.insert(all.end(), scene.begin(), scene.end());
    auto p = parseProcess(kDemo, all);
    ASSERT_TRUE(p) << p.error();
    ASSERT_EQ(p->steps.size(), 5U);
    const char* types[] = {"ChangeToolSkillType", "PickAndPlaceSkillType", "ChangeToolSkillType",
                           "PickAndPlaceSkillType", "DetachToolSkillType"};
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(p->steps[i].index, static_cast<int>(i) + 1);
        EXPECT_EQ(shortName(p->steps[i].skillTypeIri), types[i]);
        EXPECT_EQ(p->steps[i].iri, "http://skillcell.dev/demo#step" + std::to_string(i + 1));
    }
    // Step 1: the parallel gripper's dock gives ToolPosition.
    ASSERT_EQ(p->steps[0].parameters.size(), 1U);
    const auto& position = p->steps[0].parameters[0];
    EXPECT_EQ(position.name, "ToolPosition");
    const auto* dock = std::get_if<DerivationSource>(&position.value);
    ASSERT_NE(dock, nullptr);
    EXPECT_EQ(dock->iri, "http://skillcell.dev/cell/paper#dockP");
    // What the dock holds: the tool change brings a parallel gripper.
    EXPECT_EQ(dock->held, (std::vector<std::pair<std::string, std::string>>{
                              {std::string(kProcessNs) + "gripType", "parallel"}}));
    ASSERT_TRUE(dock->pose);
    EXPECT_DOUBLE_EQ(dock->pose->x, 0.3);
    EXPECT_DOUBLE_EQ(dock->pose->y, -0.45);
    EXPECT_DOUBLE_EQ(dock->pose->a, 3.141592653589793);
    // Step 4: box B gives ObjectId and PlacePosition (its target);
    // the gripper and the robot that meet the step's requirements give their endpoints.
    const auto& pick = p->steps[3].parameters;
    ASSERT_EQ(pick.size(), 4U);
    auto named = [&](const char* name) -> const StepParameter* {
        const auto it = std::find_if(pick.begin(), pick.end(),
                                     [&](const StepParameter& q) { return q.name == name; });
        return it == pick.end() ? nullptr : &*it;
    };
    for (const char* name : {"ObjectId", "PlacePosition", "ToolSkillControllerEndpoint",
                             "MoveSkillControllerEndpoint"}) {
        EXPECT_NE(named(name), nullptr) << name;
    }
    ASSERT_TRUE(named("ObjectId") && named("ToolSkillControllerEndpoint") &&
                named("MoveSkillControllerEndpoint"));
    const auto& reqs = p->steps[3].requirements;
    ASSERT_EQ(reqs.size(), 2U);
    const auto tool = std::get<RequirementEndpoint>(named("ToolSkillControllerEndpoint")->value);
    const auto robot = std::get<RequirementEndpoint>(named("MoveSkillControllerEndpoint")->value);
    EXPECT_EQ(shortName(reqs.at(tool.requirement).skillTypeIri), "GraspGripperSkillType");
    EXPECT_EQ(reqs.at(robot.requirement).describe(), "an available CartesianLinearMoveSkillType");
    const auto* box = std::get_if<DerivationSource>(&named("ObjectId")->value);
    ASSERT_NE(box, nullptr);
    EXPECT_EQ(box->objectId, "boxB");
    ASSERT_TRUE(box->targetPose);
    EXPECT_DOUBLE_EQ(box->targetPose->y, -0.2);
    EXPECT_DOUBLE_EQ(box->targetPose->z, 0.02);
    // (Its pose in the cell comes with the KB's process query: KnowledgeBaseTest.)
    EXPECT_EQ(p->steps[4].dependsOn, std::vector<std::string>{"http://skillcell.dev/demo#step4"});
    // Each pick and place requires a gripper of its grip type and a robot in the cell; nothing
    // else requires anything.
    const std::string gripType = "http://skillcell.dev/ontology/process#gripType";
    const std::string grasp = "http://skillcell.dev/UA/GripperSkills/GraspGripperSkillType";
    const FactRequirement anyRobot{
        "", "", "http://skillcell.dev/UA/RoboticSkills/CartesianLinearMoveSkillType"};
    for (const auto& [step, wanted] : {std::pair{1U, FactRequirement{gripType, "parallel", grasp}},
                                       std::pair{3U, FactRequirement{gripType, "vacuum", grasp}}}) {
        const auto& r = p->steps[step].requirements;
        EXPECT_EQ(r.size(), 2U);
        EXPECT_NE(std::find(r.begin(), r.end(), wanted), r.end()) << step;
        EXPECT_NE(std::find(r.begin(), r.end(), anyRobot), r.end()) << step;
    }
    EXPECT_EQ(FactRequirement({gripType, "vacuum", grasp}).describe(),
              "an available GraspGripperSkillType with gripType \"vacuum\"");
    for (const std::size_t i : {0U, 2U, 4U}) EXPECT_TRUE(p->steps[i].requirements.empty()) << i;
}

TEST(ProcessDescription, TakesRequirementsOnTheSkillOrOnTheCell) {
    auto p = parseProcess(
        "http://example.org/p#p",
        triples(std::string(kPrefixes) +
                ":p proc:hasStep :a ; proc:firstStep :a .\n"
                ":a proc:requiresSkillType t:ChangeToolSkillType ;\n"
                "  proc:requiresFact [ proc:factProperty proc:reach ; proc:factValue 0.85 ] ,\n"
                "  [ proc:factProperty \"http://skillcell.dev/ontology/process#gripType\" ; "
                "proc:factValue \"vacuum\" ; proc:ofSkillType t:Grasp ] .\n"));
    ASSERT_TRUE(p) << p.error();
    const auto& r = p->steps.at(0).requirements;
    ASSERT_EQ(r.size(), 2U);
    EXPECT_EQ(r[0], (FactRequirement{"http://skillcell.dev/ontology/process#reach", "0.85", ""}));
    EXPECT_EQ(r[0].describe(), "reach \"0.85\"");
    EXPECT_EQ(r[1].skillTypeIri, "http://skillcell.dev/UA/ToolChangerSkills/Grasp");
    EXPECT_EQ(r[1].propertyIri, "http://skillcell.dev/ontology/process#gripType");
}

TEST(ProcessDescription, AnObjectBringsItsMassAndSizeFromTheCell) {
    // What the query gives the process's object from the cell's object of the same id.
    auto p = parseProcess("http://example.org/p#p", triples(std::string(kPrefixes) + R"(
        :p a proc:Process ; proc:hasStep :s1 .
        :s1 a proc:Step ; proc:requiresSkillType t:DetachToolSkillType ;
            proc:hasParameter [ proc:parameterName "ObjectId" ; proc:derivedFrom :box ] .
        :box proc:objectId "box" ; proc:mass 0.5 ; proc:mass 2.5 ;
            proc:sizeX 0.04 ; proc:sizeY 0.1 ; proc:sizeZ 0.05 .)"));
    ASSERT_TRUE(p) << p.error();
    const auto& box = std::get<DerivationSource>(p->steps[0].parameters[0].value);
    EXPECT_EQ(box.mass, 2.5) << "the heaviest, when the process and the cell differ";
    EXPECT_EQ(box.size, (std::array{0.04, 0.1, 0.05}));
    EXPECT_EQ(movedObject(p->steps[0]), &box);
    // Without mass or size, nothing to check a gripper against.
    p = parseProcess("http://example.org/p#p", triples(std::string(kPrefixes) + R"(
        :p a proc:Process ; proc:hasStep :s1 .
        :s1 a proc:Step ; proc:requiresSkillType t:DetachToolSkillType ;
            proc:hasParameter [ proc:parameterName "ObjectId" ; proc:derivedFrom :box ] .
        :box proc:objectId "box" ; proc:sizeX 0.04 .)"));
    ASSERT_TRUE(p) << p.error();
    EXPECT_EQ(movedObject(p->steps[0]), nullptr);
}

TEST(ProcessDescription, TakesGivenValues) {
    auto p = parseProcess("http://example.org/p#p",
                          triples(std::string(kPrefixes) +
                                  ":p proc:hasStep :a ; proc:firstStep :a .\n"
                                  ":a proc:requiresSkillType t:AttachToolSkillType ;\n"
                                  "  proc:hasParameter [ proc:parameterName \"ToolAppUri\" ; "
                                  "proc:textValue \"urn:x\" ] ,\n"
                                  "  [ proc:parameterName \"Speed\" ; proc:numberValue 0.25 ] ,\n"
                                  "  [ proc:parameterName \"ToolPosition\" ; proc:poseValue [ "
                                  "proc:x 1 ; proc:y 2 ; proc:z 3 ; proc:roll 0 ; proc:pitch 0 ; "
                                  "proc:yaw 1.5 ] ] .\n"));
    ASSERT_TRUE(p) << p.error();
    const auto& ps = p->steps.at(0).parameters;
    ASSERT_EQ(ps.size(), 3U);
    EXPECT_EQ(std::get<double>(ps[0].value), 0.25);
    EXPECT_EQ(std::get<std::string>(ps[1].value), "urn:x");
    EXPECT_EQ(std::get<devices::Pose6>(ps[2].value), (devices::Pose6{1, 2, 3, 0, 0, 1.5}));
    EXPECT_EQ(p->steps.at(0).retries, 0) << "no retries unless the process says so";
}

TEST(ProcessDescription, TakesAStepsRetriesAndRefusesImpossibleOnes) {
    const std::string process = std::string(kPrefixes) +
                                ":p proc:hasStep :a ; proc:firstStep :a .\n"
                                ":a proc:requiresSkillType t:DetachToolSkillType ; proc:retries ";
    auto p = parseProcess("http://example.org/p#p", triples(process + "2 .\n"));
    ASSERT_TRUE(p) << p.error();
    EXPECT_EQ(p->steps.at(0).retries, 2);
    for (const char* bad : {"-1", "11", "1.5", "\"often\""}) {
        const std::string why = refusal(
            ":p proc:hasStep :a ; proc:firstStep :a .\n"
            ":a proc:requiresSkillType t:X ; proc:retries " +
            std::string(bad) + " .");
        EXPECT_NE(why.find("proc:retries"), std::string::npos) << why;
        EXPECT_NE(why.find("is not a whole number from 0 to 10"), std::string::npos) << why;
    }
}

TEST(ProcessDescription, RefusesBrokenDescriptionsNamingTheFault) {
    EXPECT_NE(refusal(":q proc:hasStep :a .").find("no process"), std::string::npos);
    EXPECT_NE(refusal(":p proc:hasStep :a , :b ; proc:firstStep :a .\n"
                      ":a proc:next :b ; proc:requiresSkillType t:X .\n"
                      ":b proc:next :a ; proc:requiresSkillType t:X .")
                  .find("loops"),
              std::string::npos);
    EXPECT_NE(refusal(":p proc:hasStep :a , :b ; proc:firstStep :a .\n"
                      ":a proc:requiresSkillType t:X . :b proc:requiresSkillType t:X .")
                  .find("reaches 1"),
              std::string::npos);
    EXPECT_NE(refusal(":p proc:hasStep :a ; proc:firstStep :a .").find("requiresSkillType"),
              std::string::npos);
    EXPECT_NE(refusal(":p proc:hasStep :a , :b ; proc:firstStep :a .\n"
                      ":a proc:next :b ; proc:requiresSkillType t:X ; proc:dependsOn :b .\n"
                      ":b proc:requiresSkillType t:X .")
                  .find("not an earlier step"),
              std::string::npos);
    const std::string noValue = refusal(
        ":p proc:hasStep :a ; proc:firstStep :a .\n"
        ":a proc:requiresSkillType t:X ; proc:hasParameter [ proc:parameterName \"P\" ] .");
    EXPECT_NE(noValue.find("step 1 (X), parameter P: no value"), std::string::npos) << noValue;
    const std::string badPose = refusal(
        ":p proc:hasStep :a ; proc:firstStep :a .\n"
        ":a proc:requiresSkillType t:X ; proc:hasParameter [ proc:parameterName \"P\" ; "
        "proc:poseValue [ proc:x 1 ] ] .");
    EXPECT_NE(badPose.find("no number proc:y"), std::string::npos) << badPose;
    EXPECT_NE(refusal(":p proc:hasStep :a ; proc:firstStep :a .\n"
                      ":a proc:requiresSkillType t:X ; proc:stepIndex 2 .")
                  .find("disagrees"),
              std::string::npos);
    const std::string noProperty = refusal(
        ":p proc:hasStep :a ; proc:firstStep :a .\n"
        ":a proc:requiresSkillType t:X ; proc:requiresFact [ proc:factValue 1 ] .");
    EXPECT_NE(noProperty.find("step 1 (X): the requirement _:"), std::string::npos) << noProperty;
    EXPECT_NE(noProperty.find("has neither a proc:factProperty nor a proc:ofSkillType"),
              std::string::npos)
        << noProperty;
    const std::string notACellRequirement = refusal(
        ":p proc:hasStep :a ; proc:firstStep :a .\n"
        ":a proc:requiresSkillType t:X ; proc:requiresFact :r ; proc:hasParameter [ "
        "proc:parameterName \"E\" ; proc:endpointOf :r ] .\n"
        ":r proc:factProperty proc:reach ; proc:factValue 1 .");
    EXPECT_NE(notACellRequirement.find("step 1 (X), parameter E: proc:endpointOf "
                                       "<http://example.org/p#r> is not one of the step's "
                                       "requirements on the cell"),
              std::string::npos)
        << notACellRequirement;
    EXPECT_NE(refusal(":p proc:hasStep :a ; proc:firstStep :a .\n"
                      ":a proc:requiresSkillType t:X ; proc:hasParameter [ "
                      "proc:parameterName \"E\" ; proc:endpointOf :elsewhere ] .")
                  .find("is not one of the step's requirements"),
              std::string::npos);
    const std::string noFactValue = refusal(
        ":p proc:hasStep :a ; proc:firstStep :a .\n"
        ":a proc:requiresSkillType t:X ; proc:requiresFact [ proc:factProperty proc:reach ] .");
    EXPECT_NE(noFactValue.find("on reach has no proc:factValue"), std::string::npos) << noFactValue;
}

TEST(ProcessDescription, AProcessMaySayHowLongItsStepsWaitForASkill) {
    auto p = parseProcess("http://example.org/p#p",
                          triples(std::string(kPrefixes) +
                                  ":p proc:hasStep :a ; proc:firstStep :a ; "
                                  "proc:skillWaitSeconds 1.5 .\n:a proc:requiresSkillType t:X ."));
    ASSERT_TRUE(p) << p.error();
    EXPECT_EQ(p->skillWait, std::chrono::milliseconds(1500));
    auto without = parseProcess(
        "http://example.org/p#p",
        triples(std::string(kPrefixes) +
                ":p proc:hasStep :a ; proc:firstStep :a .\n:a proc:requiresSkillType t:X ."));
    ASSERT_TRUE(without) << without.error();
    EXPECT_FALSE(without->skillWait) << "none: the MES's own";
    EXPECT_NE(refusal(":p proc:hasStep :a ; proc:firstStep :a ; proc:skillWaitSeconds -1 .\n"
                      ":a proc:requiresSkillType t:X .")
                  .find("proc:skillWaitSeconds '-1' is not a number of seconds from 0 to 3600"),
              std::string::npos);
}

TEST(ProcessDescription, TheQueryRefusesAnIriThatWouldBreakIt) {
    EXPECT_FALSE(processQuery("http://example.org/p> } DROP ALL { <x"));
    auto q = processQuery(kDemo);
    ASSERT_TRUE(q) << q.error();
    EXPECT_NE(q->find(std::string("<") + kDemo + ">"), std::string::npos);
}

}  // namespace
}  // namespace skillcell::mes::process_description_test
