#pragma once
// SimulatedAg95: the behaviour of a DH-Robotics AG-95 behind its registers
// (ag95_registers.hpp), fed register writes and simulated time (seconds). Initialisation
// takes kInitialisationTime and leaves the fingers fully open; until then a position write
// is ignored, as the gripper ignores it. A motion runs at the speed register's rate; closing
// on an object narrower than the fingers' gap stops them at its width (state 2, object
// caught), else they reach the position (state 1). The object comes from a probe asked when
// a motion starts (the world model, in the cell). The force register is accepted but not
// simulated (an object is held or not). It serves itself on a serial line through
// PtyModbusSlave (open()).
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "devices/common/pty_modbus_slave.hpp"
#include "devices/dh/ag95_registers.hpp"
#include "devices/gripper/fingers.hpp"

namespace skillcell::devices::dh {

struct SimulatedAg95Options {
    SimulatedAg95Options() = default;
    double speed = 1.0;  // simulated seconds per real second
    std::function<std::chrono::steady_clock::time_point()> clock;  // empty: steady_clock
    std::function<Probed()> probe;
    std::function<void(const FingerEvent&)> onEvent;  // on the port's thread
    /// Whether the world has not heard every event yet (WorldLink::behind): the fingers show
    /// as moving until it has.
    std::function<bool()> worldBehind;
    /// Initialised and closed on this object as the simulation starts: the gripper as its
    /// adapter finds it when the adapter restarts while the fingers hold a part.
    std::optional<ObjectBetweenFingers> holding;
};

class SimulatedAg95 final : public SimulatedModbusDevice {
public:
    static constexpr double kInitialisationTime = 1.5;  // s

    /// Opens its serial port (a pty) and starts answering; nullptr and `why` on failure.
    [[nodiscard]] static std::unique_ptr<SimulatedAg95> open(SimulatedAg95Options options,
                                                             std::string* why = nullptr);
    ~SimulatedAg95() override;

    [[nodiscard]] const std::string& devicePath() const { return port_->devicePath(); }
    /// The fingers' gap now (m), for tests.
    [[nodiscard]] double width();
    [[nodiscard]] std::uint64_t requests() { return port_->requests(); }

    void present(std::span<std::uint16_t> holding, std::span<std::uint16_t> input) override;
    void written(std::uint16_t address, std::uint16_t count,
                 std::span<const std::uint16_t> holding) override;

    struct Token {
    private:
        friend class SimulatedAg95;
        Token() = default;
    };
    SimulatedAg95(Token, SimulatedAg95Options options);

private:
    [[nodiscard]] double now() const;
    void advance(double now);
    void startMotion(double target, double now);
    /// Where the closing fingers stop, from what the probe found.
    void meet(const std::optional<ObjectBetweenFingers>& object, double target);
    void report(const std::vector<FingerEvent>& events) const;

    SimulatedAg95Options options_;
    std::chrono::steady_clock::time_point epoch_;
    std::mutex mutex_;  // guards the state below
    InitialisationState initialisation_ = InitialisationState::NotInitialised;
    double initialisedAt_ = 0;
    GripperState state_ = GripperState::AtPosition;
    double perMille_ = 0;        // the gap now
    std::uint16_t speed_ = 100;  // the force register is kept, not simulated
    // The motion in progress.
    bool moving_ = false;
    double from_ = 0;
    double stopAt_ = 0;
    double startedAt_ = 0;
    std::optional<std::string> contactWith_;
    bool waitingForWorld_ = false;  // the probe could not say yet: not moving
    std::string holding_;
    std::vector<FingerEvent> events_;
    double now_ = 0;
    std::unique_ptr<PtyModbusSlave> port_;  // last: stops serving before the rest goes
};

}  // namespace skillcell::devices::dh
