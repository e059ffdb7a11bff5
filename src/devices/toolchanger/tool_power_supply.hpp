#pragma once
// ToolPowerSupply: the tool changer's power pins. A tool with electronics (a gripper and its
// adapter) is powered when it is attached and loses power when it is detached. Here each
// tool's adapter is a process: power on starts it, power off sends SIGTERM (so the adapter
// says goodbye on the network, as a board with a supervisor would on a power-fail warning)
// and waits for it, bounded, then SIGKILL. A child gets SIGTERM when the changer dies
// (process::ChildProcess, death signal SIGTERM), so a crashed changer leaves no tool powered.
// A tool's stdout goes to the changer's stderr.
//
// A watchdog: an adapter that ends while its tool is powered (its firmware crashed) is
// started again at once, as a board's watchdog reboots it, up to kWatchdogRestarts times per
// power-on. A thread of its own waits for any of the powered processes to end (their pidfds).
//
// Threading: on() and off() block (off waits for the child): call them from an I/O thread.
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "process/child_process.hpp"
#include "ua/types/status_code.hpp"

namespace skillcell::devices::toolchanger {

inline constexpr int kWatchdogRestarts = 5;

class ToolPowerSupply {
public:
    explicit ToolPowerSupply(std::chrono::milliseconds stopTimeout = std::chrono::seconds(5));
    ~ToolPowerSupply();  // powers everything off
    ToolPowerSupply(const ToolPowerSupply&) = delete;
    ToolPowerSupply& operator=(const ToolPowerSupply&) = delete;

    /// Starts `argv` for `toolId` (Good if it runs already). BadInvalidArgument for an empty
    /// argv, BadResourceUnavailable (with `why`) when it cannot be started.
    ua::StatusCode on(const std::string& toolId, const std::vector<std::string>& argv,
                      std::string* why = nullptr);
    /// Stops the tool's process, if any; returns its exit status (-1: none, or killed).
    int off(const std::string& toolId);
    [[nodiscard]] bool powered(const std::string& toolId);
    /// How often the watchdog started the tool's adapter again since it was powered on.
    [[nodiscard]] int restarts(const std::string& toolId);
    /// Powers every tool off.
    void offAll();

private:
    struct Powered {
        process::ChildProcess child;
        std::vector<std::string> argv;
        int restarts = 0;
    };
    /// Waits for powered processes to end and starts them again (the watchdog's thread).
    void watch();
    /// Wakes the watchdog: the powered set changed, or it is to stop.
    void wake();
    static Expected<process::ChildProcess> start(const std::vector<std::string>& argv);

    std::chrono::milliseconds stopTimeout_;
    std::mutex mutex_;
    std::map<std::string, Powered> children_;  // by tool id
    bool stopping_ = false;
    process::UniqueFd wakeFd_;  // an eventfd
    std::thread watchdog_;      // last: started once the rest exists
};

}  // namespace skillcell::devices::toolchanger
