// Facts from the knowledge base and a step's requirements: the facts of factQuery's answer by
// skill instance, a requirement on the skill that runs the step, one on the cell (some live
// skill of a type has the fact), numbers by value, and reasons that say what the live skills
// have instead.
#include "mes/skill_facts.hpp"

#include "mes/feasibility.hpp"

#include <gtest/gtest.h>

#include <array>
#include <optional>

#include "kb/rdf/turtle.hpp"

namespace skillcell::mes::skill_facts_test {
namespace {

constexpr const char* kGs = "http://skillcell.dev/UA/GripperSkills/";
constexpr const char* kCs = "http://skillcell.dev/UA/CompositeSkills/";
const std::string kGripType = std::string(kProcessNs) + "gripType";
const std::string kGrasp = std::string(kGs) + "GraspGripperSkillType";

// A skill Skills/NAME of `component`, of the type `typeName` (i=`typeId` in `ns`), as the
// detector lists it.
skills::SkillInstance skillOf(const char* component, const char* ns, const char* name,
                              std::uint32_t typeId, const char* typeName) {
    skills::SkillInstance s;
    s.componentUri = component;
    s.nodeId = ua::NodeId(1, ua::String(std::string("Skills/") + name));
    s.browsePath = {{ns, "Skills"}, {ns, name}};
    s.types = {{skills::GlobalNodeId(ns, typeId), typeName}};
    return s;
}

skills::SkillInstance grasp(const char* component) {
    skills::SkillInstance s = skillOf(component, kGs, "Grasp", 1002U, "GraspGripperSkillType");
    s.types.push_back({skills::GlobalNodeId(kGs, 1001U), "GripperSkillType"});
    return s;
}

skills::SkillInstance pickAndPlace() {
    return skillOf("urn:pnp", kCs, "PickAndPlace", 1002U, "PickAndPlaceSkillType");
}

ProcessStep pickStep(std::vector<FactRequirement> requirements) {
    ProcessStep step;
    step.index = 2;
    step.skillTypeIri = std::string(kCs) + "PickAndPlaceSkillType";
    step.requirements = std::move(requirements);
    return step;
}

TEST(SkillFacts, ReadsTheFactsOfEachSkillInstanceFromTheQuerysAnswer) {
    const std::string id = grasp("urn:robotiq").nodeId.toString();
    auto triples = kb::rdf::readTurtle(
        "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
        "<urn:c:robotiq> proc:applicationUri \"urn:robotiq\" ; proc:offers <urn:c:robotiq/g> .\n"
        "<urn:c:robotiq/g> proc:skillNodeId \"" +
        id +
        "\" ; proc:gripType \"parallel\" .\n"
        "<urn:c:schmalz> proc:applicationUri \"urn:schmalz\" ; proc:offers <urn:c:schmalz/g> .\n"
        "<urn:c:schmalz/g> proc:skillNodeId \"" +
        id +
        "\" ; proc:gripType \"vacuum\" .\n"
        // A skill whose component the answer does not name has no facts.
        "<urn:c:orphan/g> proc:skillNodeId \"x\" ; proc:gripType \"parallel\" .\n");
    ASSERT_TRUE(triples) << triples.error();
    const SkillFacts facts = parseFacts(*triples);
    EXPECT_EQ(facts.values(keyOf(grasp("urn:robotiq")), kGripType),
              std::vector<std::string>{"parallel"});
    EXPECT_EQ(facts.values(keyOf(grasp("urn:schmalz")), kGripType),
              std::vector<std::string>{"vacuum"});
    EXPECT_TRUE(facts.values({"urn:orphan", "x"}, kGripType).empty());
    EXPECT_TRUE(facts.has(keyOf(grasp("urn:robotiq")), {kGripType, "parallel", ""}));
    EXPECT_FALSE(facts.has(keyOf(grasp("urn:robotiq")), {kGripType, "vacuum", ""}));
}

TEST(SkillFacts, NumbersCompareByValueAndTextAsWritten) {
    SkillFacts facts;
    facts.add({"urn:ur5", "s"}, "urn:reach", "0.850");
    facts.add({"urn:ur5", "s"}, "urn:name", "Parallel");
    EXPECT_TRUE(facts.has({"urn:ur5", "s"}, {"urn:reach", "0.85", ""}));
    EXPECT_FALSE(facts.has({"urn:ur5", "s"}, {"urn:reach", "0.9", ""}));
    EXPECT_FALSE(facts.has({"urn:ur5", "s"}, {"urn:name", "parallel", ""}));
    EXPECT_FALSE(facts.has({"urn:other", "s"}, {"urn:reach", "0.85", ""}));
}

TEST(SkillFacts, ACellRequirementIsMetBySomeLiveSkillOfTheTypeWithTheFact) {
    const auto step = pickStep({{kGripType, "parallel", kGrasp}});
    SkillFacts facts;
    facts.add(keyOf(grasp("urn:schmalz")), kGripType, "vacuum");
    facts.add(keyOf(grasp("urn:robotiq")), kGripType, "parallel");
    facts.add(keyOf(grasp("urn:ag95")), kGripType, "parallel");

    // The mounted gripper is the only live one: a parallel one meets it, whichever model,
    // and is the match (whose endpoint a parameter may take).
    for (const char* model : {"urn:robotiq", "urn:ag95"}) {
        const CellMatch m = matchCellRequirements(step, {pickAndPlace(), grasp(model)}, facts);
        EXPECT_EQ(m.unmet, "") << model;
        ASSERT_EQ(m.byRequirement.size(), 1U);
        ASSERT_TRUE(m.byRequirement[0]) << model;
        EXPECT_EQ(m.byRequirement[0]->componentUri, model);
    }
    // Two fit: the first by component URI, whatever order the detector lists them in.
    EXPECT_EQ(matchCellRequirements(step, {grasp("urn:robotiq"), grasp("urn:ag95")}, facts)
                  .byRequirement[0]
                  ->componentUri,
              "urn:ag95");

    // A vacuum gripper mounted: the reason names the requirement and what is there instead.
    const std::string wrong =
        matchCellRequirements(step, {pickAndPlace(), grasp("urn:schmalz")}, facts).unmet;
    EXPECT_NE(wrong.find("requires an available GraspGripperSkillType with gripType "
                         "\"parallel\""),
              std::string::npos)
        << wrong;
    EXPECT_NE(wrong.find("Skills/Grasp of urn:schmalz has gripType \"vacuum\""), std::string::npos)
        << wrong;

    // Facts of a gripper that is not live do not count (the KB keeps departed components).
    const std::string none = matchCellRequirements(step, {pickAndPlace()}, facts).unmet;
    EXPECT_NE(none.find("none of that type is available"), std::string::npos) << none;

    // A live gripper the KB has not recorded yet.
    const std::string unknown =
        matchCellRequirements(step, {pickAndPlace(), grasp("urn:new")}, facts).unmet;
    EXPECT_NE(unknown.find("urn:new has no gripType in the knowledge base"), std::string::npos)
        << unknown;

    // A requirement on the skill itself is not the cell's.
    const CellMatch own = matchCellRequirements(pickStep({{kGripType, "parallel", ""}}), {}, facts);
    EXPECT_EQ(own.unmet, "");
    ASSERT_EQ(own.byRequirement.size(), 1U);
    EXPECT_FALSE(own.byRequirement[0]);
}

// The process's object "box", which a step's parameters derive from.
DerivationSource boxSource() {
    DerivationSource box;
    box.iri = "http://example.com/demo#box";
    box.objectId = "box";
    return box;
}

// A pick of `object` (its mass and size as the KB gives them) with a parallel gripper.
ProcessStep pickOf(std::optional<double> mass, std::optional<std::array<double, 3>> size) {
    auto step = pickStep({{kGripType, "parallel", kGrasp}});
    DerivationSource box = boxSource();
    box.mass = mass;
    box.size = size;
    step.parameters.push_back({"ObjectId", box});
    return step;
}

TEST(SkillFacts, TheGripperChosenCanHoldTheObjectByItsRating) {
    const std::string payload = std::string(kProcessNs) + "maxPayload";
    const std::string width = std::string(kProcessNs) + "maxGripWidth";
    SkillFacts facts;
    // As the grippers publish them: an AG-95 (3 kg, 95 mm) and a 2F-85 (5 kg, 85 mm).
    facts.add(keyOf(grasp("urn:ag95")), kGripType, "parallel");
    facts.add(keyOf(grasp("urn:ag95")), payload, "3");
    facts.add(keyOf(grasp("urn:ag95")), width, "0.095");
    facts.add(keyOf(grasp("urn:robotiq")), kGripType, "parallel");
    facts.add(keyOf(grasp("urn:robotiq")), payload, "5.0");
    facts.add(keyOf(grasp("urn:robotiq")), width, "0.085");
    const std::vector<skills::SkillInstance> both{grasp("urn:robotiq"), grasp("urn:ag95")};

    // The step asks for the rating only when it moves an object of known mass or size; always
    // whether a skill is recorded, and, as it has requirements, the robots they are on.
    const std::string available = std::string(kProcessNs) + "available";
    const std::string onRobot = std::string(kProcessNs) + "onRobot";
    const std::string reach = std::string(kProcessNs) + "reach";
    EXPECT_EQ(requiredProperties(pickOf(4.0, std::nullopt)),
              (std::vector<std::string>{available, kGripType, width, payload, onRobot, reach}));
    EXPECT_EQ(requiredProperties(pickStep({{kGripType, "parallel", kGrasp}})),
              (std::vector<std::string>{available, kGripType, onRobot, reach}));

    // Light and narrow: both can; the first by URI (the AG-95).
    auto m = matchCellRequirements(pickOf(1.0, std::array{0.04, 0.1, 0.05}), both, facts);
    ASSERT_TRUE(m.byRequirement[0]) << m.unmet;
    EXPECT_EQ(m.byRequirement[0]->componentUri, "urn:ag95");

    // 4 kg: only the 2F-85 carries it, although the AG-95 comes first.
    m = matchCellRequirements(pickOf(4.0, std::nullopt), both, facts);
    ASSERT_TRUE(m.byRequirement[0]) << m.unmet;
    EXPECT_EQ(m.byRequirement[0]->componentUri, "urn:robotiq");

    // 90 mm across its narrower side: only the AG-95's fingers open that wide.
    m = matchCellRequirements(pickOf(1.0, std::array{0.12, 0.09, 0.05}), both, facts);
    ASSERT_TRUE(m.byRequirement[0]) << m.unmet;
    EXPECT_EQ(m.byRequirement[0]->componentUri, "urn:ag95");

    // 6 kg and 90 mm: neither; the reason names each gripper and why it cannot.
    m = matchCellRequirements(pickOf(6.0, std::array{0.12, 0.09, 0.05}), both, facts);
    EXPECT_FALSE(m.byRequirement[0]);
    EXPECT_NE(m.unmet.find("Skills/Grasp of urn:ag95: it holds at most 3 kg, and box weighs 6 kg"),
              std::string::npos)
        << m.unmet;
    EXPECT_NE(m.unmet.find("Skills/Grasp of urn:robotiq: it holds at most 5 kg, and box weighs 6 "
                           "kg; it grips at most 0.085 m across, and box is 0.09 m across"),
              std::string::npos)
        << m.unmet;

    // A gripper without a rating in the KB is not judged by one (recorded before ratings).
    SkillFacts unrated;
    unrated.add(keyOf(grasp("urn:ag95")), kGripType, "parallel");
    m = matchCellRequirements(pickOf(6.0, std::nullopt), {grasp("urn:ag95")}, unrated);
    EXPECT_TRUE(m.byRequirement[0]) << m.unmet;
}

// A robot's linear move, as the detector lists it.
skills::SkillInstance linearMove(const char* component) {
    return skillOf(component, "http://skillcell.dev/UA/RoboticSkills/", "CartesianLinearMove",
                   1010U, "CartesianLinearMoveSkillType");
}

// The reach facts of `robot` as the KB records them from Reach and ReachCentre.
void addReach(SkillFacts& facts, const char* robot, double reach, std::array<double, 3> centre) {
    const std::string p(kProcessNs);
    const auto key = keyOf(linearMove(robot));
    facts.add(key, p + "available", "true");  // recorded
    facts.add(key, p + "reach", std::to_string(reach));
    facts.add(key, p + "reachCentreX", std::to_string(centre[0]));
    facts.add(key, p + "reachCentreY", std::to_string(centre[1]));
    facts.add(key, p + "reachCentreZ", std::to_string(centre[2]));
}

TEST(SkillFacts, ReachPicksTheRobotThatReachesAndSaysWhyTheOthersDoNot) {
    const std::string robotType =
        "http://skillcell.dev/UA/RoboticSkills/CartesianLinearMoveSkillType";
    // A pick that needs a robot (by type alone), whose endpoint it takes: box from where the
    // cell has it to its target.
    auto pick = [&](devices::Pose6 at, devices::Pose6 to) {
        ProcessStep step = pickStep({{"", "", robotType}});
        DerivationSource box = boxSource();
        box.pose = at;
        box.targetPose = to;
        step.parameters.push_back({"ObjectId", box});
        step.parameters.push_back({"PlacePosition", box});
        step.parameters.push_back({"MoveSkillControllerEndpoint", RequirementEndpoint{0}});
        return step;
    };
    SkillFacts facts;
    // Two UR5s (0.85 m from the shoulder), one at the cell's origin, one 1.2 m along x.
    addReach(facts, "urn:a-near", 0.85, {0, 0, 0.089});
    addReach(facts, "urn:b-far", 0.85, {1.2, 0, 0.089});
    const std::vector<skills::SkillInstance> robots{linearMove("urn:a-near"),
                                                    linearMove("urn:b-far")};
    // A type alone needs no fact; positions ask for the reach.
    const auto wanted = requiredProperties(pick({0.4, 0, 0.02}, {0.3, 0.3, 0.02}));
    EXPECT_NE(std::find(wanted.begin(), wanted.end(), std::string(kProcessNs) + "reach"),
              wanted.end());
    EXPECT_EQ(std::find(wanted.begin(), wanted.end(), std::string()), wanted.end());

    // Within the first robot's reach: the first by URI.
    auto m = matchCellRequirements(pick({0.4, 0, 0.02}, {0.3, 0.3, 0.02}), robots, facts);
    ASSERT_TRUE(m.byRequirement[0]) << m.unmet;
    EXPECT_EQ(m.byRequirement[0]->componentUri, "urn:a-near");

    // Beyond it: the other robot, although it comes second; the reason says why.
    m = matchCellRequirements(pick({1.5, 0, 0.02}, {1.2, 0.4, 0.02}), robots, facts);
    ASSERT_TRUE(m.byRequirement[0]) << m.unmet;
    EXPECT_EQ(m.byRequirement[0]->componentUri, "urn:b-far");
    EXPECT_EQ(m.chosen,
              "an available CartesianLinearMoveSkillType: Skills/CartesianLinearMove of urn:b-far "
              "(passed over: Skills/CartesianLinearMove of urn:a-near: box at (1.5, 0, 0.02) is "
              "1.502 m from its reach centre, beyond its reach of 0.85 m; box's target at (1.2, "
              "0.4, 0.02) is 1.267 m from its reach centre, beyond its reach of 0.85 m)");

    // From one's side to the other's: neither; each named, with the distance.
    m = matchCellRequirements(pick({-0.5, 0, 0.02}, {1.9, 0, 0.02}), robots, facts);
    EXPECT_FALSE(m.byRequirement[0]);
    EXPECT_NE(m.unmet.find("the step requires an available CartesianLinearMoveSkillType"),
              std::string::npos)
        << m.unmet;
    EXPECT_NE(m.unmet.find("Skills/CartesianLinearMove of urn:a-near: box's target at (1.9, 0, "
                           "0.02) is 1.901 m from its reach centre, beyond its reach of 0.85 m"),
              std::string::npos)
        << m.unmet;
    EXPECT_NE(m.unmet.find("Skills/CartesianLinearMove of urn:b-far: box at (-0.5, 0, 0.02) is "
                           "1.701 m from its reach centre, beyond its reach of 0.85 m"),
              std::string::npos)
        << m.unmet;

    // A Move step's own robot, by its literal target; a robot the KB has recorded without a
    // reach is not judged by one; one it has not recorded yet cannot be told to reach.
    ProcessStep move;
    move.index = 1;
    move.skillTypeIri = robotType;
    move.parameters.push_back({"TargetPosition", devices::Pose6{1.5, 0, 0.3}});
    move.parameters.push_back({"ToolFrame", devices::Pose6{5, 5, 5}});  // relative: not a target
    EXPECT_EQ(unmetSkillRequirements(move, linearMove("urn:b-far"), facts), "");
    EXPECT_EQ(unmetSkillRequirements(move, linearMove("urn:a-near"), facts),
              "TargetPosition at (1.5, 0, 0.3) is 1.515 m from its reach centre, beyond its "
              "reach of 0.85 m");
    EXPECT_EQ(unmetSkillRequirements(move, linearMove("urn:unrated"), facts),
              "the knowledge base has not recorded it yet, so its reach is not known");
    facts.add(keyOf(linearMove("urn:unrated")), std::string(kProcessNs) + "available", "true");
    EXPECT_EQ(unmetSkillRequirements(move, linearMove("urn:unrated"), facts), "");
}

skills::SkillInstance changeTool(const char* component) {
    return skillOf(component, "http://skillcell.dev/UA/ToolChangerSkills/", "ChangeTool", 1004U,
                   "ChangeToolSkillType");
}

// Two robots 1.5 m apart, each with a tool changer and a gripper on it (the skills' RobotUri,
// proc:onRobot in the KB).
struct TwoRobots {
    SkillFacts facts;
    TwoRobots() {
        const std::string p(kProcessNs);
        addReach(facts, "urn:left", 1.1, {0, 0.75, 0.089});
        addReach(facts, "urn:right", 1.1, {0, -0.75, 0.089});
        for (const auto& [changer, robot] :
             {std::pair{"urn:changer-l", "urn:left"}, std::pair{"urn:changer-r", "urn:right"}}) {
            facts.add(keyOf(changeTool(changer)), p + "available", "true");
            facts.add(keyOf(changeTool(changer)), p + "onRobot", robot);
        }
        for (const auto& [gripper, robot] :
             {std::pair{"urn:gripper-l", "urn:left"}, std::pair{"urn:gripper-r", "urn:right"}}) {
            facts.add(keyOf(grasp(gripper)), p + "available", "true");
            facts.add(keyOf(grasp(gripper)), kGripType, "parallel");
            facts.add(keyOf(grasp(gripper)), p + "onRobot", robot);
        }
    }
};

TEST(SkillFacts, AToolChangerReachesWhereTheRobotItIsOnReaches) {
    TwoRobots cell;
    ProcessStep change;
    change.index = 1;
    change.skillTypeIri = "http://skillcell.dev/UA/ToolChangerSkills/ChangeToolSkillType";
    DerivationSource dock;
    dock.iri = "http://example.com/cell#dockR";
    dock.pose = devices::Pose6{0.45, -0.45, 0.35};
    change.parameters.push_back({"ToolPosition", dock});
    const auto wanted = requiredProperties(change);
    EXPECT_NE(std::find(wanted.begin(), wanted.end(), std::string(kProcessNs) + "onRobot"),
              wanted.end());
    EXPECT_EQ(robotOf(changeTool("urn:changer-r"), cell.facts), "urn:right");
    EXPECT_EQ(robotOf(linearMove("urn:left"), cell.facts), "urn:left");
    EXPECT_EQ(unmetSkillRequirements(change, changeTool("urn:changer-r"), cell.facts), "");
    EXPECT_EQ(unmetSkillRequirements(change, changeTool("urn:changer-l"), cell.facts),
              "dockR at (0.45, -0.45, 0.35) is 1.308 m from its robot urn:left's reach centre, "
              "beyond its reach of 1.1 m");
    // A changer on a robot the KB has not recorded yet: not known to reach.
    cell.facts.add(keyOf(changeTool("urn:changer-x")), std::string(kProcessNs) + "available",
                   "true");
    cell.facts.add(keyOf(changeTool("urn:changer-x")), std::string(kProcessNs) + "onRobot",
                   "urn:third");
    EXPECT_EQ(unmetSkillRequirements(change, changeTool("urn:changer-x"), cell.facts),
              "the knowledge base has not recorded its robot urn:third yet, so its reach is not "
              "known");
}

TEST(SkillFacts, APicksGripperIsTheOneOnTheRobotThatReachesTheBox) {
    TwoRobots cell;
    const std::string robotType =
        "http://skillcell.dev/UA/RoboticSkills/CartesianLinearMoveSkillType";
    auto pick = [&](devices::Pose6 at, devices::Pose6 to) {
        ProcessStep step = pickStep({{kGripType, "parallel", kGrasp}, {"", "", robotType}});
        DerivationSource box = boxSource();
        box.pose = at;
        box.targetPose = to;
        step.parameters.push_back({"ObjectId", box});
        return step;
    };
    // On the right: the gripper on the left comes first by URI, but it is carried by a robot
    // that does not reach the box, so the one on the right is taken, with the right robot.
    const ProcessStep right = pick({0.45, -0.8, 0.02}, {0.25, -0.8, 0.02});
    const std::vector<skills::SkillInstance> live{grasp("urn:gripper-l"), grasp("urn:gripper-r"),
                                                  linearMove("urn:left"), linearMove("urn:right")};
    auto m = matchCellRequirements(right, live, cell.facts);
    ASSERT_TRUE(m.byRequirement[0] && m.byRequirement[1]) << m.unmet;
    EXPECT_EQ(m.byRequirement[0]->componentUri, "urn:gripper-r");
    EXPECT_EQ(m.byRequirement[1]->componentUri, "urn:right");
    EXPECT_EQ(m.robot, "urn:right");
    EXPECT_NE(m.chosen.find("Skills/Grasp of urn:gripper-r (passed over: Skills/Grasp of "
                            "urn:gripper-l: box at (0.45, -0.8, 0.02) is 1.615 m from its robot "
                            "urn:left's reach centre"),
              std::string::npos)
        << m.chosen;

    // Between them both reach: the first gripper by URI, and the robot that carries it, not
    // the first robot by URI.
    const ProcessStep middle = pick({0.45, 0, 0.02}, {0.5, 0, 0.02});
    const std::vector<skills::SkillInstance> rightFirst{
        grasp("urn:gripper-r"), linearMove("urn:left"), linearMove("urn:right")};
    m = matchCellRequirements(middle, rightFirst, cell.facts);
    ASSERT_TRUE(m.byRequirement[0] && m.byRequirement[1]) << m.unmet;
    EXPECT_EQ(m.byRequirement[1]->componentUri, "urn:right");
    EXPECT_NE(m.chosen.find("Skills/CartesianLinearMove of urn:right (passed over: "
                            "Skills/CartesianLinearMove of urn:left: it is on robot urn:left, the "
                            "step's other skills on urn:right)"),
              std::string::npos)
        << m.chosen;
    // A skill of the step on the other robot is refused, both robots named.
    EXPECT_EQ(unmetSkillRequirements(middle, changeTool("urn:changer-l"), cell.facts, m.robot),
              "it is on robot urn:left, and the step's other skills on urn:right");

    // The left gripper, and only the right robot live: no robot has all the step needs, said
    // with each requirement's candidates and their robots.
    const std::vector<skills::SkillInstance> apart{grasp("urn:gripper-l"), linearMove("urn:right")};
    m = matchCellRequirements(middle, apart, cell.facts);
    EXPECT_FALSE(m.byRequirement[0]);
    EXPECT_EQ(m.unmet,
              "no robot has all the step requires: an available GraspGripperSkillType with "
              "gripType \"parallel\": Skills/Grasp of urn:gripper-l on urn:left; an available "
              "CartesianLinearMoveSkillType: Skills/CartesianLinearMove of urn:right on "
              "urn:right");
}

TEST(SkillFacts, ASkillRequirementConcernsTheSkillThatRunsTheStep) {
    ProcessStep step = pickStep({{kGripType, "vacuum", ""}});
    step.skillTypeIri = kGrasp;
    SkillFacts facts;
    facts.add(keyOf(grasp("urn:schmalz")), kGripType, "vacuum");
    facts.add(keyOf(grasp("urn:robotiq")), kGripType, "parallel");
    EXPECT_EQ(unmetSkillRequirements(step, grasp("urn:schmalz"), facts), "");
    EXPECT_EQ(unmetSkillRequirements(step, grasp("urn:robotiq"), facts),
              "the knowledge base does not give it gripType \"vacuum\" (it has \"parallel\")");
    EXPECT_EQ(unmetSkillRequirements(step, grasp("urn:new"), facts),
              "the knowledge base does not give it gripType \"vacuum\"");
    // Cell requirements are not the skill's.
    EXPECT_EQ(
        unmetSkillRequirements(pickStep({{kGripType, "x", kGrasp}}), grasp("urn:robotiq"), facts),
        "");
}

TEST(SkillFacts, TheQueryAsksForEachPropertyAndRefusesABrokenIri) {
    EXPECT_EQ(requiredProperties(pickStep(
                  {{kGripType, "a", kGrasp}, {"urn:reach", "1", ""}, {kGripType, "b", ""}})),
              (std::vector<std::string>{std::string(kProcessNs) + "available", kGripType,
                                        std::string(kProcessNs) + "onRobot",
                                        std::string(kProcessNs) + "reach", "urn:reach"}));
    auto q = factQuery({kGripType, "urn:reach"});
    ASSERT_TRUE(q) << q.error();
    EXPECT_NE(q->find("<" + kGripType + ">"), std::string::npos) << *q;
    EXPECT_NE(q->find("UNION"), std::string::npos) << *q;
    EXPECT_FALSE(factQuery({"urn:x> } DROP ALL { <y"}));
    EXPECT_FALSE(factQuery({}));
}

TEST(Feasibility, AStepNeedsASkillOfItsTypeAndItsCellRequirementsMetOrBroughtEarlier) {
    SkillFacts facts;
    facts.add(keyOf(grasp("urn:robotiq")), kGripType, "parallel");
    // Step 2 picks with a vacuum gripper.
    ProcessDescription process;
    process.iri = "urn:p";
    process.steps = {pickStep({{kGripType, "vacuum", kGrasp}})};

    // No pick-and-place skill, no vacuum gripper: both said, naming the step.
    auto lacking = infeasibility(process, {grasp("urn:robotiq")}, &facts);
    ASSERT_EQ(lacking.size(), 2U);
    EXPECT_EQ(lacking[0],
              "step 2 (PickAndPlaceSkillType): no component in the cell offers a "
              "PickAndPlaceSkillType");
    EXPECT_NE(lacking[1].find("requires an available GraspGripperSkillType with gripType "
                              "\"vacuum\": none is in the cell, and no earlier step mounts"),
              std::string::npos)
        << lacking[1];

    // A live vacuum gripper the KB knows of meets it.
    facts.add(keyOf(grasp("urn:schmalz")), kGripType, "vacuum");
    EXPECT_TRUE(infeasibility(process, {pickAndPlace(), grasp("urn:schmalz")}, &facts).empty());

    // None live, but step 1 takes its tool from a dock that holds a vacuum gripper.
    ProcessStep change;
    change.index = 1;
    change.skillTypeIri = std::string(kCs) + "PickAndPlaceSkillType";
    DerivationSource dock;
    dock.iri = "urn:dockV";
    dock.pose = devices::Pose6{};
    dock.held = {{kGripType, "vacuum"}};
    change.parameters.push_back({"ToolPosition", dock});
    process.steps.insert(process.steps.begin(), change);
    EXPECT_EQ(infeasibility(process, {pickAndPlace()}, &facts).size(), 1U)
        << "step 1 lacks its parameter ToolPosition on the live skill";
    // A tool brought by a later step does not count.
    std::swap(process.steps[0].index, process.steps[1].index);
    std::swap(process.steps[0], process.steps[1]);
    const auto late = infeasibility(process, {pickAndPlace()}, &facts);
    EXPECT_TRUE(std::any_of(late.begin(), late.end(), [](const std::string& l) {
        return l.find("no earlier step mounts") != std::string::npos;
    })) << late.size();

    // Without a KB, requirements are left to the steps.
    EXPECT_TRUE(infeasibility({"urn:p", {pickStep({{kGripType, "vacuum", kGrasp}})}, {}},
                              {pickAndPlace()}, nullptr)
                    .empty());
}

TEST(SkillFacts, TheQueryAlwaysAsksWhichSkillsTheKnowledgeBaseRecorded) {
    const std::string available = "<" + std::string(kProcessNs) + "available>";
    // A process's check asks only for the facts its requirements name; proc:available goes
    // with them, or every skill looks not recorded yet and the check waits its whole bound.
    ProcessDescription process;
    process.iri = "urn:p";
    process.steps = {pickStep({{kGripType, "magnetic", kGrasp}})};
    const auto properties = requiredProperties(process);
    ASSERT_EQ(properties, (std::vector<std::string>{kGripType}));
    auto q = factQuery(properties);
    ASSERT_TRUE(q) << q.error();
    EXPECT_NE(q->find(available), std::string::npos) << *q;
    // Asked for already, it is one branch of the query (its IRI twice: pattern and BIND).
    q = factQuery({std::string(kProcessNs) + "available", kGripType});
    ASSERT_TRUE(q) << q.error();
    std::size_t times = 0;
    for (auto at = q->find(available); at != std::string::npos; at = q->find(available, at + 1)) {
        ++times;
    }
    EXPECT_EQ(times, 2U) << *q;
}

}  // namespace
}  // namespace skillcell::mes::skill_facts_test
