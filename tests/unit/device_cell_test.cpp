// The devices together, in one process but each on its own server as in the cell: the
// world model, the UR5 reporting its flange there, and the 2F-85 adapter on a simulated
// gripper that asks the world what lies between its fingers. A box is picked and placed
// by running the skills through SkillClients; the test checks the world, not logs.
#include <gtest/gtest.h>

#include <thread>

#include "client_thread.hpp"
#include "devices/arm/arm_component.hpp"
#include "devices/common/frame.hpp"
#include "devices/robotiq/robotiq_component.hpp"
#include "devices/robotiq/simulated_gripper_port.hpp"
#include "devices/world/flange_reporter.hpp"
#include "devices/world/world_link.hpp"
#include "devices/world/world_nodes.hpp"
#include "running_server.hpp"

namespace skillcell::devices::device_cell_test {
namespace {

// The robot whose flange the tests move (the world has it by this id).
const std::string kArm = "arm";

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;
namespace rq = robotiq;

KDL::Frame at(double x, double y, double z, double a = 0, double b = 0, double c = 0) {
    return toFrame(Pose6{x, y, z, a, b, c});
}

/// Tool pointing down (the flange's z axis along the base's -z).
KDL::Frame down(double x, double y, double z) {
    return at(x, y, z, M_PI, 0, 0);
}

TEST(DeviceCell, AGraspedBoxTravelsWithTheRobotAndStaysWhereItIsReleased) {
    const KDL::Frame gripOffset(KDL::Vector(0, 0, 0.15));
    const KDL::Frame dockPose = down(0.3, -0.45, 0.35);

    // The world model.
    std::unique_ptr<WorldNodes> worldNodes;
    test::RunningServer worldServer(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
        World w;
        EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
        ASSERT_EQ(w.addObject({"box1", {0.04, 0.04, 0.04}, at(0.45, 0.15, 0.02)}),
                  ua::status::Good);
        ASSERT_EQ(w.addDock({"dock1", dockPose, {}}), ua::status::Good);
        ASSERT_EQ(w.addTool({"2f85", gripOffset}, "dock1"), ua::status::Good);
        auto created = WorldNodes::create(s, w);
        ASSERT_TRUE(created.ok());
        worldNodes = std::move(*created);
    });
    auto worldOf = [&] {
        return worldServer.inServer([&](ua::Server&) { return worldNodes->world(); });
    };

    // The robot, reporting its flange to the world.
    auto robotLink = WorldLink::connect(worldServer.url(), {}, kArm);
    ASSERT_TRUE(robotLink.ok());
    auto reporter = FlangeReporter::start(std::move(*robotLink));
    std::unique_ptr<ArmComponent> robot;
    test::RunningServer robotServer(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
        ArmComponentOptions o;
        o.arm.speed = 20;
        o.arm.tick = 2ms;
        o.onFlange = [r = reporter.get()](const KDL::Frame& f) { r->report(f); };
        // A move ends only once the world has its final flange pose.
        o.arm.beforeDone = [r = reporter.get()](std::function<void()> report) {
            r->whenSent(std::move(report));
        };
        auto c = ArmComponent::create(s, o);
        ASSERT_TRUE(c.ok());
        robot = std::move(*c);
    });

    // The gripper: the simulated 2F-85 knows the world, the adapter only a device path.
    auto gripperLink = WorldLink::connect(worldServer.url(), {}, kArm);
    ASSERT_TRUE(gripperLink.ok());
    WorldLink* gl = gripperLink->get();
    rq::SimulatedGripperOptions sim;
    sim.speed = 20;
    sim.probe = [gl]() -> std::optional<rq::ObjectBetweenFingers> {
        const auto found = gl->objectAtGripPoint();
        if (!found || !found->has_value()) return std::nullopt;
        return rq::ObjectBetweenFingers{(*found)->objectId, (*found)->extent[1]};
    };
    sim.onEvent = [gl](const rq::FingerEvent& e) {
        EXPECT_EQ(e.kind == rq::FingerEvent::Kind::Grasped ? gl->grasp(e.objectId) : gl->release(),
                  ua::status::Good);
    };
    auto port = rq::SimulatedGripperPort::open(sim);
    ASSERT_TRUE(port);
    std::unique_ptr<GripperComponent> gripper;
    test::RunningServer gripperServer(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
        rq::RobotiqComponentOptions o;
        o.device = port->devicePath();
        o.gripPointOffset = gripOffset;
        o.gripper.poll = 1ms;
        auto c = rq::startRobotiqComponent(s, o);
        ASSERT_TRUE(c.ok());
        gripper = std::move(*c);
    });

    test::ClientThread robotClient, gripperClient;
    auto ptp =
        robotClient.attach(robotServer.url(), ua::NodeId(1, ua::String("Skills/CartesianPtpMove")));
    auto linear = robotClient.attach(robotServer.url(),
                                     ua::NodeId(1, ua::String("Skills/CartesianLinearMove")));
    auto grasp =
        gripperClient.attach(gripperServer.url(), ua::NodeId(1, ua::String("Skills/Grasp")));
    auto release =
        gripperClient.attach(gripperServer.url(), ua::NodeId(1, ua::String("Skills/Release")));
    ASSERT_TRUE(ptp && linear && grasp && release);
    auto moveFlange = [&](const std::shared_ptr<skills::SkillClient>& skill, const KDL::Frame& f) {
        const auto outcome =
            robotClient.invoke(skill, {{"TargetPosition", frameToVariant(f)}}, 20s);
        EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    };
    // The TCP (the grip point) moves; ToolFrame tells the robot where it is.
    auto moveTcp = [&](const KDL::Frame& tcp) {
        const auto outcome = robotClient.invoke(
            linear,
            {{"TargetPosition", frameToVariant(tcp)}, {"ToolFrame", frameToVariant(gripOffset)}},
            20s);
        EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    };

    // Take the gripper from its dock (the tool changer's part, done by hand here).
    moveFlange(ptp, down(0.3, -0.45, 0.45));
    moveFlange(linear, dockPose);
    ASSERT_EQ(gl->mountTool("dock1"), ua::status::Good);
    moveFlange(linear, down(0.3, -0.45, 0.45));
    EXPECT_EQ(worldOf().flange(kArm).tool, "2f85");

    // Grasping thin air fails, and the world holds nothing.
    auto outcome = gripperClient.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_TRUE(worldOf().flange(kArm).held.empty());
    gripperClient.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await grasp->call(skills::SkillMethod::Reset);
    });

    // Approach 5 cm above the box, go down, grasp.
    moveTcp(down(0.45, 0.15, 0.07));
    moveTcp(down(0.45, 0.15, 0.02));
    outcome = gripperClient.invoke(grasp, {}, 20s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(worldOf().flange(kArm).held, "box1");
    EXPECT_NEAR(rq::widthOf(static_cast<std::uint8_t>(port->fingerPosition())), 0.04, 0.0005);

    // Carry it: up, across, down. It travels with the flange.
    moveTcp(down(0.45, 0.15, 0.07));
    EXPECT_NEAR(worldOf().object("box1")->pose.p.z(), 0.07, 1e-6);
    moveTcp(down(0.30, -0.20, 0.07));
    moveTcp(down(0.30, -0.20, 0.021));
    outcome = gripperClient.invoke(release, {}, 20s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_TRUE(worldOf().flange(kArm).held.empty());

    // The robot leaves; the box stays where it was put.
    moveTcp(down(0.30, -0.20, 0.10));
    const World w = worldOf();
    const KDL::Frame box = w.object("box1")->pose;
    EXPECT_NEAR(box.p.x(), 0.30, 1e-6);
    EXPECT_NEAR(box.p.y(), -0.20, 1e-6);
    EXPECT_NEAR(box.p.z(), 0.021, 1e-6);
    EXPECT_NEAR(w.gripPoint(kArm).p.z(), 0.10, 1e-6);

    robotServer.inServer([&](ua::Server&) {
        robot.reset();
        return 0;
    });
    gripperServer.inServer([&](ua::Server&) {
        gripper.reset();
        return 0;
    });
    worldServer.inServer([&](ua::Server&) {
        worldNodes.reset();
        return 0;
    });
}

// A standing arm tells its pose once and then only when its link's connection goes or is made
// anew: a world model that restarts (a new one on the same port, which has not heard from the
// arm) still learns where the flange is, without the arm moving.
TEST(DeviceCell, AStandingArmTellsARestartedWorldWhereItsFlangeIs) {
    const KDL::Frame pose = down(0.4, 0.1, 0.3);
    const auto startWorld = [](std::unique_ptr<WorldNodes>& nodes, std::uint16_t port) {
        auto config = test::RunningServer::defaultConfig();
        config.description.port = port;
        return std::make_unique<test::RunningServer>(config, [&nodes](ua::Server& s) {
            World w;
            EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
            auto created = WorldNodes::create(s, w);
            ASSERT_TRUE(created.ok());
            nodes = std::move(*created);
        });
    };
    std::unique_ptr<WorldNodes> firstNodes;
    auto first = startWorld(firstNodes, 0);
    const std::uint16_t port = first->port();
    auto link = WorldLink::connect(first->url(), {}, kArm);
    ASSERT_TRUE(link.ok());
    auto reporter = FlangeReporter::start(std::move(*link));
    reporter->report(pose);
    ASSERT_TRUE(reporter->flush(5s));

    first.reset();
    firstNodes.reset();
    std::unique_ptr<WorldNodes> secondNodes;
    auto second = startWorld(secondNodes, port);
    const auto heard = [&] {
        const World w = second->inServer([&](ua::Server&) { return secondNodes->world(); });
        const auto robot = w.robots().find(kArm);
        return robot != w.robots().end() && near(robot->second.pose, pose, 1e-9, 1e-9);
    };
    // Within half the 10 s after which a standing arm tells its pose anyway.
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (!heard() && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(20ms);  // the arm's thread tells it, in its own time
    }
    EXPECT_TRUE(heard());
    reporter.reset();
}

}  // namespace
}  // namespace skillcell::devices::device_cell_test
