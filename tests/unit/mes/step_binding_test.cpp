// Which live skills can run a step, and the values they get: any subtype of the step's
// type counts, a skill lacking a parameter does not, and derived values take the form the
// skill's parameter declares.
#include "mes/step_binding.hpp"

#include <gtest/gtest.h>

#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::mes::step_binding_test {
namespace {

constexpr const char* kUa = "http://opcfoundation.org/UA/";
constexpr const char* kTc = "http://skillcell.dev/UA/ToolChangerSkills/";
constexpr const char* kSkills = "http://skillcell.dev/UA/Skills/";

skills::SkillParameter parameter(const char* name, std::uint32_t dataType) {
    skills::SkillParameter p;
    p.browseName = {kTc, name};
    p.dataType = skills::GlobalNodeId(kUa, dataType);
    return p;
}

skills::SkillInstance changer(const char* component, bool withAppUri = true) {
    skills::SkillInstance s;
    s.componentUri = component;
    s.endpointUrl = "opc.tcp://127.0.0.1:4841";
    s.nodeId = ua::NodeId(1, ua::String("Skills/ChangeTool"));
    s.browsePath = {{kTc, "Skills"}, {kTc, "ChangeTool"}};
    s.types = {{skills::GlobalNodeId(kTc, 1003U), "ChangeToolSkillType"},
               {skills::GlobalNodeId(kTc, 1001U), "ToolChangerSkillType"},
               {skills::GlobalNodeId(kSkills, 1002U), "SkillType"}};
    s.parameters = {parameter("ToolPosition", ua::ns0::ThreeDFrame),
                    parameter("MoveSkillControllerEndpoint", ua::ns0::String)};
    if (withAppUri) s.parameters.push_back(parameter("ToolAppUri", ua::ns0::String));
    return s;
}

DerivationSource dock() {
    DerivationSource d;
    d.iri = "http://skillcell.dev/demo#parallelDock";
    d.pose = devices::Pose6{0.3, -0.45, 0.35, 3.14, 0, 0};
    return d;
}

ProcessStep changeStep(std::string typeIri) {
    ProcessStep step;
    step.index = 1;
    step.iri = "http://skillcell.dev/demo#step1";
    step.skillTypeIri = std::move(typeIri);
    step.parameters.push_back({"ToolPosition", dock()});
    return step;
}

TEST(StepBinding, AnInstanceOfTheTypeOrASubtypeFitsIfItHasTheParameters) {
    const auto exact = changeStep(std::string(kTc) + "ChangeToolSkillType");
    const auto super = changeStep(std::string(kTc) + "ToolChangerSkillType");
    const auto other = changeStep(std::string(kTc) + "DetachToolSkillType");
    const auto s = changer("urn:c1");
    EXPECT_EQ(unsuitability(exact, s), "");
    EXPECT_EQ(unsuitability(super, s), "") << "a subtype counts";
    EXPECT_EQ(unsuitability(other, s), "it is not a DetachToolSkillType");
    auto withAppUri = exact;
    withAppUri.parameters.push_back({"ToolAppUri", std::string("urn:tool")});
    EXPECT_EQ(unsuitability(withAppUri, changer("urn:c2", false)),
              "it has no parameter ToolAppUri");

    const std::vector<skills::SkillInstance> live = {changer("urn:c2", false), changer("urn:c1")};
    auto found = candidates(withAppUri, live, {});
    ASSERT_EQ(found.size(), 1U);
    EXPECT_EQ(found[0]->componentUri, "urn:c1");
    found = candidates(exact, live, {});
    ASSERT_EQ(found.size(), 2U);
    EXPECT_EQ(found[0]->componentUri, "urn:c1") << "a stable order";
    found = candidates(exact, live, {triedKeyOf(live[1])});
    ASSERT_EQ(found.size(), 1U);
    EXPECT_EQ(found[0]->componentUri, "urn:c2") << "a tried instance is left out";
}

TEST(StepBinding, DerivedValuesTakeTheFormTheParameterDeclares) {
    auto step = changeStep(std::string(kTc) + "ChangeToolSkillType");
    DerivationSource box;
    box.iri = "http://skillcell.dev/demo#boxA";
    box.objectId = "boxA";
    box.targetPose = devices::Pose6{0.25, 0.35, 0.025, 0, 0, 0};
    step.parameters.push_back({"MoveSkillControllerEndpoint", box});
    auto values = parameterValues(step, changer("urn:c1"));
    ASSERT_TRUE(values) << values.error();
    const auto frame = devices::frameFromVariant(values->at("ToolPosition"));
    ASSERT_TRUE(frame.ok());
    EXPECT_NEAR(frame->p.y(), -0.45, 1e-12);
    const auto* text = values->at("MoveSkillControllerEndpoint").get<ua::String>();
    ASSERT_NE(text, nullptr);
    EXPECT_EQ(std::string(*text), "boxA") << "a String from an object is its id";

    // A 3DFrame from something without a pose, a String from a bare pose: refused, named.
    step.parameters = {
        {"ToolPosition", DerivationSource{"urn:nowhere", {}, {}, "x", {}, {}, {}, {}, {}}}};
    auto bad = parameterValues(step, changer("urn:c1"));
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("step 1 (ChangeToolSkillType), parameter ToolPosition"),
              std::string::npos)
        << bad.error();
    EXPECT_NE(bad.error().find("<urn:nowhere> has no pose"), std::string::npos) << bad.error();
    step.parameters = {{"ToolAppUri", devices::Pose6{}}};
    bad = parameterValues(step, changer("urn:c1"));
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("not a 3DFrame"), std::string::npos) << bad.error();
    step.parameters = {{"ToolAppUri", 3.0}};
    bad = parameterValues(step, changer("urn:c1"));
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("a number"), std::string::npos) << bad.error();
}

TEST(StepBinding, AnEndpointParameterTakesTheEndpointOfTheSkillThatMetItsRequirement) {
    auto step = changeStep(std::string(kTc) + "ChangeToolSkillType");
    step.requirements = {{"urn:gripType", "vacuum", "urn:Grasp"}};
    step.parameters.push_back({"MoveSkillControllerEndpoint", RequirementEndpoint{0}});
    skills::SkillInstance gripper;
    gripper.endpointUrl = "opc.tcp://198.18.0.7:4840";
    auto values = parameterValues(step, changer("urn:c1"), {gripper});
    ASSERT_TRUE(values) << values.error();
    const auto* text = values->at("MoveSkillControllerEndpoint").get<ua::String>();
    ASSERT_NE(text, nullptr);
    EXPECT_EQ(std::string(*text), "opc.tcp://198.18.0.7:4840");

    // No instance met it (or none was given): refused, not an empty endpoint.
    for (const auto& matches : {std::vector<std::optional<skills::SkillInstance>>{},
                                std::vector<std::optional<skills::SkillInstance>>{std::nullopt}}) {
        auto bad = parameterValues(step, changer("urn:c1"), matches);
        ASSERT_FALSE(bad);
        EXPECT_NE(bad.error().find("parameter MoveSkillControllerEndpoint: no skill meets"),
                  std::string::npos)
            << bad.error();
    }
    // An endpoint for a parameter that is not a String.
    step.parameters = {{"ToolPosition", RequirementEndpoint{0}}};
    auto bad = parameterValues(step, changer("urn:c1"), {gripper});
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("not a String"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace skillcell::mes::step_binding_test
