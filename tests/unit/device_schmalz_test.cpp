// The Schmalz ECBPi: its IO-Link process data layout, the simulated vacuum generator
// (vacuum build-up, switching points with hysteresis, part-present bit), the simulated
// IO-Link master, and the adapter's Grasp and Release through a real server and
// SkillClient: a grasp with no part under the cup halts with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <thread>

#include "client_thread.hpp"
#include "devices/common/frame.hpp"
#include "devices/schmalz/ecbpi_component.hpp"
#include "devices/schmalz/io_link_master.hpp"
#include "lagging_world.hpp"
#include "running_server.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices::schmalz::device_schmalz_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

TEST(DeviceSchmalzProcessData, LayoutOfBothDirections) {
    EXPECT_EQ(encode(EcbpiCommand{true, false}), (ProcessDataOut{0x01, 0x00}));
    EXPECT_EQ(encode(EcbpiCommand{false, true}), (ProcessDataOut{0x02, 0x00}));
    EXPECT_EQ(decodeCommand({0x03, 0x00}), (EcbpiCommand{true, true}));

    EcbpiStatus s;
    s.partPresent = true;
    s.controlReached = true;
    s.vacuum = 0x02EE;  // 750 mbar, big-endian
    EXPECT_EQ(encode(s), (ProcessDataIn{0x03, 24, 0x02, 0xEE}));
    s.partPresent = false;
    s.controlReached = false;
    s.partDetached = true;
    s.device = DeviceStatus::Red;
    EXPECT_EQ(encode(s)[0], 0xE0);
    EXPECT_EQ(decodeStatus(encode(s)), s);
}

TEST(DeviceSchmalzSimulation, VacuumBuildsUpOnlyWithAPartAndSwitchesWithHysteresis) {
    std::optional<std::string> under;
    SimulatedEcbpi e([&] { return under; });
    // No part: the vacuum settles at the free-flow level, below SP2.
    e.write({true, false}, 0.0);
    EcbpiStatus s = e.status(1.0);
    EXPECT_NEAR(s.vacuum, 60, 1);
    EXPECT_FALSE(s.partPresent);
    EXPECT_FALSE(s.controlReached);
    e.write({false, true}, 1.0);
    EXPECT_LT(e.status(1.5).vacuum, 5);
    e.write({false, false}, 1.5);
    EXPECT_TRUE(e.takeEvents().empty());

    // A part seals the cup: SP2 within ~61 ms (400 of 750 mbar at tau 80 ms), then SP1.
    under = "plate";
    e.write({true, false}, 2.0);
    EXPECT_FALSE(e.status(2.05).partPresent);
    s = e.status(2.07);
    EXPECT_TRUE(s.partPresent);
    EXPECT_FALSE(s.controlReached);
    s = e.status(2.5);
    EXPECT_TRUE(s.controlReached);
    EXPECT_NEAR(s.vacuum, 750, 5);
    auto events = e.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, CupEvent::Kind::Grasped);
    EXPECT_EQ(events[0].partId, "plate");

    // Blow-off: SP1 off below 550, SP2 off below 300 (hysteresis), then SP3 (detached).
    e.write({false, true}, 3.0);
    s = e.status(3.0 + 0.03 * std::log(750.0 / 500));  // ~500 mbar
    EXPECT_FALSE(s.controlReached);
    EXPECT_TRUE(s.partPresent);
    s = e.status(3.5);
    EXPECT_FALSE(s.partPresent);
    EXPECT_TRUE(s.partDetached);
    events = e.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, CupEvent::Kind::Released);
    // The next suction clears SP3.
    under.reset();
    e.write({true, false}, 4.0);
    EXPECT_FALSE(e.status(4.0).partDetached);
}

// Started holding a part (its adapter restarted while the cup held it): sucking, part present,
// and the part goes with the next blow-off, as a grasped one does.
TEST(DeviceSchmalzSimulation, AGeneratorStartedHoldingAPartLetsGoOfItOnBlowOff) {
    SimulatedEcbpi e;
    e.startHolding("plate");
    EcbpiStatus s = e.status(0.5);
    EXPECT_TRUE(s.partPresent);
    EXPECT_TRUE(s.controlReached);
    EXPECT_NEAR(s.vacuum, 750, 5);
    EXPECT_TRUE(e.takeEvents().empty()) << "held already: no new grasp";
    e.write({false, true}, 1.0);
    EXPECT_FALSE(e.status(1.5).partPresent);
    const auto events = e.takeEvents();
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, CupEvent::Kind::Released);
    EXPECT_EQ(events[0].partId, "plate");
}

TEST(DeviceSchmalzMaster, PortsAndLengthsAreChecked) {
    SimulatedIoLinkOptions o;
    o.port = 2;
    SimulatedIoLinkMaster m(o);
    EXPECT_EQ(m.readProcessData(1).status(), ua::status::BadNotFound);
    const std::uint8_t three[3] = {1, 0, 0};
    EXPECT_EQ(m.writeProcessData(2, three), ua::status::BadInvalidArgument);
    const std::uint8_t on[2] = {1, 0};
    EXPECT_EQ(m.writeProcessData(2, on), ua::status::Good);
    EXPECT_TRUE(m.lastCommand().suction);
    const auto in = m.readProcessData(2);
    ASSERT_TRUE(in.ok());
    EXPECT_EQ(in->size(), kProcessDataInSize);
}

class VacuumCell {
public:
    VacuumCell() {
        SimulatedIoLinkOptions o;
        o.speed = 10;
        o.probe = [this]() -> std::optional<std::string> {
            std::lock_guard lock(mutex_);
            return under_;
        };
        o.onEvent = [this](const CupEvent& e) {
            {
                std::lock_guard lock(mutex_);
                events_.push_back(e);
            }
            world_.told();
        };
        o.worldBehind = [this] { return world_.behind(); };
        o.awaitWorld = [this] { return world_.await(5s); };
        master_ = std::make_unique<SimulatedIoLinkMaster>(o);
        server_ = std::make_unique<test::RunningServer>(
            test::RunningServer::defaultConfig(), [this](ua::Server& s) {
                EcbpiComponentOptions options;
                options.gripper.poll = 1ms;
                std::string error;
                auto c = startEcbpiComponent(s, *master_, options, &error);
                ASSERT_TRUE(c.ok()) << error;
                component_ = std::move(*c);
            });
    }
    ~VacuumCell() {
        server_->inServer([this](ua::Server&) {
            component_.reset();
            return 0;
        });
        server_.reset();
    }
    VacuumCell(const VacuumCell&) = delete;
    VacuumCell& operator=(const VacuumCell&) = delete;

    void put(std::optional<std::string> part) {
        std::lock_guard lock(mutex_);
        under_ = std::move(part);
    }
    /// The world model the generator tells its grasps and releases.
    test::LaggingWorld& world() { return world_; }
    std::vector<CupEvent> events() {
        std::lock_guard lock(mutex_);
        return events_;
    }
    std::string url() const { return server_->url(); }
    SimulatedIoLinkMaster& master() { return *master_; }
    std::vector<ua::String> namespaces() {
        return server_->inServer([](ua::Server& s) { return s.addressSpace().namespaces(); });
    }
    ua::Variant read(const ua::NodeId& id) {
        return server_->inServer([&](ua::Server& s) {
            const ua::Node* node = s.addressSpace().find(id);
            return node == nullptr ? ua::Variant() : *s.addressSpace().readValue(*node).value;
        });
    }

private:
    std::mutex mutex_;
    std::optional<std::string> under_;
    std::vector<CupEvent> events_;
    test::LaggingWorld world_;
    std::unique_ptr<SimulatedIoLinkMaster> master_;
    std::unique_ptr<GripperComponent> component_;
    std::unique_ptr<test::RunningServer> server_;
};

TEST(DeviceSchmalzSkills, ItsServerLoadsTheGripperModelsAndNotTheRobotOnes) {
    // Each start parses only the models its skills need: the gripper skills and what they
    // require, not Robotics, IA or the other skill models.
    VacuumCell cell;
    const auto namespaces = cell.namespaces();
    const auto has = [&](std::string_view uri) {
        return std::find(namespaces.begin(), namespaces.end(), uri) != namespaces.end();
    };
    EXPECT_TRUE(has(ua::companion::kGripperSkillsUri));
    EXPECT_TRUE(has(ua::companion::kSkillsUri));
    EXPECT_TRUE(has(ua::companion::kDiUri));
    EXPECT_FALSE(has(ua::companion::kRoboticsUri));
    EXPECT_FALSE(has(ua::companion::kIaUri));
    EXPECT_FALSE(has(ua::companion::kRoboticSkillsUri));
    EXPECT_FALSE(has(ua::companion::kToolChangerSkillsUri));
}

TEST(DeviceSchmalzSkills, GraspAndReleaseAndAGraspWithNoPartFails) {
    VacuumCell cell;
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/Grasp")));
    auto release = t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/Release")));
    ASSERT_TRUE(grasp && release);

    // Nothing under the cup.
    auto outcome = t.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("no part under the cup"), std::string::npos) << outcome.reason;
    EXPECT_FALSE(cell.master().lastCommand().suction);  // suction switched off again
    ASSERT_EQ(t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await grasp->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);

    cell.put("plate");
    outcome = t.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_TRUE(cell.master().lastCommand().suction);  // it keeps holding
    EXPECT_GT(cell.master().vacuum(), 400);

    outcome = t.invoke(release, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_FALSE(cell.master().lastCommand().suction);
    EXPECT_FALSE(cell.master().lastCommand().blowOff);
    EXPECT_LT(cell.master().vacuum(), 20);
    const auto events = cell.events();
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].kind, CupEvent::Kind::Grasped);
    EXPECT_EQ(events[1].kind, CupEvent::Kind::Released);

    // The grip point: VACUUM, 12 cm from the mounting plate; no MoveGripper skill.
    for (const auto& p : grasp->parameters()) {
        if (p.name == "GripPointType") {
            EXPECT_EQ(cell.read(p.nodeId), ua::Variant(std::int32_t{1}));
        }
        if (p.name == "GripPointOffset") {
            const auto offset = frameFromVariant(cell.read(p.nodeId));
            ASSERT_TRUE(offset.ok());
            EXPECT_NEAR(offset->p.z(), 0.12, 1e-12);
        }
    }
    EXPECT_FALSE(t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/MoveGripper"))));
}

// A grasp or release the world has not heard yet (it restarts): the switching points show
// what they showed before until it has, so the skill ends only then (issue 25).
TEST(DeviceSchmalzSkills, AGraspEndsOnlyOnceTheWorldHasHeardIt) {
    VacuumCell cell;
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/Grasp")));
    auto release = t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/Release")));
    ASSERT_TRUE(grasp && release);
    cell.put("plate");
    // 25 reads of 1 ms polls: well within the 1 s evacuation budget.
    test::expectEachEndsOnlyOnceHeard(t, grasp, release, cell.world(), 25);
    ASSERT_EQ(cell.events().size(), 2u);
}

// The world down for longer than the adapter's release budget (1 s) as the part lets go: a
// read of the in-process master waits for the world to come back, so the release ends then,
// instead of failing with a vacuum "that did not go" (issue 25's chaos suite found it).
TEST(DeviceSchmalzSkills, AReleaseWaitsForAWorldThatIsDownLongerThanItsBudget) {
    VacuumCell cell;
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/Grasp")));
    auto release = t.attach(cell.url(), ua::NodeId(1, ua::String("Skills/Release")));
    ASSERT_TRUE(grasp && release);
    cell.put("plate");
    auto outcome = t.invoke(grasp, {}, 20s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    cell.world().goDown();
    std::thread outage([&cell] {
        std::this_thread::sleep_for(1500ms);  // the outage itself: longer than the budget
        cell.world().comeBack();
    });
    outcome = t.invoke(release, {}, 20s);
    outage.join();
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(cell.events().size(), 2u);
}

}  // namespace
}  // namespace skillcell::devices::schmalz::device_schmalz_test
