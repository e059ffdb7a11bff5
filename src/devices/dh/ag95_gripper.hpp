#pragma once
// Ag95Gripper: the DH-Robotics AG-95 adapter, a ParallelGripper over its Modbus RTU registers
// (ag95_registers.hpp), one operation at a time on a GripperWorker: initialise the gripper
// when it is not (write 0x0100, poll 0x0200), write force and speed, write the position
// (which starts the motion), poll the gripper state until the fingers stop, and judge the
// outcome from it. A Grasp opens the fingers first when they are not open.
// The AG-95 has no stop command: suspend and halt ask for the position the fingers are at,
// resume asks for the target again.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "devices/common/modbus_rtu_master.hpp"
#include "devices/dh/ag95_registers.hpp"
#include "devices/gripper/gripper_worker.hpp"

namespace skillcell::devices::dh {

struct Ag95GripperOptions {
    Ag95GripperOptions() = default;
    std::chrono::milliseconds poll{5};
    /// Real time an operation (initialisation included) may take before it fails.
    std::chrono::milliseconds timeout{30'000};
    double speed = 0.1;       // m/s, finger speed of every motion
    double graspForce = 100;  // N
};

class Ag95Gripper final : public ParallelGripper {
public:
    [[nodiscard]] static std::unique_ptr<Ag95Gripper> start(std::unique_ptr<ModbusRtuMaster> line,
                                                            Ag95GripperOptions options = {});
    ~Ag95Gripper() override = default;

    void grasp(Done done) override;
    void release(Done done) override;
    void moveTo(double width, double force, Done done) override;
    void suspend() override { worker_.suspend(); }
    void resume() override { worker_.resume(); }
    void halt() override { worker_.halt(); }
    /// The AG-95's datasheet: 3 kg recommended payload, the fingers' 95 mm stroke.
    [[nodiscard]] GripperRating rating() const override { return {3.0, kStroke}; }

    struct Token {
    private:
        friend class Ag95Gripper;
        Token() = default;
    };
    Ag95Gripper(Token, std::unique_ptr<ModbusRtuMaster> line, Ag95GripperOptions options)
        : line_(std::move(line)), options_(options), worker_(options.poll) {}

private:
    enum class Goal : std::uint8_t { Grasp, Release, Move };
    using Control = GripperWorker::Control;
    struct State {
        InitialisationState initialisation;
        GripperState gripper;
        std::uint16_t position;
    };
    void submit(Goal goal, std::uint16_t target, std::uint16_t force, Done done);
    std::optional<std::string> execute(Goal goal, std::uint16_t target, std::uint16_t force,
                                       Control& control);
    std::optional<std::string> initialise(Control& control);
    /// Writes the target and polls until the fingers stop: their state, or the failure.
    std::optional<std::string> travel(std::uint16_t target, Control& control, State& stopped);
    [[nodiscard]] ua::Result<State> read();
    ua::StatusCode write(std::uint16_t address, std::uint16_t value);
    [[nodiscard]] std::string lineError() const { return "serial line: " + line_->lastError(); }
    /// A Grasp opens fingers that are less open than this (per mille) first.
    static constexpr std::uint16_t kOpenEnough = 990;

    std::unique_ptr<ModbusRtuMaster> line_;
    Ag95GripperOptions options_;
    GripperWorker worker_;  // last: stopped (joined) before the line goes
};

}  // namespace skillcell::devices::dh
