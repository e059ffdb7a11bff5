#pragma once
// GripperWorker: the thread a gripper adapter runs its operations on, one at a time, and the
// rules every gripper shares for them: a new operation replaces one still waiting; halt()
// abandons the running one (it reports nothing) and drops the waiting one; suspend() and
// resume() set a flag the running operation sees at its next pause. What an operation does
// on the wire is the adapter's (RobotiqGripper: Modbus registers, EcbpiGripper: IO-Link
// process data); it polls through Control, the only place it waits.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "devices/gripper/parallel_gripper.hpp"

namespace skillcell::devices {

class GripperWorker {
public:
    /// What a running operation sees of its worker.
    class Control {
    public:
        /// Waits one poll period (less when halted): false once the operation is abandoned.
        bool pause();
        /// As of the last pause(): the operation is to hold still.
        [[nodiscard]] bool suspended() const { return suspended_; }
        [[nodiscard]] bool abandoned() const { return abandoned_; }

    private:
        friend class GripperWorker;
        Control(GripperWorker& worker, std::uint64_t generation)
            : worker_(worker), generation_(generation) {}
        GripperWorker& worker_;
        std::uint64_t generation_;
        bool suspended_ = false;
        bool abandoned_ = false;
    };
    /// Runs the operation: nullopt on success, else why it failed.
    using Body = std::function<std::optional<std::string>(Control&)>;

    explicit GripperWorker(std::chrono::milliseconds poll);
    /// Abandons what runs and joins the thread.
    ~GripperWorker();
    GripperWorker(const GripperWorker&) = delete;
    GripperWorker& operator=(const GripperWorker&) = delete;

    /// `done` gets the outcome, on the worker thread; `onAbandoned` runs there instead when
    /// the operation was halted (to leave the device safe: fingers stopped, suction off).
    void submit(Body body, Gripper::Done done, std::function<void()> onAbandoned);
    void suspend();
    void resume();
    void halt();

private:
    struct Operation {
        Body body;
        Gripper::Done done;
        std::function<void()> onAbandoned;
    };
    void run();

    std::chrono::milliseconds poll_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<Operation> pending_;
    std::uint64_t generation_ = 0;  // bumps on halt: the running operation is abandoned
    bool suspended_ = false;
    bool stopping_ = false;
    std::thread thread_;  // last: starts once the rest is set up
};

}  // namespace skillcell::devices
