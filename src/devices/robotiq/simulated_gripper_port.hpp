#pragma once
// SimulatedGripperPort: a simulated 2F-85 on a serial line. It opens a pseudo-terminal
// pair, puts the slave side in raw mode and serves the Robotiq register map as a Modbus
// RTU slave (libmodbus, slave id 9) on the master side from a thread of its own. The
// adapter opens devicePath() like any serial device; nothing else connects the two.
//
// Simulated time is the steady clock times the speed factor (or an injected clock).
// Finger events (grasped, released) go to `onEvent` on the port's thread.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "devices/robotiq/simulated_2f85.hpp"
#include "ua/types/result.hpp"

namespace skillcell::devices::robotiq {

struct SimulatedGripperOptions {
    SimulatedGripperOptions() = default;
    double speed = 1.0;
    std::function<std::chrono::steady_clock::time_point()> clock;  // empty: steady_clock
    Simulated2F85::Probe probe;
    std::function<void(const FingerEvent&)> onEvent;
};

class SimulatedGripperPort {
public:
    /// Opens the pty pair and starts serving. On failure `why` (if given) says why.
    [[nodiscard]] static std::unique_ptr<SimulatedGripperPort> open(SimulatedGripperOptions options,
                                                                    std::string* why = nullptr);
    ~SimulatedGripperPort();
    SimulatedGripperPort(const SimulatedGripperPort&) = delete;
    SimulatedGripperPort& operator=(const SimulatedGripperPort&) = delete;

    /// The serial device the adapter opens (the pty's slave side, /dev/pts/N).
    [[nodiscard]] const std::string& devicePath() const { return path_; }
    /// The fingers' position now (0 open .. 255 closed), for tests.
    [[nodiscard]] double fingerPosition();
    /// Requests served so far (tests wait on the protocol, not on time).
    [[nodiscard]] std::uint64_t requests();
    /// Waits until `count` requests have been served; false after `timeout`.
    bool waitForRequests(std::uint64_t count, std::chrono::milliseconds timeout);
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

private:
    void serve();
    [[nodiscard]] double now() const;

    SimulatedGripperOptions options_;
    std::chrono::steady_clock::time_point epoch_;
    int master_ = -1;
    int slave_ = -1;  // kept open so the master never sees a hang-up between clients
    int stop_[2] = {-1, -1};
    std::string path_;
    std::mutex mutex_;  // guards gripper_ and requests_
    std::condition_variable served_;
    Simulated2F85 gripper_;
    std::uint64_t requests_ = 0;
    std::thread thread_;
};

}  // namespace skillcell::devices::robotiq
