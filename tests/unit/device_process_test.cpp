// The device components as processes, as the cell runs them: `skillcell device world`
// seeded from its command line, `device ur5 --world` and `device schmalz --world`. The
// robot takes the vacuum gripper from its dock (the test plays the tool changer's part),
// picks a box and puts it down elsewhere through the skills; the test then checks the
// world model.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <future>
#include <memory>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "client_thread.hpp"
#include "component_process.hpp"
#include "devices/common/frame.hpp"
#include "devices/world/world_link.hpp"
#include "temp_dir.hpp"
#include "ua/client/blocking_client.hpp"

namespace skillcell::devices::device_process_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

/// `skillcell device ...` (tests/support/component_process.hpp), without discovery.
struct DeviceProcess : test::DeviceProcess {
    explicit DeviceProcess(std::vector<std::string> args)
        : test::DeviceProcess(SKILLCELL_BINARY, std::move(args)) {}
};

KDL::Frame down(double x, double y, double z) {
    return toFrame(Pose6{x, y, z, M_PI, 0, 0});
}

TEST(DeviceProcesses, TheRobotPicksAndPlacesABoxWithTheVacuumGripper) {
    // Poses: the dock where the flange takes the gripper, the box on the table.
    const std::string dock = "0.3,-0.45,0.35,3.141592653589793,0,0";
    DeviceProcess world({"world", "--object", "box1:0.04,0.04,0.04@0.45,0.15,0.02", "--dock",
                         "dock1@" + dock, "--tool", "ecbpi:dock1@0,0,0.12"});
    ASSERT_FALSE(world.url().empty());
    DeviceProcess robot({"ur5", "--speed", "20", "--world", world.url()});
    DeviceProcess gripper({"schmalz", "--speed", "20", "--world", world.url()});
    ASSERT_FALSE(robot.url().empty());
    ASSERT_FALSE(gripper.url().empty());

    auto link = WorldLink::connect(world.url(), {}, "robot");
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    test::ClientThread robotClient, gripperClient;
    auto ptp =
        robotClient.attach(robot.url(), ua::NodeId(1, ua::String("Skills/CartesianPtpMove")));
    auto linear =
        robotClient.attach(robot.url(), ua::NodeId(1, ua::String("Skills/CartesianLinearMove")));
    auto grasp = gripperClient.attach(gripper.url(), ua::NodeId(1, ua::String("Skills/Grasp")));
    auto release = gripperClient.attach(gripper.url(), ua::NodeId(1, ua::String("Skills/Release")));
    ASSERT_TRUE(ptp && linear && grasp && release);

    const KDL::Frame cup(KDL::Vector(0, 0, 0.12));
    auto move = [&](const std::shared_ptr<skills::SkillClient>& skill, const KDL::Frame& tcp,
                    const KDL::Frame& tool) {
        const auto outcome = robotClient.invoke(
            skill, {{"TargetPosition", frameToVariant(tcp)}, {"ToolFrame", frameToVariant(tool)}},
            20s);
        EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    };
    const KDL::Frame none = KDL::Frame::Identity();

    // To the dock and lock the gripper (the tool changer's part).
    move(ptp, down(0.3, -0.45, 0.45), none);
    move(linear, down(0.3, -0.45, 0.35), none);
    ASSERT_EQ(w.mountTool("dock1"), ua::status::Good);  // the flange is at the dock
    move(linear, down(0.3, -0.45, 0.45), none);

    // The cup on the box's top face: grasp. Up and over, down, release.
    move(linear, down(0.45, 0.15, 0.09), cup);
    move(linear, down(0.45, 0.15, 0.04), cup);
    auto outcome = gripperClient.invoke(grasp, {}, 20s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.graspedObject(), "box1");
    move(linear, down(0.45, 0.15, 0.09), cup);
    move(linear, down(0.25, -0.15, 0.09), cup);
    move(linear, down(0.25, -0.15, 0.041), cup);
    outcome = gripperClient.invoke(release, {}, 20s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    move(linear, down(0.25, -0.15, 0.10), cup);

    // A grasp above nothing fails with the reason; the world is unchanged.
    outcome = gripperClient.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("no part under the cup"), std::string::npos) << outcome.reason;

    EXPECT_EQ(*w.graspedObject(), "");
    const auto box = w.objectPose("box1");
    ASSERT_TRUE(box.ok());
    EXPECT_NEAR(box->p.x(), 0.25, 1e-6);
    EXPECT_NEAR(box->p.y(), -0.15, 1e-6);
    EXPECT_NEAR(box->p.z(), 0.021, 1e-6);  // the top face at 0.041
    EXPECT_EQ(*w.mountedTool(), "ecbpi");
}

// A robot controller killed and started again finds its arm where it stopped (absolute
// encoders: the world model has the flange there), holding what it held: it does not jump to
// its home pose, carrying the box along.
TEST(DeviceProcesses, ARestartedArmStartsWhereItsFlangeIsNotAtHome) {
    DeviceProcess world({"world", "--object", "box1:0.04,0.04,0.04@0.45,0.15,0.02"});
    ASSERT_FALSE(world.url().empty());
    auto link = WorldLink::connect(world.url(), {}, "robot");
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    auto robot = std::make_unique<DeviceProcess>(
        std::vector<std::string>{"ur5", "--speed", "20", "--world", world.url()});
    ASSERT_FALSE(robot->url().empty());
    const KDL::Frame home = *w.flangePose();
    {
        test::ClientThread client;
        auto ptp =
            client.attach(robot->url(), ua::NodeId(1, ua::String("Skills/CartesianPtpMove")));
        ASSERT_TRUE(ptp);
        const auto outcome = client.invoke(ptp,
                                           {{"TargetPosition", frameToVariant(down(0.4, 0.2, 0.3))},
                                            {"ToolFrame", frameToVariant(KDL::Frame::Identity())}},
                                           20s);
        ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    }
    const KDL::Frame stopped = *w.flangePose();
    EXPECT_TRUE(near(stopped, down(0.4, 0.2, 0.3), 1e-4, 1e-4)) << describe(stopped);
    EXPECT_FALSE(near(stopped, home, 0.01, 0.01));
    robot->kill(SIGKILL);
    robot.reset();
    robot = std::make_unique<DeviceProcess>(
        std::vector<std::string>{"ur5", "--speed", "20", "--world", world.url()});
    ASSERT_FALSE(robot->url().empty());
    // Its own report of the flange, and the world's, where it stopped.
    ua::BlockingClient client;
    ASSERT_EQ(client.connect(robot->url()), ua::status::Good);
    const auto published = client.readValue(ua::NodeId(1, ua::String("UR5/FlangePose")));
    ASSERT_TRUE(published.ok());
    const auto reported = frameFromVariant(*published);
    ASSERT_TRUE(reported.ok());
    EXPECT_TRUE(near(*reported, stopped, 1e-6, 1e-6)) << describe(*reported);
    EXPECT_TRUE(near(*w.flangePose(), stopped, 1e-6, 1e-6)) << describe(*w.flangePose());
}

// The world killed and started again on its state file goes on from the cell as it was (the
// box still in the gripper, the gripper still mounted), and a device's link to it connects
// again by itself, as a fieldbus does.
TEST(DeviceProcesses, AKilledWorldGoesOnFromItsStateFileAndItsLinksConnectAgain) {
    const test::TempDir dir("skillcell-world-state");
    const std::string state = (dir.path() / "world.json").string();
    const std::string dock = "0.3,-0.45,0.35,3.141592653589793,0,0";
    std::vector<std::string> args{"world",
                                  "--object",
                                  "box1:0.04,0.04,0.04@0.45,0.15,0.02",
                                  "--dock",
                                  "dock1@" + dock,
                                  "--tool",
                                  "ecbpi:dock1@0,0,0.12",
                                  "--state-file",
                                  state};
    auto world = std::make_unique<DeviceProcess>(args);
    ASSERT_FALSE(world->url().empty());
    const std::string url = world->url();
    auto link = WorldLink::connect(url, {}, "robot");
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    ASSERT_EQ(w.setFlangePose(down(0.3, -0.45, 0.35)), ua::status::Good);
    ASSERT_EQ(w.mountTool("dock1"), ua::status::Good);
    ASSERT_EQ(w.setFlangePose(down(0.45, 0.15, 0.04 + 0.12)), ua::status::Good);
    ASSERT_EQ(w.grasp("box1"), ua::status::Good);
    ASSERT_EQ(w.setFlangePose(down(0.2, -0.1, 0.3)), ua::status::Good);
    const KDL::Frame carried = *w.objectPose("box1");

    world->kill(SIGKILL);
    world.reset();
    EXPECT_NE(w.mountedTool().status(), ua::status::Good);
    EXPECT_TRUE(w.lostConnection());

    // A device started while the world is down (a tool's adapter powered as the world
    // restarts) waits for it instead of exiting: the test holds the world's port, closes the
    // device's first connection there, and starts the world only then.
    // The gripper lives on a thread of its own, which outlives it: a child is started with
    // PR_SET_PDEATHSIG, which fires when the thread that started it ends.
    const auto port = url.substr(url.rfind(':') + 1);
    std::promise<std::string> gripperUrl;
    std::promise<void> stopGripper;
    std::thread gripperThread;
    struct JoinAtEnd {
        std::promise<void>& stop;
        std::thread& thread;
        ~JoinAtEnd() {
            if (!thread.joinable()) return;
            stop.set_value();
            thread.join();
        }
    } joinAtEnd{stopGripper, gripperThread};
    {
        const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        ASSERT_GE(listener, 0);
        const int one = 1;
        ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        sockaddr_in at{};
        at.sin_family = AF_INET;
        at.sin_port = htons(static_cast<std::uint16_t>(std::stoi(port)));
        at.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ASSERT_EQ(::bind(listener, reinterpret_cast<const sockaddr*>(&at), sizeof at), 0);
        ASSERT_EQ(::listen(listener, 4), 0);
        gripperThread = std::thread([&url, &gripperUrl, stop = stopGripper.get_future()] {
            DeviceProcess gripper({"schmalz", "--speed", "20", "--world", url, "--robot", "robot"});
            gripperUrl.set_value(gripper.url());
            stop.wait();
        });
        pollfd ready{listener, POLLIN, 0};
        const bool tried = ::poll(&ready, 1, 30'000) == 1;
        if (tried) ::close(::accept(listener, nullptr, nullptr));  // a world not there yet
        ::close(listener);
        // Started again where it was (the port the devices know), on the same file.
        args.insert(args.end(), {"--port", port});
        world = std::make_unique<DeviceProcess>(args);
        ASSERT_TRUE(tried) << "the gripper never tried to reach the world";
    }
    ASSERT_EQ(world->url(), url);
    EXPECT_FALSE(gripperUrl.get_future().get().empty())
        << "a gripper started while the world was down";
    w.clearLoss();
    const auto tool = w.mountedTool();
    ASSERT_TRUE(tool.ok()) << ua::statusName(tool.status());
    EXPECT_EQ(*tool, "ecbpi");
    EXPECT_EQ(*w.graspedObject(), "box1");
    EXPECT_EQ(*w.objectGrasps("box1"), 1u);
    EXPECT_TRUE(near(*w.objectPose("box1"), carried, 1e-12, 1e-12));
    EXPECT_FALSE(w.lostConnection());
    // And it moves on with the flange as before the kill.
    ASSERT_EQ(w.setFlangePose(down(0.25, -0.15, 0.041 + 0.12)), ua::status::Good);
    ASSERT_EQ(w.release(), ua::status::Good);
    EXPECT_NEAR(w.objectPose("box1")->p.z(), 0.021, 1e-9);

    // A state file that is not one stops the world at start, naming it.
    stopGripper.set_value();
    gripperThread.join();
    world.reset();
    { std::ofstream(state) << "{\"format\": \"skillcell world 1\", \"revision\": 3}"; }
    DeviceProcess broken(args);
    EXPECT_TRUE(broken.url().empty());
    const auto ended = broken.kill(SIGTERM);  // it has exited already: this reaps it
    ASSERT_TRUE(ended);
    EXPECT_FALSE(ended->success()) << ended->describe();
}

}  // namespace
}  // namespace skillcell::devices::device_process_test
