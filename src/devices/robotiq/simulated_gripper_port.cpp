#include "devices/robotiq/simulated_gripper_port.hpp"

#include <algorithm>

namespace skillcell::devices::robotiq {

SimulatedGripperPort::SimulatedGripperPort(Token, SimulatedGripperOptions options)
    : options_(std::move(options)), gripper_(options_.probe) {
    epoch_ = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
    if (options_.holding) gripper_.startHolding(*options_.holding);
}

std::unique_ptr<SimulatedGripperPort> SimulatedGripperPort::open(SimulatedGripperOptions options,
                                                                 std::string* why) {
    auto gripper = std::make_unique<SimulatedGripperPort>(Token{}, std::move(options));
    ModbusRegisterMap map;
    map.slaveId = kSlaveId;
    map.baudRate = kBaudRate;
    map.holdingStart = kCommandAddress;
    map.holdingCount = kRegisterCount;
    map.inputStart = kStatusAddress;
    map.inputCount = kRegisterCount;
    gripper->port_ = PtyModbusSlave::open(map, *gripper, why);
    if (!gripper->port_) return nullptr;
    return gripper;
}

SimulatedGripperPort::~SimulatedGripperPort() {
    port_.reset();  // no request reaches the gripper from here on
}

double SimulatedGripperPort::now() const {
    const auto t = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
    return std::chrono::duration<double>(t - epoch_).count() * options_.speed;
}

double SimulatedGripperPort::fingerPosition() {
    std::lock_guard lock(mutex_);
    (void)gripper_.status(now());  // where the fingers are now, not at the last request
    return gripper_.position();
}

bool SimulatedGripperPort::waitForCommand(const std::function<bool(const Command&)>& predicate,
                                          std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return written_.wait_for(lock, timeout, [&] { return predicate(gripper_.command()); });
}

Command SimulatedGripperPort::lastCommand() {
    std::lock_guard lock(mutex_);
    return gripper_.command();
}

void SimulatedGripperPort::report(const std::vector<FingerEvent>& events) const {
    for (const auto& e : events) {
        if (options_.onEvent) options_.onEvent(e);
    }
}

void SimulatedGripperPort::present(std::span<std::uint16_t>, std::span<std::uint16_t> input) {
    // What the fingers did up to now reaches the world before the reply does, so a robot
    // that reads "object detected" finds the world already holding it. Events go out
    // without the lock: reporting them is a network round trip. While the world has not
    // heard one yet (it restarts), the fingers show as still moving.
    std::vector<FingerEvent> events;
    Status status;
    {
        std::lock_guard lock(mutex_);
        status = gripper_.status(now());
        events = gripper_.takeEvents();
    }
    report(events);
    if (options_.worldBehind && options_.worldBehind()) status.object = ObjectStatus::Moving;
    const Registers registers = encode(status);
    std::copy(registers.begin(), registers.end(), input.begin());
}

void SimulatedGripperPort::written(std::uint16_t, std::uint16_t,
                                   std::span<const std::uint16_t> holding) {
    std::vector<FingerEvent> events;
    {
        std::lock_guard lock(mutex_);
        Registers command{};
        std::copy_n(holding.begin(), kRegisterCount, command.begin());
        gripper_.write(decodeCommand(command), now());
        events = gripper_.takeEvents();
    }
    written_.notify_all();
    report(events);
}

}  // namespace skillcell::devices::robotiq
