// The Robotiq 2F-85: its register map (bytes as the manual gives them), the simulated
// gripper's behaviour behind the registers, the Modbus RTU protocol over a pseudo-terminal
// (a plain libmodbus master against the simulated slave), and the adapter's skills Grasp,
// Release and MoveGripper through a real server and SkillClient.
#include <gtest/gtest.h>
#include <modbus.h>

#include <asio/co_spawn.hpp>
#include <asio/use_future.hpp>
#include <atomic>
#include <cerrno>
#include <mutex>

#include "client_thread.hpp"
#include "devices/common/frame.hpp"
#include "devices/robotiq/robotiq_component.hpp"
#include "devices/robotiq/simulated_gripper_port.hpp"
#include "running_server.hpp"

namespace skillcell::devices::robotiq::device_robotiq_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

TEST(DeviceRobotiqRegisters, CommandsAndStatusHaveTheManualsLayout) {
    // The manual's "close with full speed and force": 09 00 00 FF FF FF.
    Command c;
    c.activate = true;
    c.go = true;
    c.position = 0xFF;
    c.speed = 0xFF;
    c.force = 0xFF;
    EXPECT_EQ(encode(c), (Registers{0x0900, 0x00FF, 0xFFFF}));
    EXPECT_EQ(decodeCommand(encode(c)), c);
    Command all = c;
    all.autoRelease = true;
    all.autoReleaseOpen = true;
    all.position = 0x12;
    all.speed = 0x34;
    all.force = 0x56;
    EXPECT_EQ(encode(all), (Registers{0x3900, 0x0012, 0x3456}));
    EXPECT_EQ(decodeCommand(encode(all)), all);

    // Status 0xF9: activated, going, activation complete, at the requested position;
    // 0xB9: an object detected while closing.
    Status s;
    s.activated = true;
    s.going = true;
    s.activation = ActivationStatus::Active;
    s.object = ObjectStatus::AtRequestedPosition;
    s.requestEcho = 0xFF;
    s.position = 0xE3;
    s.current = 0x0A;
    EXPECT_EQ(encode(s), (Registers{0xF900, 0x00FF, 0xE30A}));
    s.object = ObjectStatus::ContactClosing;
    EXPECT_EQ(encode(s)[0], 0xB900);
    s.fault = Fault::ActivationBitNotSet;
    EXPECT_EQ(encode(s)[1], 0x07FF);
    EXPECT_EQ(decodeStatus(encode(s)), s);
    EXPECT_EQ(decodeStatus({0x1000, 0, 0}).activation, ActivationStatus::Activating);

    // Positions over the 85 mm stroke: 0 open, 255 closed.
    EXPECT_DOUBLE_EQ(widthOf(0), 0.085);
    EXPECT_DOUBLE_EQ(widthOf(255), 0.0);
    EXPECT_EQ(positionFor(0.085), 0);
    EXPECT_EQ(positionFor(0.0), 255);
    EXPECT_EQ(positionFor(1.0), 0);  // clamped
    EXPECT_EQ(speedFor(kMaxSpeed), 255);
    EXPECT_EQ(forceFor(kMinForce), 0);
}

TEST(DeviceRobotiqSimulation, ActivationMotionAndObjectDetection) {
    std::optional<ObjectBetweenFingers> between;
    Simulated2F85 g([&] { return between; });
    Command c;
    c.go = true;
    c.position = 255;
    g.write(c, 0.0);  // rGTO without rACT
    EXPECT_EQ(g.status(0.0).fault, Fault::ActivationBitNotSet);

    c = Command{};
    c.activate = true;
    g.write(c, 1.0);
    EXPECT_EQ(g.status(1.5).activation, ActivationStatus::Activating);
    EXPECT_EQ(g.status(2.0).activation, ActivationStatus::Active);
    EXPECT_EQ(g.status(2.0).position, 0);

    // Close on nothing at full speed (150 mm/s over 85 mm: 0.567 s).
    c.go = true;
    c.position = 255;
    c.speed = 255;
    g.write(c, 3.0);
    EXPECT_EQ(g.status(3.2).object, ObjectStatus::Moving);
    EXPECT_GT(g.status(3.2).position, 0);
    EXPECT_LT(g.status(3.2).position, 255);
    const Status closed = g.status(3.0 + 0.085 / 0.150 + 1e-6);
    EXPECT_EQ(closed.object, ObjectStatus::AtRequestedPosition);
    EXPECT_EQ(closed.position, 255);
    EXPECT_TRUE(g.takeEvents().empty());

    // Open, then close on a 40 mm box: the fingers stop at its width.
    c.position = 0;
    g.write(c, 4.0);
    EXPECT_EQ(g.status(5.0).position, 0);
    between = ObjectBetweenFingers{"box1", 0.040};
    c.position = 255;
    g.write(c, 6.0);
    const Status holding = g.status(7.0);
    EXPECT_EQ(holding.object, ObjectStatus::ContactClosing);
    EXPECT_NEAR(widthOf(holding.position), 0.040, 0.0005);
    EXPECT_GT(holding.current, 0);
    auto events = g.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FingerEvent::Kind::Grasped);
    EXPECT_EQ(events[0].objectId, "box1");

    // Opening lets go.
    c.position = 0;
    g.write(c, 8.0);
    events = g.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, FingerEvent::Kind::Released);

    // An object wider than the stroke does not fit between the fingers.
    between = ObjectBetweenFingers{"crate", 0.200};
    c.position = 255;
    g.write(c, 9.0);
    EXPECT_EQ(g.status(10.0).object, ObjectStatus::AtRequestedPosition);

    // rGTO = 0 stops the fingers where they are.
    c.position = 0;
    g.write(c, 11.0);
    c.go = false;
    g.write(c, 11.2);
    const auto stoppedAt = g.status(11.2).position;
    EXPECT_EQ(g.status(12.0).position, stoppedAt);
    EXPECT_GT(stoppedAt, 0);
}

/// A plain libmodbus RTU master on the simulated gripper's pty.
class Master {
public:
    explicit Master(const std::string& path, int slave = kSlaveId)
        : ctx_(modbus_new_rtu(path.c_str(), kBaudRate, 'N', 8, 1)) {
        EXPECT_NE(ctx_, nullptr);
        EXPECT_EQ(modbus_set_slave(ctx_, slave), 0);
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

// Started holding an object (its adapter restarted while the fingers held it): activated,
// closed on it, so an adapter does not activate it again (which would open the fingers);
// opening lets go of it.
TEST(DeviceRobotiqSimulation, AGripperStartedHoldingAnObjectLetsGoOfItWhenItOpens) {
    Simulated2F85 g;
    g.startHolding({"box", 0.04});
    Status s = g.status(0.0);
    EXPECT_TRUE(s.activated);
    EXPECT_EQ(s.activation, ActivationStatus::Active);
    EXPECT_EQ(s.object, ObjectStatus::ContactClosing);
    EXPECT_NEAR(s.position, 255.0 * (1 - 0.04 / kStroke), 1);
    EXPECT_TRUE(g.takeEvents().empty()) << "held already: no new grasp";
    Command open = g.command();
    open.position = 0;
    g.write(open, 1.0);
    const auto events = g.takeEvents();
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, FingerEvent::Kind::Released);
    EXPECT_EQ(events[0].objectId, "box");
    EXPECT_EQ(g.status(3.0).position, 0);
}

TEST(DeviceRobotiqProtocol, TheSimulatedGripperAnswersModbusRtuOnAPty) {
    SimulatedGripperOptions o;
    o.speed = 50;
    auto port = SimulatedGripperPort::open(o);
    ASSERT_TRUE(port);
    EXPECT_EQ(port->devicePath().rfind("/dev/pts/", 0), 0u) << port->devicePath();
    Master m(port->devicePath());

    std::uint16_t status[3] = {};
    ASSERT_EQ(modbus_read_input_registers(m.get(), kStatusAddress, 3, status), 3);
    EXPECT_EQ(status[0], 0x0000);  // reset, not activated

    const Registers activate = encode(Command{.activate = true});
    ASSERT_EQ(modbus_write_registers(m.get(), kCommandAddress, 3, activate.data()), 3);
    ASSERT_EQ(modbus_read_input_registers(m.get(), kStatusAddress, 3, status), 3);
    EXPECT_EQ(decodeStatus({status[0], status[1], status[2]}).activation,
              ActivationStatus::Activating);
    // The holding registers read back what was written (function 3).
    std::uint16_t command[3] = {};
    ASSERT_EQ(modbus_read_registers(m.get(), kCommandAddress, 3, command), 3);
    EXPECT_EQ(command[0], 0x0100);

    // Addresses outside the map answer the Modbus exception "illegal data address".
    EXPECT_EQ(modbus_read_input_registers(m.get(), 0x0100, 3, status), -1);
    EXPECT_EQ(errno, EMBXILADD);
    EXPECT_EQ(modbus_read_input_registers(m.get(), kStatusAddress, 4, status), -1);
    EXPECT_EQ(errno, EMBXILADD);

    // Another slave id gets no answer at all (the line stays usable).
    {
        modbus_set_slave(m.get(), 3);
        EXPECT_EQ(modbus_read_input_registers(m.get(), kStatusAddress, 3, status), -1);
        EXPECT_EQ(errno, ETIMEDOUT);
        modbus_set_slave(m.get(), kSlaveId);
    }
    ASSERT_EQ(modbus_read_input_registers(m.get(), kStatusAddress, 3, status), 3)
        << modbus_strerror(errno);
    EXPECT_GE(port->requests(), 5u);
}

/// A gripper component on a real server, with its simulated gripper on a pty.
class GripperCell {
public:
    explicit GripperCell(std::function<std::chrono::steady_clock::time_point()> clock = {}) {
        SimulatedGripperOptions o;
        o.speed = clock ? 1.0 : 20.0;
        o.clock = std::move(clock);
        o.probe = [this]() -> std::optional<ObjectBetweenFingers> {
            std::lock_guard lock(mutex_);
            return between_;
        };
        o.onEvent = [this](const FingerEvent& e) {
            std::lock_guard lock(mutex_);
            events_.push_back(e);
        };
        port_ = SimulatedGripperPort::open(o);
        EXPECT_TRUE(port_);
        server_ = std::make_unique<test::RunningServer>(
            test::RunningServer::defaultConfig(), [this](ua::Server& s) {
                RobotiqComponentOptions options;
                options.device = port_->devicePath();  // all the adapter knows
                options.gripper.poll = 1ms;
                std::string error;
                auto c = startRobotiqComponent(s, options, &error);
                ASSERT_TRUE(c.ok()) << error;
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
    std::vector<FingerEvent> events() {
        std::lock_guard lock(mutex_);
        return events_;
    }
    std::string url() const { return server_->url(); }
    SimulatedGripperPort& port() { return *port_; }
    ua::Variant read(const ua::NodeId& id) {
        return server_->inServer([&](ua::Server& s) {
            const ua::Node* node = s.addressSpace().find(id);
            return node == nullptr ? ua::Variant() : *s.addressSpace().readValue(*node).value;
        });
    }
    static ua::NodeId skill(const std::string& name) {
        return ua::NodeId(1, ua::String("Skills/" + name));
    }

private:
    std::mutex mutex_;
    std::optional<ObjectBetweenFingers> between_;
    std::vector<FingerEvent> events_;
    std::unique_ptr<SimulatedGripperPort> port_;
    std::unique_ptr<GripperComponent> component_;
    std::unique_ptr<test::RunningServer> server_;
};

TEST(DeviceRobotiqSkills, GraspReleaseAndMoveThroughTheRegisterProtocol) {
    GripperCell cell;
    test::ClientThread t;
    auto grasp = t.attach(cell.url(), GripperCell::skill("Grasp"));
    auto release = t.attach(cell.url(), GripperCell::skill("Release"));
    auto move = t.attach(cell.url(), GripperCell::skill("MoveGripper"));
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
    EXPECT_DOUBLE_EQ(cell.port().fingerPosition(), 0);

    // A 30 mm part: the grasp holds it, the fingers rest at its width.
    cell.put(ObjectBetweenFingers{"part", 0.030});
    outcome = t.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_NEAR(widthOf(static_cast<std::uint8_t>(cell.port().fingerPosition())), 0.030, 0.0005);
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
    EXPECT_EQ(static_cast<int>(cell.port().fingerPosition()), positionFor(0.050));
    outcome = t.invoke(move, {{"Width", ua::Variant(0.010)}, {"Force", ua::Variant(50.0)}}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("stopped the fingers at 30"), std::string::npos)
        << outcome.reason;
    // A width beyond the EURange is refused at the write.
    outcome = t.invoke(move, {{"Width", ua::Variant(0.5)}}, 20s);
    EXPECT_EQ(outcome.kind, Kind::Refused);

    // The grip point: PARALLEL, 15 cm from the mounting plate.
    const auto& params = grasp->parameters();
    ua::NodeId typeNode, offsetNode;
    for (const auto& p : params) {
        if (p.name == "GripPointType") typeNode = p.nodeId;
        if (p.name == "GripPointOffset") offsetNode = p.nodeId;
    }
    EXPECT_EQ(cell.read(typeNode), ua::Variant(std::int32_t{0}));
    const auto offset = frameFromVariant(cell.read(offsetNode));
    ASSERT_TRUE(offset.ok());
    EXPECT_TRUE(near(*offset, KDL::Frame(KDL::Vector(0, 0, 0.15)), 1e-12, 1e-12));
}

TEST(DeviceRobotiqSkills, HaltStopsTheFingersMidway) {
    // Simulated time moves only when the test says so.
    std::atomic<std::int64_t> ms{0};
    GripperCell cell([&] {
        return std::chrono::steady_clock::time_point(std::chrono::milliseconds(ms.load()));
    });
    test::ClientThread t;
    auto release = t.attach(cell.url(), GripperCell::skill("Release"));
    auto move = t.attach(cell.url(), GripperCell::skill("MoveGripper"));
    ASSERT_TRUE(release && move);
    // Step time in 100 ms slices until the first release (activation included) is done;
    // each slice waits for the adapter's next poll to see it.
    auto released = asio::co_spawn(
        t.io(),
        [&]() -> asio::awaitable<skills::SkillOutcome> {
            std::map<std::string, ua::Variant> none;  // named: GCC 12 and co_await temporaries
            co_return co_await release->run(std::move(none), 20s);
        },
        asio::use_future);
    for (int i = 0; i < 100 && released.wait_for(0s) != std::future_status::ready; ++i) {
        const auto n = cell.port().requests();
        ms += 100;
        // No further poll comes once the release has ended: then the future is ready.
        (void)cell.port().waitForRequests(n + 1, 500ms);
    }
    ASSERT_EQ(released.wait_for(5s), std::future_status::ready);
    ASSERT_EQ(released.get().kind, Kind::Finished);

    const auto started = t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_await move->setParameter("Width", ua::Variant(0.0));
        co_return co_await move->start();
    });
    ASSERT_EQ(started, ua::status::Good);
    ASSERT_TRUE(
        cell.port().waitForCommand([](const Command& c) { return c.go && c.position == 255; }, 5s));
    // 100 ms at 100 mm/s: the fingers close by 10 mm, then the skill is halted.
    auto n = cell.port().requests();
    ms += 100;
    ASSERT_TRUE(cell.port().waitForRequests(n + 1, 5s));
    ASSERT_EQ(t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await move->call(skills::SkillMethod::Halt);
    }),
              ua::status::Good);
    // rGTO = 0: stop.
    EXPECT_TRUE(cell.port().waitForCommand([](const Command& c) { return !c.go; }, 5s));
    const double position = cell.port().fingerPosition();
    EXPECT_NEAR(widthOf(0) - widthOf(static_cast<std::uint8_t>(position)), 0.010, 0.001);
    ms += 10'000;  // however long it waits now, the fingers stay
    EXPECT_DOUBLE_EQ(cell.port().fingerPosition(), position);
}

TEST(DeviceRobotiqSkills, SuspendHoldsTheFingersAndResumeFinishesTheMove) {
    std::atomic<std::int64_t> ms{0};
    GripperCell cell([&] {
        return std::chrono::steady_clock::time_point(std::chrono::milliseconds(ms.load()));
    });
    test::ClientThread t;
    auto move = t.attach(cell.url(), GripperCell::skill("MoveGripper"));
    ASSERT_TRUE(move);
    auto call = [&](skills::SkillMethod m) {
        return t.run(
            [&]() -> asio::awaitable<ua::StatusCode> { co_return co_await move->call(m); });
    };
    // Close to 45 mm: activation first (1 s), then 40 mm at 100 mm/s.
    auto moved = asio::co_spawn(
        t.io(),
        [&]() -> asio::awaitable<skills::SkillOutcome> {
            // A named map: GCC 12 destroys braced temporaries in co_await twice.
            std::map<std::string, ua::Variant> parameters;
            parameters.emplace("Width", ua::Variant(0.045));
            co_return co_await move->run(std::move(parameters), 20s);
        },
        asio::use_future);
    ASSERT_TRUE(cell.port().waitForCommand([](const Command& c) { return c.activate; }, 5s));
    ms += 1100;  // the activation completes
    ASSERT_TRUE(cell.port().waitForCommand(
        [](const Command& c) { return c.go && c.position == positionFor(0.045); }, 5s));
    ms += 200;  // 20 mm of the way
    ASSERT_TRUE(cell.port().waitForRequests(cell.port().requests() + 1, 5s));
    ASSERT_EQ(call(skills::SkillMethod::Suspend), ua::status::Good);
    EXPECT_TRUE(cell.port().waitForCommand([](const Command& c) { return !c.go; }, 5s));
    const double held = cell.port().fingerPosition();
    ms += 5000;  // suspended: the fingers stay
    EXPECT_DOUBLE_EQ(cell.port().fingerPosition(), held);
    EXPECT_GT(held, 0);
    EXPECT_LT(held, positionFor(0.045));

    ASSERT_EQ(call(skills::SkillMethod::Resume), ua::status::Good);
    EXPECT_TRUE(cell.port().waitForCommand([](const Command& c) { return c.go; }, 5s));
    const auto n = cell.port().requests();
    ms += 1000;  // enough for the rest of the way
    (void)cell.port().waitForRequests(n + 1, 5s);
    ASSERT_EQ(moved.wait_for(10s), std::future_status::ready);
    const auto outcome = moved.get();
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_EQ(static_cast<int>(cell.port().fingerPosition()), positionFor(0.045));
}

}  // namespace
}  // namespace skillcell::devices::robotiq::device_robotiq_test
