// The dashboard's SceneWatcher against a real world model server: the first scene is whole
// (sizes, docks, poses, tools), and what a robot then changes through the world's methods
// (the flange moves, a tool is mounted) arrives by the subscription, without any polling.
// A DIN rail is drawn from its start to its end, and a terminal block snapped onto it shows
// the rail and its position along it.
#include "dashboard/scene_watcher.hpp"

#include <gtest/gtest.h>

#include <asio.hpp>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "devices/common/frame.hpp"
#include "devices/world/din_rail.hpp"
#include "devices/world/fuse_slot.hpp"
#include "devices/world/world_link.hpp"
#include "devices/world/world_nodes.hpp"
#include "running_server.hpp"

namespace skillcell::dashboard {
namespace {

// The robot whose flange the tests move (the world has it by this id).
const std::string kArm = "arm";

using namespace std::chrono_literals;

KDL::Frame at(double x, double y, double z, double a = 0) {
    return devices::toFrame(devices::Pose6{x, y, z, a, 0, 0});
}

/// The scenes a watcher reports, for a test to wait on.
class Scenes {
public:
    void add(const SceneView& s) {
        const std::lock_guard lock(mutex_);
        last_ = s;
        ++count_;
        changed_.notify_all();
    }
    /// Waits (at most 10 s) for a scene that `ok` accepts; the last one either way.
    std::optional<SceneView> waitFor(const std::function<bool(const SceneView&)>& ok) {
        std::unique_lock lock(mutex_);
        changed_.wait_for(lock, 10s, [&] { return last_ && ok(*last_); });
        return last_;
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::optional<SceneView> last_;
    int count_ = 0;
};

/// A world model server holding `world`, watched by a SceneWatcher on a thread of its own;
/// what it reports goes to `scenes`. Stops the watch, then the world, when it goes.
class WatchedWorld {
public:
    explicit WatchedWorld(devices::World world)
        : server_(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
              auto created = devices::WorldNodes::create(s, std::move(world));
              ASSERT_TRUE(created.ok());
              nodes_ = std::move(*created);
          }) {
        thread_ = std::thread([this] { io_.run(); });
        watcher_ = SceneWatcher::start(io_.get_executor(), server_.url(), ua::ClientConfig{},
                                       [this](const SceneView& s) { scenes.add(s); });
    }
    WatchedWorld(const WatchedWorld&) = delete;
    WatchedWorld& operator=(const WatchedWorld&) = delete;
    ~WatchedWorld() {
        asio::post(io_, [w = watcher_] { w->stop(); });
        work_.reset();
        thread_.join();  // the watch ends: its connection closes
        server_.inServer([this](ua::Server&) { nodes_.reset(); });
    }
    [[nodiscard]] bool ready() const { return nodes_ != nullptr; }
    [[nodiscard]] std::string url() const { return server_.url(); }

    Scenes scenes;

private:
    std::unique_ptr<devices::WorldNodes> nodes_;
    test::RunningServer server_;
    asio::io_context io_{1};
    asio::executor_work_guard<asio::io_context::executor_type> work_ = asio::make_work_guard(io_);
    std::thread thread_;
    std::shared_ptr<SceneWatcher> watcher_;
};

TEST(SceneWatcher, TheFirstSceneIsWholeAndChangesComeBySubscription) {
    devices::World w;
    ASSERT_EQ(w.addRobot(kArm, at(-0.1, 0.2, 0)), ua::status::Good);
    ASSERT_EQ(w.addObject({"box1", {0.04, 0.1, 0.05}, at(0.45, 0.15, 0.025)}), ua::status::Good);
    ASSERT_EQ(w.addDock({"dock1", at(0.3, -0.45, 0.35, M_PI), {}}), ua::status::Good);
    ASSERT_EQ(w.addTool({"parallel", at(0, 0, 0.15)}, "dock1"), ua::status::Good);
    WatchedWorld world(std::move(w));
    ASSERT_TRUE(world.ready());
    Scenes& scenes = world.scenes;

    auto first = scenes.waitFor([](const SceneView& s) { return !s.objects.empty(); });
    ASSERT_TRUE(first);
    ASSERT_EQ(first->objects.size(), 1U);
    EXPECT_EQ(first->objects[0].id, "box1");
    EXPECT_NEAR(first->objects[0].position[0], 0.45, 1e-9);
    EXPECT_NEAR(first->objects[0].position[1], 0.15, 1e-9);
    EXPECT_NEAR(first->objects[0].size[1], 0.1, 1e-9);
    ASSERT_EQ(first->docks.size(), 1U);
    EXPECT_EQ(first->docks[0].tool, "parallel");
    EXPECT_NEAR(first->docks[0].position[0], 0.3, 1e-9);
    ASSERT_EQ(first->robots.size(), 1U);
    EXPECT_EQ(first->robots[0].id, kArm);
    EXPECT_NEAR(first->robots[0].base[1], 0.2, 1e-9);
    EXPECT_EQ(first->robots[0].mountedTool, "");

    // A robot takes the tool from the dock, as the tool changer's skill would.
    auto link = devices::WorldLink::connect(world.url(), {}, kArm);
    ASSERT_TRUE(link.ok());
    ASSERT_EQ((*link)->setFlangePose(at(0.3, -0.45, 0.35, M_PI)), ua::status::Good);
    ASSERT_EQ((*link)->mountTool("dock1"), ua::status::Good);
    auto mounted = scenes.waitFor([](const SceneView& s) {
        return s.robots.size() == 1 && s.robots[0].mountedTool == "parallel" &&
               s.docks.size() == 1 && s.docks[0].tool.empty();
    });
    ASSERT_TRUE(mounted);
    EXPECT_EQ(mounted->docks[0].tool, "");
    EXPECT_NEAR(mounted->robots[0].flange[1], -0.45, 1e-9);

    ASSERT_EQ((*link)->setFlangePose(at(0.2, 0.1, 0.4, M_PI)), ua::status::Good);
    auto moved = scenes.waitFor(
        [](const SceneView& s) { return std::abs(s.robots[0].flange[0] - 0.2) < 1e-9; });
    ASSERT_TRUE(moved);
    EXPECT_NEAR(moved->robots[0].flange[1], 0.1, 1e-9);
}

TEST(SceneWatcher, ARailAndATerminalBlockSnappedOntoIt) {
    const devices::BoxSize block{0.0052, 0.045, 0.035};
    const devices::DinRail rail{"rail1", at(0.3, 0.3, 0.0075), 0.2};
    devices::World w;
    ASSERT_EQ(w.addRobot(kArm), ua::status::Good);
    ASSERT_EQ(w.addRail(rail), ua::status::Good);
    ASSERT_EQ(w.addObject({"tb1", block, at(0.45, 0, 0.0175), devices::ObjectKind::TerminalBlock}),
              ua::status::Good);
    ASSERT_EQ(w.addObject({"box1", {0.04, 0.04, 0.04}, at(0.45, 0.15, 0.02)}), ua::status::Good);
    ASSERT_EQ(w.addDock({"dock1", at(0.3, -0.45, 0.35, M_PI), {}}), ua::status::Good);
    ASSERT_EQ(w.addTool({"parallel", at(0, 0, 0.15)}, "dock1"), ua::status::Good);
    WatchedWorld world(std::move(w));
    ASSERT_TRUE(world.ready());
    Scenes& scenes = world.scenes;
    auto first = scenes.waitFor([](const SceneView& s) { return !s.rails.empty(); });
    ASSERT_TRUE(first);
    ASSERT_EQ(first->rails.size(), 1U);
    EXPECT_EQ(first->rails[0].id, "rail1");
    EXPECT_NEAR(first->rails[0].start[0], 0.3, 1e-9);
    EXPECT_NEAR(first->rails[0].end[0], 0.5, 1e-9);
    EXPECT_NEAR(first->rails[0].end[1], 0.3, 1e-9);
    ASSERT_EQ(first->objects.size(), 2U);
    for (const auto& o : first->objects) {
        EXPECT_EQ(o.terminalBlock, o.id == "tb1") << o.id;
        EXPECT_EQ(o.rail, "") << o.id;
    }

    // A robot picks tb1 from the top, hooks it over the rail's upper edge and rotates it down.
    auto link = devices::WorldLink::connect(world.url(), {}, kArm);
    ASSERT_TRUE(link.ok());
    devices::WorldLink& robot = **link;
    const KDL::Frame gripPoint = at(0, 0, 0.15);
    const KDL::Frame gripInBlock(KDL::Rotation::RotX(M_PI), KDL::Vector::Zero());
    auto flangeFor = [&](const KDL::Frame& blockPose) {
        return blockPose * gripInBlock * gripPoint.Inverse();
    };
    ASSERT_EQ(robot.setFlangePose(at(0.3, -0.45, 0.35, M_PI)), ua::status::Good);
    ASSERT_EQ(robot.mountTool("dock1"), ua::status::Good);
    ASSERT_EQ(robot.setFlangePose(flangeFor(at(0.45, 0, 0.0175))), ua::status::Good);
    ASSERT_EQ(robot.grasp("tb1"), ua::status::Good);
    for (int i = 0; i <= 3; ++i) {
        const double tilt = devices::kHookTilt * (3 - i) / 3;
        ASSERT_EQ(robot.setFlangePose(flangeFor(devices::hookedPose(rail, 0.0026, block, tilt))),
                  ua::status::Good);
    }
    ASSERT_EQ(robot.release(), ua::status::Good);
    auto tb1 = [](const SceneView& s) -> const SceneView::Box* {
        for (const auto& o : s.objects) {
            if (o.id == "tb1") return &o;
        }
        return nullptr;
    };
    auto snapped = scenes.waitFor(
        [&](const SceneView& s) { return tb1(s) != nullptr && tb1(s)->rail == "rail1"; });
    ASSERT_TRUE(snapped && tb1(*snapped));
    EXPECT_EQ(tb1(*snapped)->rail, "rail1");
    EXPECT_NEAR(tb1(*snapped)->railPosition, 0.0026, 1e-9);
    EXPECT_NEAR(tb1(*snapped)->position[0], 0.3026, 1e-9);
}

TEST(SceneWatcher, AFuseSlotAndTheFuseSeatedInIt) {
    const devices::BoxSize ato{0.0191, 0.0051, 0.0185};
    devices::FuseSlot slot;
    slot.id = "F1";
    slot.pose = at(0.45, 0.25, 0.06);
    devices::World w;
    ASSERT_EQ(w.addRobot(kArm), ua::status::Good);
    ASSERT_EQ(w.addFuseSlot(slot), ua::status::Good);
    ASSERT_EQ(w.addObject({"fuse1", ato, at(0.45, -0.05, ato.z / 2), devices::ObjectKind::Fuse}),
              ua::status::Good);
    ASSERT_EQ(w.addDock({"dock1", at(0.3, -0.45, 0.35, M_PI), {}}), ua::status::Good);
    ASSERT_EQ(w.addTool({"parallel", at(0, 0, 0.15)}, "dock1"), ua::status::Good);
    WatchedWorld world(std::move(w));
    ASSERT_TRUE(world.ready());
    Scenes& scenes = world.scenes;
    auto first = scenes.waitFor([](const SceneView& s) { return !s.fuseSlots.empty(); });
    ASSERT_TRUE(first);
    ASSERT_EQ(first->fuseSlots.size(), 1U);
    EXPECT_EQ(first->fuseSlots[0].id, "F1");
    EXPECT_NEAR(first->fuseSlots[0].position[1], 0.25, 1e-9);
    EXPECT_EQ(first->fuseSlots[0].fuse, "");

    // A robot picks the fuse from the top and pushes it into the slot to its depth.
    auto link = devices::WorldLink::connect(world.url(), {}, kArm);
    ASSERT_TRUE(link.ok());
    devices::WorldLink& robot = **link;
    const KDL::Frame gripPoint = at(0, 0, 0.15);
    const KDL::Frame gripInFuse(KDL::Rotation::RotX(M_PI), KDL::Vector::Zero());
    auto flangeFor = [&](const KDL::Frame& fusePose) {
        return fusePose * gripInFuse * gripPoint.Inverse();
    };
    ASSERT_EQ(robot.setFlangePose(at(0.3, -0.45, 0.35, M_PI)), ua::status::Good);
    ASSERT_EQ(robot.mountTool("dock1"), ua::status::Good);
    ASSERT_EQ(robot.setFlangePose(flangeFor(at(0.45, -0.05, ato.z / 2))), ua::status::Good);
    ASSERT_EQ(robot.grasp("fuse1"), ua::status::Good);
    ASSERT_EQ(robot.setFlangePose(flangeFor(devices::seatedPose(slot, ato))), ua::status::Good);
    ASSERT_EQ(robot.release(), ua::status::Good);
    auto seated = scenes.waitFor([](const SceneView& s) {
        return s.fuseSlots.size() == 1 && s.fuseSlots[0].fuse == "fuse1";
    });
    ASSERT_TRUE(seated);
}

}  // namespace
}  // namespace skillcell::dashboard
