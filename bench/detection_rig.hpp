#pragma once
// What the detection benchmarks share (skill_detection_bench, cell_scale_bench): a detector
// as a component runs one (an mDNS responder, a SkillDetector fed by its ServerWatcher, on an
// I/O thread of its own), and a timeline of what it saw, which the benchmark's thread waits
// on: "announced NAME" (an mDNS announcement), "skills PORT" (every skill of the component at
// that port is in the detector's map), "removed PORT" (its last skill left the map).
// Components are told apart by their port: a benchmark may restart one component, with one
// application URI and certificate, again and again.
#include <asio.hpp>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "skills/skill_detector.hpp"
#include "ua/discovery/mdns_responder.hpp"

namespace skillcell::bench {

using Clock = std::chrono::steady_clock;

/// When each event was first seen, and which components are detected now.
class Timeline {
public:
    void record(const std::string& key) {
        std::lock_guard lock(mutex_);
        seen_.emplace(key, Clock::now());
        changed_.notify_all();
    }
    void detected(const std::string& port, bool now) {
        std::lock_guard lock(mutex_);
        if (now) {
            present_.insert(port);
        } else {
            present_.erase(port);
        }
        changed_.notify_all();
    }
    std::optional<Clock::time_point> waitFor(const std::string& key,
                                             std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        if (!changed_.wait_for(lock, timeout, [&] { return seen_.contains(key); })) {
            return std::nullopt;
        }
        return seen_.at(key);
    }
    /// Waits until at least `n` components are detected at once; false after `timeout`.
    bool waitForDetected(std::size_t n, std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        return changed_.wait_for(lock, timeout, [&] { return present_.size() >= n; });
    }
    [[nodiscard]] std::size_t detectedCount() {
        std::lock_guard lock(mutex_);
        return present_.size();
    }
    void clear() {
        std::lock_guard lock(mutex_);
        seen_.clear();
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::map<std::string, Clock::time_point> seen_;
    std::set<std::string> present_;
};

/// "opc.tcp://127.0.0.1:4711/" -> "4711".
inline std::string portOf(const std::string& url) {
    const auto colon = url.rfind(':');
    if (colon == std::string::npos) return url;
    std::string port = url.substr(colon + 1);
    if (const auto slash = port.find('/'); slash != std::string::npos) port.resize(slash);
    return port;
}

/// The command line of a `skillcell server` component for the benchmarks: insecure, on the
/// loopback, announcing `mdnsName` (with `ttl` seconds, 0: the default), offering `skills`
/// (TYPE=NAME no-op skills).
inline std::vector<std::string> serverArgv(const std::string& skillcell,
                                           const std::string& applicationUri,
                                           const std::string& mdnsName,
                                           const std::filesystem::path& pkiDir, int ttl = 0,
                                           const std::vector<std::string>& skills = {}) {
    std::vector<std::string> argv = {
        skillcell,      "--log-level", "warn",   "server",    "--insecure",
        "--port",       "0",           "--host", "127.0.0.1", "--application-uri",
        applicationUri, "--mdns-name", mdnsName, "--pki-dir", pkiDir.string()};
    if (ttl > 0) argv.insert(argv.end(), {"--mdns-ttl", std::to_string(ttl)});
    for (const auto& skill : skills) argv.insert(argv.end(), {"--noop-skill", skill});
    return argv;
}

/// mDNS must not reach a real network: true when no interface but loopback does multicast
/// (inside tests/netns/run_in_private_netns.sh).
inline bool onlyLoopbackMulticast() {
    for (const auto& nic : ua::mdns::listIpv4Interfaces()) {
        if (nic.up && nic.multicast && !nic.loopback) return false;
    }
    return true;
}

/// A detector on an I/O thread of its own, recording into a Timeline.
class DetectionRig {
public:
    /// `skillsPerComponent`: a component counts as detected once that many of its skills are
    /// in the map. Nothing on failure, with `error` set.
    static std::unique_ptr<DetectionRig> start(std::size_t skillsPerComponent, std::string* error) {
        auto rig = std::make_unique<DetectionRig>(skillsPerComponent);
        ua::mdns::MdnsConfig config;
        config.queryPeriod = std::chrono::seconds(30);
        const bool ok =
            asio::post(rig->io_,
                       asio::use_future([&] { return rig->startOnIoThread(config, error); }))
                .get();
        if (!ok) return nullptr;
        return rig;
    }
    ~DetectionRig() {
        asio::post(io_, asio::use_future([this] {
                       if (watcher_) watcher_->stop();
                       if (detector_) detector_->stop();
                       if (responder_) responder_->shutdown();
                   }))
            .get();
        work_.reset();
        thread_.join();
    }
    DetectionRig(const DetectionRig&) = delete;
    DetectionRig& operator=(const DetectionRig&) = delete;
    /// Not started yet: start() is the way in.
    explicit DetectionRig(std::size_t skillsPerComponent)
        : skillsPerComponent_(skillsPerComponent), thread_([this] { io_.run(); }) {}

    [[nodiscard]] Timeline& timeline() { return timeline_; }

private:
    bool startOnIoThread(const ua::mdns::MdnsConfig& config, std::string* error) {
        auto responder = ua::mdns::MdnsResponder::create(io_.get_executor(), config, error);
        if (!responder) return false;
        responder_ = std::move(*responder);
        responder_->subscribe([this](const ua::mdns::ServiceEvent& e) {
            if (e.kind == ua::mdns::ServiceEvent::Kind::Announced) {
                timeline_.record("announced " + e.instance.name);
            }
        });
        detector_ = skills::SkillDetector::create(io_.get_executor());
        detector_->subscribe([this](const skills::SkillEvent& e) {
            const std::string port = portOf(e.instance.endpointUrl);
            std::size_t& n = skillsAt_[port];
            if (e.kind == skills::SkillEvent::Kind::Added) {
                if (++n == skillsPerComponent_) {
                    timeline_.record("skills " + port);
                    timeline_.detected(port, true);
                }
            } else if (n > 0 && --n == 0) {
                timeline_.record("removed " + port);
                timeline_.detected(port, false);
            }
        });
        responder_->start();
        watcher_ = skills::attachMdns(detector_, responder_);
        return true;
    }

    std::size_t skillsPerComponent_;
    Timeline timeline_;
    asio::io_context io_{1};
    asio::executor_work_guard<asio::io_context::executor_type> work_ = asio::make_work_guard(io_);
    std::shared_ptr<ua::mdns::MdnsResponder> responder_;
    std::shared_ptr<skills::SkillDetector> detector_;
    std::shared_ptr<ua::lds::ServerWatcher> watcher_;
    std::map<std::string, std::size_t> skillsAt_;  // port -> skills in the map (I/O thread)
    std::thread thread_;  // last: runs io_, which the members above must outlive
};

}  // namespace skillcell::bench
