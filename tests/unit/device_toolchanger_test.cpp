// The Kelvin tool changer: its tool table (identification bands), and the changer as a
// process in a cell (run in a private network namespace: discovery is on). The changer
// finds the robot's move skill by discovery, takes the parallel gripper from its dock, which
// powers the gripper's adapter process, and completes when that adapter is detected; then
// it changes to the vacuum gripper and detaches it. The test checks the world model.
#include <gtest/gtest.h>

#include <poll.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include "client_thread.hpp"
#include "devices/common/frame.hpp"
#include "devices/toolchanger/dock_map_file.hpp"
#include "devices/toolchanger/tool_table.hpp"
#include "devices/world/world_link.hpp"
#include "process_tree.hpp"
#include "simulated_cell.hpp"
#include "temp_dir.hpp"
#include "ua/client/blocking_client.hpp"

namespace skillcell::devices::device_toolchanger_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;
using toolchanger::DockMap;
using toolchanger::loadDockMap;
using toolchanger::PinReading;
using toolchanger::saveDockMap;
using toolchanger::ToolTable;

TEST(ToolTable, FindsToolsByTheirBandAndCallsTheGapsFaults) {
    ToolTable t;
    ASSERT_EQ(t.add("parallel:1.0-1.5:urn:skillcell:device:robotiq-2f85"), ua::status::Good);
    ASSERT_EQ(t.add("vacuum:2-2.5:urn:x"), ua::status::Good);
    EXPECT_EQ(t.identify(0.05).kind, PinReading::Kind::NoTool);
    const auto p = t.identify(1.2);
    ASSERT_EQ(p.kind, PinReading::Kind::Tool);
    EXPECT_EQ(p.tool->id, "parallel");
    EXPECT_EQ(p.tool->applicationUri, "urn:skillcell:device:robotiq-2f85");
    EXPECT_EQ(t.identify(2.5).tool->id, "vacuum");
    EXPECT_EQ(t.identify(1.7).kind, PinReading::Kind::Fault);  // between bands
    EXPECT_EQ(t.identify(9.0).kind, PinReading::Kind::Fault);  // above every band
    EXPECT_EQ(t.byApplicationUri("urn:x")->id, "vacuum");
    EXPECT_EQ(t.byApplicationUri("urn:y"), nullptr);
}

TEST(ToolTable, RefusesBadSpecsWithTheReason) {
    ToolTable t;
    ASSERT_EQ(t.add("a:1-2:urn:a"), ua::status::Good);
    std::string why;
    for (const char* bad :
         {"b", "b:1-2", "b:x-2:urn:b", "b:2-1:urn:b", "b:0.1-0.5:urn:b", ":3-4:urn:b", "b:3-4:"}) {
        EXPECT_EQ(t.add(bad, &why), ua::status::BadInvalidArgument) << bad;
        EXPECT_FALSE(why.empty()) << bad;
    }
    EXPECT_EQ(t.add("b:1.5-3:urn:b", &why), ua::status::BadInvalidArgument);
    EXPECT_NE(why.find("overlaps"), std::string::npos) << why;
    EXPECT_EQ(t.add("a:5-6:urn:c", &why), ua::status::BadInvalidArgument);
    EXPECT_EQ(t.add("c:5-6:urn:a", &why), ua::status::BadInvalidArgument);
    EXPECT_EQ(t.setPowerCommand("zzz=/bin/true", &why), ua::status::BadInvalidArgument);
    EXPECT_EQ(t.setPowerCommand("a=", &why), ua::status::BadInvalidArgument);
    ASSERT_EQ(t.setPowerCommand("a=/bin/sleep  10", &why), ua::status::Good);
    EXPECT_EQ(t.byId("a")->powerCommand, (std::vector<std::string>{"/bin/sleep", "10"}));
    EXPECT_EQ(t.entries().size(), 1U);
}

using test::parallelDock;
using test::robotiqUri;
using test::schmalzUri;
using test::vacuumDock;

ua::Variant pose(const std::string& text) {
    return test::poseValue(text);
}

TEST(DockMapFile, KeepsEachToolsDockAndSaysWhyAFileIsNoDockMap) {
    test::TempDir dir("dock-map");
    const auto file = dir.path() / "docks.json";
    auto none = loadDockMap(file);
    ASSERT_TRUE(none);
    EXPECT_TRUE(none->docks.empty());  // no file yet: nothing taken
    EXPECT_FALSE(none->locking);
    const KDL::Frame parallel = toFrame(*parsePose6(parallelDock()));
    const KDL::Frame vacuum = toFrame(*parsePose6(vacuumDock()));
    DockMap docks;
    docks.docks["parallel"] = parallel;
    docks.locking = vacuum;
    ASSERT_TRUE(saveDockMap(file, docks));
    auto back = loadDockMap(file);
    ASSERT_TRUE(back);
    ASSERT_EQ(back->docks.size(), 1u);
    EXPECT_TRUE(KDL::Equal(back->docks.at("parallel"), parallel, 1e-9));
    ASSERT_TRUE(back->locking);
    EXPECT_TRUE(KDL::Equal(*back->locking, vacuum, 1e-9));
    docks.docks["vacuum"] = vacuum;
    docks.locking.reset();
    ASSERT_TRUE(saveDockMap(file, docks));
    back = loadDockMap(file);
    ASSERT_TRUE(back);
    ASSERT_EQ(back->docks.size(), 2u);
    EXPECT_TRUE(KDL::Equal(back->docks.at("vacuum"), vacuum, 1e-9));
    EXPECT_FALSE(back->locking);
    EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));

    for (const char* text :
         {"not json", R"({"docks": []})", R"({"docks": {"p": [1, 2]}})",
          R"({"docks": {"p": [1, 2, 3, 4, 5, "x"]}})", R"({"docks": {}, "locking": [1, 2, 3]})"}) {
        std::ofstream(file) << text;
        auto bad = loadDockMap(file);
        ASSERT_FALSE(bad) << text;
        EXPECT_NE(bad.failure().message.find(file.string()), std::string::npos)
            << bad.failure().message;
    }
}

TEST(ToolChangerProcess, ChangesToolsFoundByTheirPinAndPowersTheirAdapters) {
    test::SimulatedCell cell(SKILLCELL_BINARY, {}, false);
    ASSERT_TRUE(cell.ready());
    const std::string& worldUrl = cell.world->url();
    const std::string& changerUrl = cell.changer->url();

    auto link = WorldLink::connect(worldUrl, {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    test::ClientThread client;
    auto change = client.attach(changerUrl, ua::NodeId(1, ua::String("Skills/ChangeTool")));
    auto attach = client.attach(changerUrl, ua::NodeId(1, ua::String("Skills/AttachTool")));
    auto detach = client.attach(changerUrl, ua::NodeId(1, ua::String("Skills/DetachTool")));
    ASSERT_TRUE(change && attach && detach);

    // To the parallel gripper: its adapter is powered and detected before the skill ends.
    auto outcome = client.invoke(
        change,
        {{"ToolPosition", pose(parallelDock())}, {"ToolAppUri", test::textValue(robotiqUri())}},
        60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "parallel");
    // Already mounted: nothing to do.
    outcome = client.invoke(
        change,
        {{"ToolPosition", pose(parallelDock())}, {"ToolAppUri", test::textValue(robotiqUri())}},
        60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;

    // To the vacuum gripper: the parallel one goes back to its dock first.
    outcome = client.invoke(
        change,
        {{"ToolPosition", pose(vacuumDock())}, {"ToolAppUri", test::textValue(schmalzUri())}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "vacuum");

    // Attaching while a tool is mounted fails with the reason, and changes nothing.
    outcome = client.invoke(attach, {{"ToolPosition", pose(parallelDock())}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("attached already"), std::string::npos) << outcome.reason;

    // Detaching at the parallel gripper's dock (occupied) fails: the coupling stays locked.
    outcome = client.invoke(detach, {{"ToolPosition", pose(parallelDock())}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("did not open"), std::string::npos) << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "vacuum");
    ASSERT_EQ(client.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await detach->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);

    outcome = client.invoke(detach, {{"ToolPosition", pose(vacuumDock())}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "");

    // Nothing at this position: the coupling does not lock.
    ASSERT_EQ(client.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await attach->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);
    outcome =
        client.invoke(attach, {{"ToolPosition", pose("0.4,0.1,0.3,3.141592653589793,0,0")}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("did not lock"), std::string::npos) << outcome.reason;
    // A tool the changer does not know is refused before anything moves.
    outcome = client.invoke(
        change,
        {{"ToolPosition", pose(vacuumDock())}, {"ToolAppUri", test::textValue("urn:nobody")}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("urn:nobody"), std::string::npos) << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "");
}

using test::childrenOf;

// The changer takes the parallel gripper from its dock, through its ChangeTool skill.
void mountParallelGripper(test::SimulatedCell& cell) {
    test::ClientThread client;
    auto change =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    ASSERT_TRUE(change);
    const auto outcome = client.invoke(
        change,
        {{"ToolPosition", pose(parallelDock())}, {"ToolAppUri", test::textValue(robotiqUri())}},
        60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
}

// A changer killed outright (no shutdown, so no powering off) must not leave its tools'
// adapters running: an adapter would go on answering for a tool that nobody powers, and a
// restarted changer would power a second one.
TEST(ToolChangerProcess, AToolsAdapterEndsWhenTheChangerIsKilled) {
    test::SimulatedCell cell(SKILLCELL_BINARY, {}, false);
    ASSERT_TRUE(cell.ready());
    ASSERT_NO_FATAL_FAILURE(mountParallelGripper(cell));

    const std::vector<pid_t> adapters = childrenOf(cell.changer->pid());
    ASSERT_FALSE(adapters.empty()) << "the changer powered no adapter process";
    std::vector<int> ends;  // pidfds: readable once their process has ended
    for (const pid_t adapter : adapters) {
        const int fd = static_cast<int>(::syscall(SYS_pidfd_open, adapter, 0));
        if (fd >= 0) ends.push_back(fd);
    }
    ASSERT_EQ(ends.size(), adapters.size()) << "an adapter ended before the changer was killed";

    cell.changer->kill(SIGKILL);
    for (const int fd : ends) {
        pollfd ended{fd, POLLIN, 0};
        EXPECT_EQ(::poll(&ended, 1, 10000), 1) << "an adapter outlived its changer by 10 s";
        ::close(fd);
    }
}

// A powered tool's adapter that crashes is started again by the changer, as a board's watchdog
// reboots it; powered off, it ends and is not started again.
TEST(ToolChangerProcess, AToolsAdapterThatCrashesWhilePoweredIsStartedAgain) {
    test::SimulatedCell cell(SKILLCELL_BINARY, {}, false);
    ASSERT_TRUE(cell.ready());
    ASSERT_NO_FATAL_FAILURE(mountParallelGripper(cell));
    const std::vector<pid_t> adapters = childrenOf(cell.changer->pid());
    ASSERT_EQ(adapters.size(), 1U) << "the changer powers one adapter";
    ASSERT_EQ(::kill(adapters[0], SIGKILL), 0);
    std::vector<pid_t> now;
    for (int i = 0; i < 500; ++i) {  // bounded: 5 s
        now = childrenOf(cell.changer->pid());
        if (now.size() == 1 && now[0] != adapters[0]) break;
        std::this_thread::sleep_for(10ms);
    }
    ASSERT_EQ(now.size(), 1U);
    EXPECT_NE(now[0], adapters[0]) << "the crashed adapter was not started again";
    const int restarted = static_cast<int>(::syscall(SYS_pidfd_open, now[0], 0));
    ASSERT_GE(restarted, 0);

    test::ClientThread client;
    auto detach =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/DetachTool")));
    ASSERT_TRUE(detach);
    const auto outcome = client.invoke(detach, {{"ToolPosition", pose(parallelDock())}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    pollfd ended{restarted, POLLIN, 0};
    EXPECT_EQ(::poll(&ended, 1, 10000), 1) << "the restarted adapter outlived its power";
    ::close(restarted);
    EXPECT_TRUE(childrenOf(cell.changer->pid()).empty());
}

// After a crash the changer's memory is gone, but the tool is still locked on: the restarted
// changer asks the identification pin which tool it is, publishes it and powers it again. It
// does not guess where the tool came from: a change asks for a DetachTool at its dock first.
TEST(ToolChangerProcess, ARestartedChangerReadsTheMountedToolFromItsPinAndItsDockFromItsDockMap) {
    test::SimulatedCell cell(SKILLCELL_BINARY, {}, false);
    ASSERT_TRUE(cell.ready());
    ASSERT_NO_FATAL_FAILURE(mountParallelGripper(cell));
    cell.changer->kill(SIGKILL);
    cell.restartChanger();
    ASSERT_FALSE(cell.changer->url().empty());

    // MountedTool from the pin, and the tool's adapter running again (bounded waits: the
    // changer reads the pin once it serves).
    ua::BlockingClient reader;
    ASSERT_EQ(reader.connect(cell.changer->url()), ua::status::Good);
    std::string mounted;
    std::vector<pid_t> adapters;
    for (int i = 0; i < 100 && (mounted.empty() || adapters.empty()); ++i) {
        auto value = reader.readValue(ua::NodeId(1, ua::String("ToolChanger/MountedTool")));
        if (value && value->get<ua::String>() != nullptr) mounted = *value->get<ua::String>();
        adapters = childrenOf(cell.changer->pid());
        if (mounted.empty() || adapters.empty()) std::this_thread::sleep_for(100ms);
    }
    EXPECT_EQ(mounted, "parallel");
    EXPECT_FALSE(adapters.empty()) << "the mounted tool's adapter was not powered again";

    test::ClientThread client;
    auto change =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    auto detach =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/DetachTool")));
    ASSERT_TRUE(change && detach);
    // The dock it took the parallel gripper from survived in its dock map: a change puts that
    // gripper back there and takes the vacuum one.
    auto outcome = client.invoke(
        change,
        {{"ToolPosition", pose(vacuumDock())}, {"ToolAppUri", test::textValue(schmalzUri())}}, 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    auto link = WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    EXPECT_EQ(*(*link)->mountedTool(), "vacuum");
    EXPECT_EQ(*(*link)->dockTool("dockP"), "parallel");

    // Killed after the coupling closed on the vacuum gripper and before it noted which tool
    // it took: its dock map says only that a lock was under way at the vacuum dock. The pin
    // names the tool; that dock is its own, and a change puts it back there.
    cell.changer->kill(SIGKILL);
    DockMap crashed;
    crashed.locking = toFrame(*parsePose6(vacuumDock()));
    ASSERT_TRUE(saveDockMap(cell.dockMapFile(), crashed));
    cell.restartChanger();
    ASSERT_FALSE(cell.changer->url().empty());
    {
        test::ClientThread restarted;
        auto changeBack =
            restarted.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
        ASSERT_TRUE(changeBack);
        outcome = restarted.invoke(
            changeBack,
            {{"ToolPosition", pose(parallelDock())}, {"ToolAppUri", test::textValue(robotiqUri())}},
            60s);
        ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    }
    EXPECT_EQ(*(*link)->mountedTool(), "parallel");
    EXPECT_EQ(*(*link)->dockTool("dockV"), "vacuum");

    // Without its dock map (a changer that never took the mounted tool): the change is refused
    // with the reason, and DetachTool at the dock is the way out.
    std::filesystem::remove(cell.dockMapFile());
    cell.changer->kill(SIGKILL);
    cell.restartChanger();
    ASSERT_FALSE(cell.changer->url().empty());
    test::ClientThread again;
    // Clients of this thread of their own: they must go before it does.
    auto changeAgain =
        again.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    auto detachAgain =
        again.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/DetachTool")));
    ASSERT_TRUE(changeAgain && detachAgain);
    outcome = again.invoke(
        changeAgain,
        {{"ToolPosition", pose(vacuumDock())}, {"ToolAppUri", test::textValue(schmalzUri())}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("its dock is unknown"), std::string::npos) << outcome.reason;
    outcome = again.invoke(detachAgain, {{"ToolPosition", pose(parallelDock())}}, 60s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
}

// The robot dies while the changer moves it to the dock, and is started again (where it
// stopped): the change goes on once discovery finds the robot again, from what the pin says.
TEST(ToolChangerProcess, AChangeWhoseRobotDiesGoesOnWhenTheRobotIsBack) {
    test::SimulatedCell cell(SKILLCELL_BINARY, {}, false);
    ASSERT_TRUE(cell.ready());
    auto link = WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    const KDL::Frame start = *w.flangePose();
    test::ClientThread client;
    auto change =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    ASSERT_TRUE(change);
    skills::SkillOutcome outcome;
    std::thread running([&] {
        outcome = client.invoke(
            change,
            {{"ToolPosition", pose(parallelDock())}, {"ToolAppUri", test::textValue(robotiqUri())}},
            60s);
    });
    // Killed once the robot has left where it stood (a bounded poll of the world model).
    bool moving = false;
    for (int i = 0; i < 1500 && !moving; ++i) {
        moving = !near(*w.flangePose(), start, 1e-3, 1e-3);
        if (!moving) std::this_thread::sleep_for(10ms);
    }
    if (moving) {
        cell.robot->kill(SIGKILL);
        cell.restartRobot();
    }
    running.join();
    ASSERT_TRUE(moving) << "the robot never moved: " << outcome.reason;
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(*w.mountedTool(), "parallel");
    EXPECT_EQ(*w.dockTool("dockP"), "");
}

}  // namespace
}  // namespace skillcell::devices::device_toolchanger_test
