#pragma once
// RobotiqGripper: the 2F-85 adapter. It implements ParallelGripper over a RobotiqClient:
// one worker thread owns the serial line and runs one operation at a time: activate the
// gripper when it is not (rACT 0 then 1, until gSTA = 3), write the request (rGTO,
// rPR, rSP, rFR), then read the status registers at the poll period until the fingers
// stop (gOBJ != 0 with gPR echoing the request), and judge the outcome from gOBJ. A
// Grasp opens the fingers first when they are not open.
// Polling is the 2F-85's protocol: it reports nothing unasked.
// Suspend writes rGTO = 0 (the fingers stop) and resume writes the request again; halt
// does the same as suspend and abandons the operation.
#include <chrono>
#include <memory>
#include <optional>
#include <variant>

#include "devices/gripper/gripper_worker.hpp"
#include "devices/robotiq/robotiq_client.hpp"

namespace skillcell::devices::robotiq {

struct RobotiqGripperOptions {
    RobotiqGripperOptions() = default;
    std::chrono::milliseconds poll{5};
    /// Real time an operation (activation included) may take before it fails.
    std::chrono::milliseconds timeout{30'000};
    double speed = 0.1;       // m/s, finger speed of every motion
    double graspForce = 100;  // N
};

class RobotiqGripper final : public ParallelGripper {
public:
    [[nodiscard]] static std::unique_ptr<RobotiqGripper> start(
        std::unique_ptr<RobotiqClient> client, RobotiqGripperOptions options = {});
    ~RobotiqGripper() override = default;

    void grasp(Done done) override;
    void release(Done done) override;
    void moveTo(double width, double force, Done done) override;
    void suspend() override { worker_.suspend(); }
    void resume() override { worker_.resume(); }
    void halt() override { worker_.halt(); }
    /// The 2F-85's datasheet: 5 kg (friction grip), the fingers' 85 mm stroke.
    [[nodiscard]] GripperRating rating() const override { return {5.0, kStroke}; }

    struct Token {
    private:
        friend class RobotiqGripper;
        Token() = default;
    };
    RobotiqGripper(Token, std::unique_ptr<RobotiqClient> client, RobotiqGripperOptions options)
        : client_(std::move(client)), options_(options), worker_(options.poll) {}

private:
    enum class Goal : std::uint8_t { Grasp, Release, Move };
    using Control = GripperWorker::Control;
    void submit(Goal goal, std::uint8_t position, std::uint8_t force, Done done);
    /// Runs one operation on the worker thread; nullopt on success, else the failure.
    std::optional<std::string> execute(Goal goal, const Command& command, Control& control);
    std::optional<std::string> activate(Control& control);
    /// Writes `command` and polls until the fingers stop: their status, or the failure.
    std::variant<Status, std::string> travel(const Command& command, Control& control);
    /// A Grasp opens fingers that are closed further than this first.
    static constexpr std::uint8_t kOpenEnough = 3;

    std::unique_ptr<RobotiqClient> client_;
    RobotiqGripperOptions options_;
    GripperWorker worker_;  // last: stopped (joined) before the client goes
};

}  // namespace skillcell::devices::robotiq
