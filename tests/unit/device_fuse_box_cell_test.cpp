// The InsertFuse composite in a work cell of processes (discovery on, in a private network
// namespace): the world model with the fuse slots and fuses of examples/cells/fuse-box.toml,
// the robot, the tool changer with the Robotiq 2F-85 and the pick-and-place component. With
// the KUKA iiwa a fuse goes into its slot, and what cannot be inserted is refused before
// anything moves, with the reason: a slot that holds a fuse, a slot the world does not have,
// an object that is no fuse, no force limit. A robot that senses no force (the UR5) is
// refused before it moves.
#include <gtest/gtest.h>

#include "client_thread.hpp"
#include "devices/world/world_link.hpp"
#include "simulated_cell.hpp"

namespace skillcell::devices::device_fuse_box_cell_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

/// The fuse-box cell's slots and fuses, and a box beside them, as the world model's arguments.
std::vector<std::string> fuseScene() {
    const cell::CellFile fuseBox = test::exampleCell("fuse-box");
    cell::CellFile scene;
    scene.fuseSlots = fuseBox.fuseSlots;
    scene.objects = fuseBox.objects;
    scene.objects.push_back({"box", {0.04, 0.04, 0.04}, {0.45, 0.1, 0.02}, {}, {}});
    return cell::worldArguments(scene);
}

/// A cell with `robot`, the parallel gripper mounted.
struct MountedCell {
    explicit MountedCell(const std::string& robot)
        : cell(SKILLCELL_BINARY, {}, true, test::kRobotiq2f85, false, "50", fuseScene(), robot) {
        if (!cell.ready()) {
            problem = "the cell did not come up";
            return;
        }
        auto change = changerClient.attach(cell.changer->url(),
                                           ua::NodeId(1, ua::String("Skills/ChangeTool")));
        insert =
            client.attach(cell.pickplace->url(), ua::NodeId(1, ua::String("Skills/InsertFuse")));
        if (!change || !insert) {
            problem = "no ChangeTool or InsertFuse skill";
            return;
        }
        const auto outcome =
            changerClient.invoke(change,
                                 {{"ToolPosition", test::poseValue(test::parallelDock())},
                                  {"ToolAppUri", test::textValue(cell.parallelUri.c_str())}},
                                 60s);
        mounted = outcome.kind == Kind::Finished;
        problem = outcome.reason;
    }
    skills::SkillOutcome run(const char* fuse, const char* slot, double limit = 20) {
        (void)client.run([&]() -> asio::awaitable<ua::StatusCode> {
            co_return co_await insert->call(skills::SkillMethod::Reset);
        });
        return client.invoke(insert,
                             {{"ObjectId", test::textValue(fuse)},
                              {"SlotId", test::textValue(slot)},
                              {"ForceLimit", ua::Variant(limit)}},
                             120s);
    }
    test::SimulatedCell cell;
    test::ClientThread changerClient, client;  // a client is connected to one server
    std::shared_ptr<skills::SkillClient> insert;
    bool mounted = false;
    std::string problem;  // why it is not mounted
};

TEST(FuseBoxCell, TheIiwaInsertsAFuseAndWhatCannotBeInsertedIsRefusedBeforeItMoves) {
    MountedCell c("iiwa");
    ASSERT_TRUE(c.mounted) << c.problem;
    auto link = WorldLink::connect(c.cell.world->url(), {}, c.cell.robotName);
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;

    auto outcome = c.run("fuse10A", "F1");
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.fuseSeat("fuse10A"), "F1");
    EXPECT_EQ(w.fuseSlot("F1")->fuse, "fuse10A");
    EXPECT_EQ(*w.graspedObject(), "");

    const auto before = w.objectPose("fuse15A");
    ASSERT_TRUE(before.ok());
    const std::pair<skills::SkillOutcome, const char*> refusals[] = {
        {c.run("fuse15A", "F1"), "slot F1 holds fuse fuse10A already"},
        {c.run("fuse15A", "F9"), "the world model has no fuse slot F9"},
        {c.run("box", "F2"), "object box is no fuse"},
        {c.run("fuse15A", "F2", 0), "ForceLimit must be above 0 N"},
    };
    for (const auto& [refused, reason] : refusals) {
        EXPECT_EQ(refused.kind, Kind::Failed) << reason;
        EXPECT_NE(refused.reason.find(reason), std::string::npos) << refused.reason;
    }
    const auto after = w.objectPose("fuse15A");
    ASSERT_TRUE(after.ok());
    EXPECT_TRUE(near(*before, *after, 1e-9, 1e-9));
    EXPECT_EQ(*w.fuseSeat("fuse15A"), "");
}

TEST(FuseBoxCell, ARobotThatSensesNoForceIsRefusedBeforeItMoves) {
    MountedCell c("ur5");
    ASSERT_TRUE(c.mounted) << c.problem;
    auto link = WorldLink::connect(c.cell.world->url(), {}, c.cell.robotName);
    ASSERT_TRUE(link.ok());
    const auto flange = (*link)->flangePose();
    ASSERT_TRUE(flange.ok());
    const auto outcome = c.run("fuse10A", "F1");
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("offers no CartesianForceLimitedLinearMove: a fuse is inserted "
                                  "under a force limit"),
              std::string::npos)
        << outcome.reason;
    const auto still = (*link)->flangePose();
    ASSERT_TRUE(still.ok());
    EXPECT_TRUE(near(*flange, *still, 1e-9, 1e-9));
}

}  // namespace
}  // namespace skillcell::devices::device_fuse_box_cell_test
