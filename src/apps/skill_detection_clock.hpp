#pragma once
// SkillDetectionClock: when each component's skills appeared in a SkillDetector of our own
// and when they left it: what `skillcell demo` measures against the paper's table (time from
// starting a component to the detection of its skills by the others). It runs an mDNS
// responder and a detector on a thread of its own, exactly as a component does, and records
// the moment a component's first skill arrives (the detector adds all of a component's
// skills from one browse) and the moment its last one goes.
#include <asio/executor_work_guard.hpp>
#include <asio/io_context.hpp>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "skills/skill_detector.hpp"
#include "ua/discovery/mdns_responder.hpp"

namespace skillcell::apps {

class SkillDetectionClock {
public:
    using Clock = std::chrono::steady_clock;

    /// Starts listening; nothing and `error` set when mDNS cannot start.
    [[nodiscard]] static std::unique_ptr<SkillDetectionClock> start(
        skills::SkillDetectorConfig config, ua::mdns::MdnsConfig mdns, std::string* error);
    ~SkillDetectionClock();
    SkillDetectionClock(const SkillDetectionClock&) = delete;
    SkillDetectionClock& operator=(const SkillDetectionClock&) = delete;

    /// When the skills of the component `applicationUri` appeared at or after `since`;
    /// nothing if they did not within `timeout`.
    [[nodiscard]] std::optional<Clock::time_point> waitAppeared(const std::string& applicationUri,
                                                                Clock::time_point since,
                                                                std::chrono::milliseconds timeout);
    /// True once the component has no skills in the detector (at once if it has none).
    [[nodiscard]] bool waitGone(const std::string& applicationUri,
                                std::chrono::milliseconds timeout);
    /// The detector's current map (any thread).
    [[nodiscard]] std::vector<skills::SkillInstance> instances() const;

    struct Token {
    private:
        friend class SkillDetectionClock;
        Token() = default;
    };
    explicit SkillDetectionClock(Token /*only start() makes one*/) {}

private:
    void record(const skills::SkillEvent& event);  // on the io thread

    asio::io_context io_{1};
    std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work_;
    std::thread thread_;
    std::shared_ptr<ua::mdns::MdnsResponder> responder_;
    std::shared_ptr<skills::SkillDetector> detector_;
    std::shared_ptr<ua::lds::ServerWatcher> watcher_;

    std::mutex mutex_;
    std::condition_variable changed_;
    struct Component {
        std::size_t skills = 0;
        std::vector<Clock::time_point> appearances;
    };
    std::map<std::string, Component> components_;  // by application URI
};

}  // namespace skillcell::apps
