// The work cell of the paper (section VIII) as processes, with discovery on (in a private
// network namespace): world model, UR5, Kelvin tool changer (which powers the Robotiq 2F-85
// and Schmalz ECBPi adapters when it attaches them) and the pick-and-place composite, which
// finds the robot and the mounted tool by discovery. Change to the parallel gripper, pick
// and place box A; change to the vacuum gripper, pick and place box B; detach the tool. The
// test then checks the world model: both boxes at their targets, no tool mounted. The same
// runs with the DH-Robotics AG-95 as the parallel gripper: nothing above its adapter changes.
#include <gtest/gtest.h>

#include <csignal>
#include <functional>
#include <map>
#include <memory>
#include <thread>

#include "client_thread.hpp"
#include "devices/common/frame.hpp"
#include "devices/world/world_link.hpp"
#include "process_tree.hpp"
#include "simulated_cell.hpp"
#include "skills/reservation_client.hpp"

namespace skillcell::devices::device_work_cell_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

using test::parallelDock;
using test::poseValue;
using test::schmalzUri;
using test::textValue;
using test::vacuumDock;

void expectAt(WorldLink& w, const std::string& id, double x, double y, double z) {
    const auto p = w.objectPose(id);
    ASSERT_TRUE(p.ok()) << id;
    EXPECT_NEAR(p->p.x(), x, 1e-3) << id;
    EXPECT_NEAR(p->p.y(), y, 1e-3) << id;
    EXPECT_NEAR(p->p.z(), z, 1e-3) << id;
}

class WorkCell : public testing::TestWithParam<test::ParallelGripperModel> {};

TEST_P(WorkCell, ChangesToolsAndPicksAndPlacesTwoBoxesFoundByDiscovery) {
    // The paper's boxes, and box C out of the robot's reach.
    auto boxes = test::paperObjects();
    boxes.emplace_back("boxC:0.04,0.04,0.04@1.5,0,0.02");
    test::SimulatedCell cell(SKILLCELL_BINARY, boxes, true, GetParam());
    ASSERT_TRUE(cell.ready());

    auto link = WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    test::ClientThread client, pickClient;  // one connection each
    auto change =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    auto detach =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/DetachTool")));
    auto pick =
        pickClient.attach(cell.pickplace->url(), ua::NodeId(1, ua::String("Skills/PickAndPlace")));
    ASSERT_TRUE(change && detach && pick);

    // Another holder has the robot (a second MES): the changer does not move it, and says
    // who holds it. Released, the change runs; the changer holds the robot while it moves it,
    // and lets go of it at its end (checked at the end of the test).
    test::ClientThread other;
    const std::uint64_t token = other.run([&]() -> asio::awaitable<std::uint64_t> {
        if ((co_await other.client().connect(cell.robot->url())).isBad()) co_return 0;
        auto t = co_await skills::reserve(other.client(), "urn:test:another-mes", false);
        co_return t ? *t : 0;
    });
    ASSERT_NE(token, 0U);
    auto outcome = client.invoke(change,
                                 {{"ToolPosition", poseValue(parallelDock())},
                                  {"ToolAppUri", textValue(cell.parallelUri.c_str())}},
                                 60s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("reserved by urn:test:another-mes (BadResourceUnavailable)"),
              std::string::npos)
        << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "");
    ASSERT_EQ(client.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await change->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);
    ASSERT_EQ(other.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await skills::release(other.client(), token);
    }),
              ua::status::Good);

    outcome = client.invoke(change,
                            {{"ToolPosition", poseValue(parallelDock())},
                             {"ToolAppUri", textValue(cell.parallelUri.c_str())}},
                            60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    outcome = pickClient.invoke(
        pick,
        {{"ObjectId", textValue("boxA")}, {"PlacePosition", poseValue("0.25,0.35,0.025,0,0,0")}},
        120s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.graspedObject(), "");
    expectAt(w, "boxA", 0.25, 0.35, 0.025);

    outcome = client.invoke(
        change,
        {{"ToolPosition", poseValue(vacuumDock())}, {"ToolAppUri", textValue(schmalzUri())}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    outcome = pickClient.invoke(
        pick,
        {{"ObjectId", textValue("boxB")}, {"PlacePosition", poseValue("0.25,-0.2,0.02,0,0,0")}},
        120s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    expectAt(w, "boxB", 0.25, -0.2, 0.02);

    // A sub-skill that fails ends the composite with the step and the robot's reason.
    outcome = pickClient.invoke(
        pick, {{"ObjectId", textValue("boxC")}, {"PlacePosition", poseValue("0.3,0.2,0.02,0,0,0")}},
        120s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("step approach: the move"), std::string::npos) << outcome.reason;
    expectAt(w, "boxC", 1.5, 0, 0.02);
    ASSERT_EQ(pickClient.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await pick->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);

    outcome = client.invoke(detach, {{"ToolPosition", poseValue(vacuumDock())}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;

    // The world: both boxes at their targets, no tool mounted, nothing held.
    expectAt(w, "boxA", 0.25, 0.35, 0.025);
    expectAt(w, "boxB", 0.25, -0.2, 0.02);
    EXPECT_EQ(*w.mountedTool(), "");
    EXPECT_EQ(*w.graspedObject(), "");
    // The composites let go of the robot after each run, failed ones too.
    EXPECT_EQ(other.run([&]() -> asio::awaitable<std::string> {
        co_return co_await skills::reservationHolder(other.client());
    }),
              "");

    // No tool: the composite fails cleanly, naming what is missing.
    outcome = pickClient.invoke(
        pick,
        {{"ObjectId", textValue("boxB")}, {"PlacePosition", poseValue("0.3,-0.2,0.02,0,0,0")}},
        120s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("GraspGripperSkillType"), std::string::npos) << outcome.reason;
}

// A composite killed mid-pick, the box in its gripper: the composite started again carries the
// box on to its place from where it is, without letting go of it or taking it again; asked once
// more, it finds the box at its place and does nothing.
// The changer takes the parallel gripper from its dock (ChangeTool).
void mountParallelGripper(test::SimulatedCell& cell) {
    test::ClientThread client;
    auto change =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    ASSERT_TRUE(change);
    const auto outcome = client.invoke(change,
                                       {{"ToolPosition", poseValue(parallelDock())},
                                        {"ToolAppUri", textValue(cell.parallelUri.c_str())}},
                                       60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
}

// Whether the robot holds `id` within 30 s (a bounded poll of the world model).
bool grasps(WorldLink& w, const std::string& id) {
    for (int i = 0; i < 1500; ++i) {
        if (*w.graspedObject() == id) return true;
        std::this_thread::sleep_for(20ms);
    }
    return false;
}

const std::map<std::string, ua::Variant>& pickBoxA() {
    static const std::map<std::string, ua::Variant> request = {
        {"ObjectId", textValue("boxA")}, {"PlacePosition", poseValue("0.25,0.35,0.025,0,0,0")}};
    return request;
}

/// The settling tests' cell: the paper's, the parallel gripper mounted, and a pick of boxA
/// that a test cuts into once the box is in the gripper.
class Settling {
public:
    explicit Settling(test::ParallelGripperModel parallel = test::kRobotiq2f85)
        : cell(SKILLCELL_BINARY, test::paperObjects(), true, parallel) {}

    /// Whether the cell came up with the gripper mounted; world() is usable then.
    [[nodiscard]] bool ready() {
        if (!cell.ready()) return false;
        auto connected = WorldLink::connect(cell.world->url(), {}, cell.robotName);
        if (!connected.ok()) return false;
        link_ = std::move(*connected);
        mountParallelGripper(cell);
        return !testing::Test::HasFatalFailure();
    }
    WorldLink& world() { return *link_; }

    /// Runs the pick of boxA and calls `cut` once the world shows boxA grasped; the pick's
    /// outcome, and whether boxA was grasped (else `cut` was not called).
    std::pair<skills::SkillOutcome, bool> pickCutBy(const std::function<void()>& cut) {
        test::ClientThread client;
        auto pick =
            client.attach(cell.pickplace->url(), ua::NodeId(1, ua::String("Skills/PickAndPlace")));
        if (!pick) return {skills::SkillOutcome{}, false};
        skills::SkillOutcome outcome;
        std::thread running([&] { outcome = client.invoke(pick, pickBoxA(), 120s); });
        const bool grasped = grasps(*link_, "boxA");
        if (grasped) cut();
        running.join();
        return {outcome, grasped};
    }

    test::SimulatedCell cell;

private:
    std::unique_ptr<WorldLink> link_;
};

TEST(WorkCellSettling, APickCutShortIsCarriedOnFromWhereTheBoxIsNotPickedAgain) {
    Settling settling;
    ASSERT_TRUE(settling.ready());
    test::SimulatedCell& cell = settling.cell;
    WorldLink& w = settling.world();
    const auto& request = pickBoxA();
    auto [outcome, grasped] = settling.pickCutBy([&] { cell.pickplace->kill(SIGKILL); });
    ASSERT_TRUE(grasped) << "the first run never grasped boxA: " << outcome.reason;
    EXPECT_EQ(outcome.kind, Kind::Lost) << outcome.reason;
    EXPECT_EQ(*w.graspedObject(), "boxA");
    EXPECT_EQ(*w.objectGrasps("boxA"), 1U);
    EXPECT_FALSE(near(*w.objectPose("boxA"), KDL::Frame(KDL::Vector(0.25, 0.35, 0.025)), 0.01, 1))
        << "the first run got further than its grasp";

    cell.restartPickAndPlace();
    ASSERT_FALSE(cell.pickplace->url().empty());
    test::ClientThread again;
    auto pick =
        again.attach(cell.pickplace->url(), ua::NodeId(1, ua::String("Skills/PickAndPlace")));
    ASSERT_TRUE(pick);
    outcome = again.invoke(pick, request, 120s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    expectAt(w, "boxA", 0.25, 0.35, 0.025);
    EXPECT_EQ(*w.graspedObject(), "");
    EXPECT_EQ(*w.objectGrasps("boxA"), 1U) << "boxA was let go of and taken again";

    // At its place, the box needs nothing more: the robot stays where it is.
    const auto flange = *w.flangePose();
    outcome = again.invoke(pick, request, 120s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.objectGrasps("boxA"), 1U);
    EXPECT_TRUE(near(*w.flangePose(), flange, 1e-6, 1e-6));
}

// The robot killed mid-pick, the box in the gripper, and started again: the composite's run
// goes on once discovery finds the robot again, from where the box is, and places it.
TEST(WorkCellSettling, APickWhoseRobotDiesGoesOnWhenTheRobotIsBack) {
    Settling settling;
    ASSERT_TRUE(settling.ready());
    test::SimulatedCell& cell = settling.cell;
    WorldLink& w = settling.world();
    const auto [outcome, grasped] = settling.pickCutBy([&] {
        cell.robot->kill(SIGKILL);
        cell.restartRobot();
    });
    ASSERT_TRUE(grasped) << "the run never grasped boxA: " << outcome.reason;
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    expectAt(w, "boxA", 0.25, 0.35, 0.025);
    EXPECT_EQ(*w.graspedObject(), "");
    EXPECT_EQ(*w.objectGrasps("boxA"), 1U);
}

// The gripper's adapter dies mid-pick, the box in its fingers; the changer's watchdog starts
// it again, and the gripper it finds still holds the box (a 2F-85 or an AG-95 keeps its grip
// while its client restarts): the pick goes on, lets go of the box at its place, and the
// tool can be put back in its dock (a tool that still held the box could not).
TEST_P(WorkCell, APickWhoseGripperAdapterDiesGoesOnWithTheBoxStillHeld) {
    Settling settling(GetParam());
    ASSERT_TRUE(settling.ready());
    test::SimulatedCell& cell = settling.cell;
    WorldLink& w = settling.world();
    const auto adapters = test::childrenOf(cell.changer->pid());
    ASSERT_EQ(adapters.size(), 1U);
    auto [outcome, grasped] = settling.pickCutBy([&] { ::kill(adapters[0], SIGKILL); });
    ASSERT_TRUE(grasped) << "the run never grasped boxA: " << outcome.reason;
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    expectAt(w, "boxA", 0.25, 0.35, 0.025);
    EXPECT_EQ(*w.graspedObject(), "") << "the restarted gripper never let go of the box";
    EXPECT_EQ(*w.objectGrasps("boxA"), 1U);
    test::ClientThread changer;
    auto detach =
        changer.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/DetachTool")));
    ASSERT_TRUE(detach);
    outcome = changer.invoke(detach, {{"ToolPosition", poseValue(parallelDock())}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
}

INSTANTIATE_TEST_SUITE_P(ParallelGrippers, WorkCell,
                         testing::Values(test::kRobotiq2f85, test::kDhAg95),
                         [](const testing::TestParamInfo<test::ParallelGripperModel>& model) {
                             return std::string(model.param.adapter().command);
                         });

}  // namespace
}  // namespace skillcell::devices::device_work_cell_test
