// The work cell of the paper (section VIII) as processes, with discovery on (in a private
// network namespace): world model, UR5, Kelvin tool changer (which powers the Robotiq 2F-85
// and Schmalz ECBPi adapters when it attaches them) and the pick-and-place composite, which
// finds the robot and the mounted tool by discovery. Change to the parallel gripper, pick
// and place box A; change to the vacuum gripper, pick and place box B; detach the tool. The
// test then checks the world model: both boxes at their targets, no tool mounted.
#include <gtest/gtest.h>

#include "client_thread.hpp"
#include "device_process.hpp"
#include "devices/common/frame.hpp"
#include "devices/world/world_link.hpp"

namespace skillcell::devices {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

constexpr const char* kRobotiqUri = "urn:skillcell:device:robotiq-2f85";
constexpr const char* kSchmalzUri = "urn:skillcell:device:schmalz-ecbpi";
constexpr const char* kParallelDock = "0.3,-0.45,0.35,3.141592653589793,0,0";
constexpr const char* kVacuumDock = "0.45,-0.3,0.35,3.141592653589793,0,0";

ua::Variant pose(const char* text) {
    return frameToVariant(toFrame(*parsePose6(text)));
}

ua::Variant text(const char* s) {
    return ua::Variant(ua::String(s));
}

void expectAt(WorldLink& w, const std::string& id, double x, double y, double z) {
    const auto p = w.objectPose(id);
    ASSERT_TRUE(p.ok()) << id;
    EXPECT_NEAR(p->p.x(), x, 1e-3) << id;
    EXPECT_NEAR(p->p.y(), y, 1e-3) << id;
    EXPECT_NEAR(p->p.z(), z, 1e-3) << id;
}

TEST(WorkCell, ChangesToolsAndPicksAndPlacesTwoBoxesFoundByDiscovery) {
    const std::string bin = SKILLCELL_BINARY;
    const std::vector<std::string> fast = {"--mdns-ttl", "5", "--mdns-query-period", "1"};
    auto with = [&](std::vector<std::string> args) {
        args.insert(args.end(), fast.begin(), fast.end());
        return args;
    };
    test::DeviceProcess world(
        bin,
        with({"world", "--object", "boxA:0.04,0.1,0.05@0.45,0.15,0.025", "--object",
              "boxB:0.04,0.04,0.04@0.45,-0.05,0.02", "--dock",
              std::string("dockP@") + kParallelDock, "--dock", std::string("dockV@") + kVacuumDock,
              "--tool", "parallel:dockP@0,0,0.15", "--tool", "vacuum:dockV@0,0,0.12"}),
        true);
    ASSERT_FALSE(world.url().empty());
    const auto toolsPki = world.pkiDir().string() + "-tools";
    const std::string common = " --port 0 --host 127.0.0.1 --insecure --speed 20 --world " +
                               world.url() + " --mdns-ttl 5 --mdns-query-period 1";
    test::DeviceProcess changer(
        bin,
        with({"toolchanger", "--world", world.url(), "--tool",
              std::string("parallel:1.0-1.5:") + kRobotiqUri, "--tool",
              std::string("vacuum:2.0-2.5:") + kSchmalzUri, "--power",
              "parallel=" + bin + " device robotiq --pki-dir " + toolsPki + "-robotiq" + common,
              "--power",
              "vacuum=" + bin + " device schmalz --pki-dir " + toolsPki + "-schmalz" + common,
              "--detection-timeout-ms", "20000"}),
        true);
    test::DeviceProcess pickplace(
        bin, with({"pickplace", "--world", world.url(), "--detection-timeout-ms", "5000"}), true);
    test::DeviceProcess robot(bin, with({"ur5", "--speed", "50", "--world", world.url()}), true);
    ASSERT_FALSE(changer.url().empty());
    ASSERT_FALSE(pickplace.url().empty());
    ASSERT_FALSE(robot.url().empty());

    auto link = WorldLink::connect(world.url());
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    test::ClientThread client, pickClient;  // one connection each
    auto change = client.attach(changer.url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    auto detach = client.attach(changer.url(), ua::NodeId(1, ua::String("Skills/DetachTool")));
    auto pick =
        pickClient.attach(pickplace.url(), ua::NodeId(1, ua::String("Skills/PickAndPlace")));
    ASSERT_TRUE(change && detach && pick);

    auto outcome = client.invoke(
        change, {{"ToolPosition", pose(kParallelDock)}, {"ToolAppUri", text(kRobotiqUri)}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    outcome = pickClient.invoke(
        pick, {{"ObjectId", text("boxA")}, {"PlacePosition", pose("0.25,0.35,0.025,0,0,0")}}, 120s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.graspedObject(), "");
    expectAt(w, "boxA", 0.25, 0.35, 0.025);

    outcome = client.invoke(
        change, {{"ToolPosition", pose(kVacuumDock)}, {"ToolAppUri", text(kSchmalzUri)}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    outcome = pickClient.invoke(
        pick, {{"ObjectId", text("boxB")}, {"PlacePosition", pose("0.25,-0.2,0.02,0,0,0")}}, 120s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    expectAt(w, "boxB", 0.25, -0.2, 0.02);

    outcome = client.invoke(detach, {{"ToolPosition", pose(kVacuumDock)}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;

    // The world: both boxes at their targets, no tool mounted, nothing held.
    expectAt(w, "boxA", 0.25, 0.35, 0.025);
    expectAt(w, "boxB", 0.25, -0.2, 0.02);
    EXPECT_EQ(*w.mountedTool(), "");
    EXPECT_EQ(*w.graspedObject(), "");

    // No tool: the composite fails cleanly, naming what is missing.
    outcome = pickClient.invoke(
        pick, {{"ObjectId", text("boxB")}, {"PlacePosition", pose("0.3,-0.2,0.02,0,0,0")}}, 120s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("GraspGripperSkillType"), std::string::npos) << outcome.reason;
    std::error_code ec;
    std::filesystem::remove_all(toolsPki + "-robotiq", ec);
    std::filesystem::remove_all(toolsPki + "-schmalz", ec);
}

}  // namespace
}  // namespace skillcell::devices
