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
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <variant>

#include "devices/gripper/parallel_gripper.hpp"
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
    ~RobotiqGripper() override;

    void grasp(Done done) override;
    void release(Done done) override;
    void moveTo(double width, double force, Done done) override;
    void suspend() override;
    void resume() override;
    void halt() override;

    struct Token {
    private:
        friend class RobotiqGripper;
        Token() = default;
    };
    RobotiqGripper(Token, std::unique_ptr<RobotiqClient> client, RobotiqGripperOptions options)
        : client_(std::move(client)), options_(options) {}

private:
    enum class Goal : std::uint8_t { Grasp, Release, Move };
    struct Job {
        Goal goal;
        Command command;
        Done done;
    };
    void submit(Goal goal, std::uint8_t position, std::uint8_t force, Done done);
    void run();
    /// Runs one job on the worker thread; nullopt on success, else the failure; sets
    /// `abandoned` when halt() ended it.
    std::optional<std::string> execute(const Job& job, bool& abandoned);
    std::optional<std::string> activate(bool& abandoned);
    /// Writes `command` and polls until the fingers stop: their status, or the failure.
    std::variant<Status, std::string> travel(const Command& command, std::uint64_t generation,
                                             bool& abandoned);
    /// A Grasp opens fingers that are closed further than this first.
    static constexpr std::uint8_t kOpenEnough = 3;
    /// Waits one poll period, or less when halted; false when the job is abandoned.
    bool pause(std::uint64_t generation);

    std::unique_ptr<RobotiqClient> client_;
    RobotiqGripperOptions options_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<Job> pending_;
    std::uint64_t generation_ = 0;  // bumps on halt: the running job is abandoned
    bool suspended_ = false;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace skillcell::devices::robotiq
