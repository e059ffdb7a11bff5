#pragma once
// SimulatedGripperPort: a simulated 2F-85 on a serial line: the Robotiq register map
// served as Modbus RTU slave 9 on a pseudo-terminal (PtyModbusSlave). The adapter opens
// devicePath() like any serial device; nothing else connects the two.
//
// Simulated time is the steady clock times the speed factor (or an injected clock).
// Finger events (grasped, released) go to `onEvent` on the port's thread.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "devices/common/pty_modbus_slave.hpp"
#include "devices/robotiq/simulated_2f85.hpp"
#include "ua/types/result.hpp"

namespace skillcell::devices::robotiq {

struct SimulatedGripperOptions {
    SimulatedGripperOptions() = default;
    double speed = 1.0;
    std::function<std::chrono::steady_clock::time_point()> clock;  // empty: steady_clock
    Simulated2F85::Probe probe;
    std::function<void(const FingerEvent&)> onEvent;
    /// Whether the world has not heard every event yet (WorldLink::behind): gOBJ shows the
    /// fingers moving until it has.
    std::function<bool()> worldBehind;
    /// What the fingers hold as the simulation starts (Simulated2F85::startHolding).
    std::optional<ObjectBetweenFingers> holding;
};

class SimulatedGripperPort final : public SimulatedModbusDevice {
public:
    /// Opens the pty pair and starts serving. On failure `why` (if given) says why.
    [[nodiscard]] static std::unique_ptr<SimulatedGripperPort> open(SimulatedGripperOptions options,
                                                                    std::string* why = nullptr);
    ~SimulatedGripperPort() override;

    /// The serial device the adapter opens (the pty's slave side, /dev/pts/N).
    [[nodiscard]] const std::string& devicePath() const { return port_->devicePath(); }
    /// The fingers' position now (0 open .. 255 closed), for tests.
    [[nodiscard]] double fingerPosition();
    /// Requests served so far (tests wait on the protocol, not on time).
    [[nodiscard]] std::uint64_t requests() { return port_->requests(); }
    /// Waits until `count` requests have been served; false after `timeout`.
    bool waitForRequests(std::uint64_t count, std::chrono::milliseconds timeout) {
        return port_->waitForRequests(count, timeout);
    }
    /// Waits until the command registers as last written satisfy `predicate`; false
    /// after `timeout`.
    bool waitForCommand(const std::function<bool(const Command&)>& predicate,
                        std::chrono::milliseconds timeout);
    /// The command registers as last written.
    [[nodiscard]] Command lastCommand();

    struct Token {
    private:
        friend class SimulatedGripperPort;
        Token() = default;
    };
    SimulatedGripperPort(Token, SimulatedGripperOptions options);

    void present(std::span<std::uint16_t> holding, std::span<std::uint16_t> input) override;
    void written(std::uint16_t address, std::uint16_t count,
                 std::span<const std::uint16_t> holding) override;

private:
    [[nodiscard]] double now() const;
    void report(const std::vector<FingerEvent>& events) const;

    SimulatedGripperOptions options_;
    std::chrono::steady_clock::time_point epoch_;
    std::mutex mutex_;  // guards gripper_
    std::condition_variable written_;
    Simulated2F85 gripper_;
    std::unique_ptr<PtyModbusSlave> port_;  // last: stops serving before the rest goes
};

}  // namespace skillcell::devices::robotiq
