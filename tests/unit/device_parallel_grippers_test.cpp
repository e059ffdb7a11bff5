// Two parallel-gripper models, one behaviour: the Robotiq 2F-85 (its register map, a go bit,
// input registers) and the DH-Robotics AG-95 (another register map, holding registers only,
// no stop command) run the same skill scenario through a real server and SkillClients, each
// on its simulated gripper behind a pty. Nothing above the adapter differs: this is what lets
// a cell swap one for the other without a change to any process (issue 6). Plus the AG-95's
// register protocol, spoken by a plain libmodbus master.
#include <gtest/gtest.h>
#include <modbus.h>

#include <cctype>
#include <cerrno>
#include <mutex>

#include "client_thread.hpp"
#include "devices/common/frame.hpp"
#include "devices/dh/ag95_component.hpp"
#include "devices/dh/simulated_ag95.hpp"
#include "devices/robotiq/robotiq_component.hpp"
#include "devices/robotiq/simulated_gripper_port.hpp"
#include "lagging_world.hpp"
#include "running_server.hpp"

namespace skillcell::devices::device_parallel_grippers_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

/// One model: its simulated gripper and its component, as a cell would start them.
struct Model {
    std::string name;
    /// Opens the simulated gripper; its device path.
    std::function<std::string(std::function<Probed()> probe,
                              std::function<void(const FingerEvent&)> onEvent,
                              std::function<bool()> worldBehind)>
        simulate;
    /// The fingers' gap now (m).
    std::function<double()> width;
    std::function<ua::Result<std::shared_ptr<void>>(ua::Server&, const std::string& device)>
        component;
    double gripOffsetZ;
    std::shared_ptr<void> simulated;  // keeps it running
};

Model robotiq2f85() {
    Model model;
    model.name = "Robotiq 2F-85";
    model.gripOffsetZ = 0.15;
    auto port = std::make_shared<std::unique_ptr<robotiq::SimulatedGripperPort>>();
    model.simulate = [port](auto probe, auto onEvent, auto worldBehind) {
        robotiq::SimulatedGripperOptions o;
        o.speed = 20;
        o.probe = std::move(probe);
        o.onEvent = std::move(onEvent);
        o.worldBehind = std::move(worldBehind);
        *port = robotiq::SimulatedGripperPort::open(o);
        return *port ? (*port)->devicePath() : std::string();
    };
    model.width = [port] {
        return robotiq::widthOf(static_cast<std::uint8_t>((*port)->fingerPosition()));
    };
    model.component = [](ua::Server& s,
                         const std::string& device) -> ua::Result<std::shared_ptr<void>> {
        robotiq::RobotiqComponentOptions o;
        o.device = device;
        o.gripper.poll = 1ms;
        auto c = robotiq::startRobotiqComponent(s, o);
        if (!c) return c.status();
        return std::shared_ptr<void>(std::move(*c));
    };
    model.simulated = port;
    return model;
}

Model dhAg95() {
    Model model;
    model.name = "DH-Robotics AG-95";
    model.gripOffsetZ = 0.16;
    auto gripper = std::make_shared<std::unique_ptr<dh::SimulatedAg95>>();
    model.simulate = [gripper](auto probe, auto onEvent, auto worldBehind) {
        dh::SimulatedAg95Options o;
        o.speed = 20;
        o.probe = std::move(probe);
        o.onEvent = std::move(onEvent);
        o.worldBehind = std::move(worldBehind);
        *gripper = dh::SimulatedAg95::open(o);
        return *gripper ? (*gripper)->devicePath() : std::string();
    };
    model.width = [gripper] { return (*gripper)->width(); };
    model.component = [](ua::Server& s,
                         const std::string& device) -> ua::Result<std::shared_ptr<void>> {
        dh::Ag95ComponentOptions o;
        o.device = device;
        o.gripper.poll = 1ms;
        auto c = dh::startAg95Component(s, o);
        if (!c) return c.status();
        return std::shared_ptr<void>(std::move(*c));
    };
    model.simulated = gripper;
    return model;
}

/// A gripper component on a real server, with its simulated gripper on a pty.
class GripperCell {
public:
    explicit GripperCell(Model model) : model_(std::move(model)) {
        const std::string device = model_.simulate(
            [this]() -> Probed {
                std::lock_guard lock(mutex_);
                ++probes_;
                if (unknownFor_ > 0) {
                    --unknownFor_;
                    return Probed::unknown();
                }
                return between_;
            },
            [this](const FingerEvent& e) {
                {
                    std::lock_guard lock(mutex_);
                    events_.push_back(e);
                }
                world_.told();
            },
            [this] { return world_.behind(); });
        EXPECT_FALSE(device.empty());
        server_ = std::make_unique<test::RunningServer>(
            test::RunningServer::defaultConfig(), [this, device](ua::Server& s) {
                auto c = model_.component(s, device);  // the device path is all it knows
                ASSERT_TRUE(c.ok()) << ua::statusName(c.status());
                component_ = std::move(*c);
            });
    }
    ~GripperCell() {
        server_->inServer([this](ua::Server&) {
            component_.reset();
            return 0;
        });
        server_.reset();
    }
    GripperCell(const GripperCell&) = delete;
    GripperCell& operator=(const GripperCell&) = delete;

    void put(std::optional<ObjectBetweenFingers> object) {
        std::lock_guard lock(mutex_);
        between_ = std::move(object);
    }
    /// The world cannot say what lies between the fingers for the next `probes` probes.
    void cannotSay(int probes) {
        std::lock_guard lock(mutex_);
        unknownFor_ = probes;
    }
    int probes() {
        std::lock_guard lock(mutex_);
        return probes_;
    }
    /// The world model the gripper tells its grasps and releases.
    test::LaggingWorld& world() { return world_; }
    std::vector<FingerEvent> events() {
        std::lock_guard lock(mutex_);
        return events_;
    }
    [[nodiscard]] double width() const { return model_.width(); }
    [[nodiscard]] std::string url() const { return server_->url(); }
    ua::Variant read(const ua::NodeId& id) {
        return server_->inServer([&](ua::Server& s) {
            const ua::Node* node = s.addressSpace().find(id);
            return node == nullptr ? ua::Variant() : *s.addressSpace().readValue(*node).value;
        });
    }

private:
    Model model_;
    std::mutex mutex_;
    std::optional<ObjectBetweenFingers> between_;
    std::vector<FingerEvent> events_;
    test::LaggingWorld world_;
    int unknownFor_ = 0;
    int probes_ = 0;
    std::shared_ptr<void> component_;
    std::unique_ptr<test::RunningServer> server_;
};

ua::NodeId skill(const std::string& name) {
    return ua::NodeId(1, ua::String("Skills/" + name));
}

class ParallelGripperModels : public testing::TestWithParam<Model (*)()> {};

}  // namespace

TEST_P(ParallelGripperModels, TheSameSkillsBehaveTheSame) {
    const Model model = GetParam()();
    SCOPED_TRACE(model.name);
    GripperCell cell(model);
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), skill("Grasp"));
    auto release = t.attach(cell.url(), skill("Release"));
    auto move = t.attach(cell.url(), skill("MoveGripper"));
    ASSERT_TRUE(grasp && release && move);

    // Nothing between the fingers: the grasp fails with the reason (the skill halts).
    auto outcome = t.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("no object between the fingers"), std::string::npos)
        << outcome.reason;
    ASSERT_EQ(t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await grasp->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);

    outcome = t.invoke(release, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;

    // A 30 mm part: the grasp holds it, the fingers rest at its width.
    cell.put(ObjectBetweenFingers{"part", 0.030});
    outcome = t.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_NEAR(cell.width(), 0.030, 0.0005);
    outcome = t.invoke(release, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    const auto events = cell.events();
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].kind, FingerEvent::Kind::Grasped);
    EXPECT_EQ(events[0].objectId, "part");
    EXPECT_EQ(events[1].kind, FingerEvent::Kind::Released);

    // MoveGripper to 50 mm: free; to 10 mm with the part in the way: stopped by it.
    outcome = t.invoke(move, {{"Width", ua::Variant(0.050)}, {"Force", ua::Variant(50.0)}}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_NEAR(cell.width(), 0.050, 0.0005);
    outcome = t.invoke(move, {{"Width", ua::Variant(0.010)}, {"Force", ua::Variant(50.0)}}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("stopped the fingers at 30"), std::string::npos)
        << outcome.reason;
    outcome = t.invoke(move, {{"Width", ua::Variant(0.5)}}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Refused);  // beyond the skill model's EURange

    // The grip point: PARALLEL, at the model's offset.
    ua::NodeId typeNode;
    ua::NodeId offsetNode;
    for (const auto& p : grasp->parameters()) {
        if (p.name == "GripPointType") typeNode = p.nodeId;
        if (p.name == "GripPointOffset") offsetNode = p.nodeId;
    }
    EXPECT_EQ(cell.read(typeNode), ua::Variant(std::int32_t{0}));
    const auto offset = frameFromVariant(cell.read(offsetNode));
    ASSERT_TRUE(offset.ok());
    EXPECT_TRUE(near(*offset, KDL::Frame(KDL::Vector(0, 0, model.gripOffsetZ)), 1e-12, 1e-12));
}

// A grasp or release the world has not heard yet (it restarts) is still under way, for
// all the adapter can tell: the skill ends only once the world has caught up, so nothing
// above it moves a part the simulation does not know is held (issue 25).
TEST_P(ParallelGripperModels, AGraspEndsOnlyOnceTheWorldHasHeardIt) {
    const Model model = GetParam()();
    SCOPED_TRACE(model.name);
    GripperCell cell(model);
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), skill("Grasp"));
    auto release = t.attach(cell.url(), skill("Release"));
    ASSERT_TRUE(grasp && release);

    cell.put(ObjectBetweenFingers{"part", 0.030});
    test::expectEachEndsOnlyOnceHeard(t, grasp, release, cell.world(), 25);
    ASSERT_EQ(cell.events().size(), 2u);
}

// The world cannot say what lies between the fingers as they start to close (it restarts):
// they wait, and close on the part once it can, instead of closing on nothing.
TEST_P(ParallelGripperModels, FingersWaitForAWorldThatCannotSayWhatIsBetweenThem) {
    const Model model = GetParam()();
    SCOPED_TRACE(model.name);
    GripperCell cell(model);
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), skill("Grasp"));
    ASSERT_TRUE(grasp);
    cell.put(ObjectBetweenFingers{"part", 0.030});
    constexpr int kUnknown = 10;
    cell.cannotSay(kUnknown);
    const auto outcome = t.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_NEAR(cell.width(), 0.030, 0.0005);
    EXPECT_EQ(cell.probes(), kUnknown + 1);
    const auto events = cell.events();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FingerEvent::Kind::Grasped);
    EXPECT_EQ(events[0].objectId, "part");
}

// Named after the model, not the address of its function, so that a test's name (and CTest's)
// is the same in every build.
INSTANTIATE_TEST_SUITE_P(Models, ParallelGripperModels, testing::Values(&robotiq2f85, &dhAg95),
                         [](const testing::TestParamInfo<Model (*)()>& param) {
                             std::string name;
                             for (const char c : param.param().name) {
                                 if (std::isalnum(static_cast<unsigned char>(c)) != 0) name += c;
                             }
                             return name;
                         });

namespace {

/// A plain libmodbus RTU master on the simulated AG-95's pty.
class Master {
public:
    explicit Master(const std::string& device)
        : ctx_(modbus_new_rtu(device.c_str(), dh::kBaudRate, 'N', 8, 1)) {
        modbus_set_slave(ctx_, dh::kSlaveId);
        EXPECT_EQ(modbus_connect(ctx_), 0) << modbus_strerror(errno);
        modbus_set_response_timeout(ctx_, 0, 200'000);
    }
    ~Master() {
        modbus_close(ctx_);
        modbus_free(ctx_);
    }
    Master(const Master&) = delete;
    Master& operator=(const Master&) = delete;
    modbus_t* get() { return ctx_; }

private:
    modbus_t* ctx_;
};

}  // namespace

TEST(DeviceAg95Protocol, RegistersAsDhDocumentsThem) {
    // Simulated time under the test's control.
    auto now =
        std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
    dh::SimulatedAg95Options o;
    o.clock = [now] { return *now; };
    auto gripper = dh::SimulatedAg95::open(o);
    ASSERT_TRUE(gripper);
    Master m(gripper->devicePath());
    std::uint16_t state[3] = {};
    auto readState = [&] {
        return modbus_read_registers(m.get(), dh::kInitialisationState, 3, state) == 3;
    };

    // Not initialised: a position write is ignored.
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[0], 0);
    ASSERT_EQ(modbus_write_register(m.get(), dh::kPosition, 500), 1);
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[1], static_cast<std::uint16_t>(dh::GripperState::AtPosition));
    EXPECT_EQ(state[2], 0);

    // Initialisation: 2 while it runs, then 1 with the fingers fully open.
    ASSERT_EQ(modbus_write_register(m.get(), dh::kInitialise, 1), 1);
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[0], 2);
    *now += std::chrono::milliseconds(1600);
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[0], 1);
    EXPECT_EQ(state[2], 1000);

    // A motion at 50 % speed: moving, then at the position.
    ASSERT_EQ(modbus_write_register(m.get(), dh::kSpeed, 50), 1);
    ASSERT_EQ(modbus_write_register(m.get(), dh::kPosition, 500), 1);
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[1], static_cast<std::uint16_t>(dh::GripperState::Moving));
    *now += std::chrono::milliseconds(100);  // 7.5 mm of 47.5 mm
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[1], static_cast<std::uint16_t>(dh::GripperState::Moving));
    EXPECT_NEAR(state[2], 1000 - 79, 2);
    *now += std::chrono::seconds(1);
    ASSERT_TRUE(readState());
    EXPECT_EQ(state[1], static_cast<std::uint16_t>(dh::GripperState::AtPosition));
    EXPECT_EQ(state[2], 500);

    // The control registers read back as written.
    std::uint16_t speed = 0;
    ASSERT_EQ(modbus_read_registers(m.get(), dh::kSpeed, 1, &speed), 1);
    EXPECT_EQ(speed, 50);

    // Outside the map: the Modbus exception "illegal data address"; input registers: none.
    EXPECT_EQ(modbus_read_registers(m.get(), 0x0300, 1, state), -1);
    EXPECT_EQ(errno, EMBXILADD);
    EXPECT_EQ(modbus_read_input_registers(m.get(), dh::kInitialisationState, 1, state), -1);
    EXPECT_EQ(errno, EMBXILADD);
    // Another slave id gets no answer; the line stays usable.
    modbus_set_slave(m.get(), 7);
    EXPECT_EQ(modbus_read_registers(m.get(), dh::kInitialisationState, 3, state), -1);
    EXPECT_EQ(errno, ETIMEDOUT);
    modbus_set_slave(m.get(), dh::kSlaveId);
    EXPECT_TRUE(readState());
}

}  // namespace skillcell::devices::device_parallel_grippers_test
