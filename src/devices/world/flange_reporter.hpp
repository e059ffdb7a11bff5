#pragma once
// FlangeReporter: sends a robot's flange poses to the world model from a thread of its
// own, so that the robot's io_context never waits for a round trip. Poses are coalesced:
// while one report travels, only the newest pending pose is kept, and the last pose of a
// motion is always sent. Each answer carries the contact force at the pose sent: what a
// force-sensing arm measures, one round trip late.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "devices/world/world_link.hpp"

namespace skillcell::devices {

class FlangeReporter {
public:
    [[nodiscard]] static std::unique_ptr<FlangeReporter> start(std::unique_ptr<WorldLink> link);
    ~FlangeReporter();
    FlangeReporter(const FlangeReporter&) = delete;
    FlangeReporter& operator=(const FlangeReporter&) = delete;

    /// Any thread; never blocks on the network.
    void report(const KDL::Frame& flange);
    /// Waits until every pose reported so far has been sent (or `timeout` passes); true
    /// when they have.
    bool flush(std::chrono::milliseconds timeout);
    /// Calls `callback` once every pose reported so far has been sent (at once if they
    /// have, else on the reporter's thread). A failed send counts as sent: a lost world
    /// model must not stop the robot.
    void whenSent(std::function<void()> callback);
    /// The contact force at the last pose the world answered for (N); any thread.
    [[nodiscard]] double contactForce() const { return contactForce_.load(); }
    /// How many reported poses the world has not answered yet (a failed send counts as
    /// answered); any thread.
    [[nodiscard]] std::uint64_t unanswered();

    struct Token {
    private:
        friend class FlangeReporter;
        Token() = default;
    };
    FlangeReporter(Token, std::unique_ptr<WorldLink> link) : link_(std::move(link)) {}

private:
    void run();

    std::unique_ptr<WorldLink> link_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<KDL::Frame> pending_;
    std::vector<std::pair<std::uint64_t, std::function<void()>>> waiters_;
    std::uint64_t reported_ = 0;
    std::uint64_t sent_ = 0;
    bool stopping_ = false;
    bool warned_ = false;
    std::atomic<double> contactForce_{0.0};
    std::thread thread_;
};

}  // namespace skillcell::devices
