// Skill detection latency, the paper's headline measure: how long after a component process
// starts do its skills appear in another component's SkillDetector, and how long after it
// stops (gracefully, or killed) are they gone. Each start is a real
// `skillcell server --noop-skill ...` process; the detector is this process's (MdnsResponder,
// ServerWatcher, SkillDetector, as in `skillcell detect` and `skillcell server --detect`).
//
//   start -> READY           the process is listening: the baseline every other row includes
//   start -> mDNS announced  its announcement reached us
//   start -> skills detected every skill of it is in the detector's map (connect, browse, types)
//   SIGTERM -> skills gone   goodbye and closed connection
//   kill -9 -> skills gone   the kernel closes its sockets: the detector's connection drops
//
// mDNS must not reach a real network: run it inside a private network namespace,
//   tests/netns/run_in_private_netns.sh build/bench/skillcell_bench_skill_detection
// (it refuses to run where a non-loopback multicast interface is up).
#include <spdlog/spdlog.h>

#include <asio.hpp>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "latency_stats.hpp"
#include "process/child_process.hpp"
#include "skills/skill_detector.hpp"
#include "ua/discovery/mdns_responder.hpp"

namespace {

using namespace std::chrono_literals;
using skillcell::bench::Samples;
using skillcell::process::ChildProcess;
using Clock = std::chrono::steady_clock;
namespace mdns = skillcell::ua::mdns;
namespace skills = skillcell::skills;

struct Options {
    int count = 30;
    int killed = 3;  // of them, how many are killed instead of stopped
    int ttl = 2;
    std::string skillcell = SKILLCELL_BINARY;
};

// The skills every component process offers.
const std::vector<std::string> kSkills = {"CartesianLinearMoveSkillType=Move",
                                          "GraspGripperSkillType=Grasp"};

/// When each event was seen; the main thread waits on it.
class Timeline {
public:
    void record(const std::string& key) {
        std::lock_guard lock(mutex_);
        seen_.emplace(key, Clock::now());
        changed_.notify_all();
    }
    std::optional<Clock::time_point> waitFor(const std::string& key,
                                             std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        if (!changed_.wait_for(lock, timeout, [&] { return seen_.contains(key); }))
            return std::nullopt;
        return seen_.at(key);
    }
    void clear() {
        std::lock_guard lock(mutex_);
        seen_.clear();
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::map<std::string, Clock::time_point> seen_;
};

/// "opc.tcp://127.0.0.1:4711/" -> "4711": runs reuse one application URI (one component
/// restarted again and again, which keeps its certificate), a run is told by its port.
std::string portOf(const std::string& url) {
    const auto colon = url.rfind(':');
    if (colon == std::string::npos) return url;
    std::string port = url.substr(colon + 1);
    if (const auto slash = port.find('/'); slash != std::string::npos) port.resize(slash);
    return port;
}

void printRow(const char* what, const Samples& samples) {
    const auto s = skillcell::bench::summarize(samples);
    std::printf("  %-38s %9.2f %9.2f %9.2f %5zu\n", what, s.medianUs / 1000, s.p99Us / 1000,
                s.maxUs / 1000, s.n);
}

bool onlyLoopbackMulticast() {
    for (const auto& nic : mdns::listIpv4Interfaces()) {
        if (nic.up && nic.multicast && !nic.loopback) return false;
    }
    return true;
}

int run(const Options& o) {
    if (!onlyLoopbackMulticast()) {
        std::fprintf(stderr,
                     "refusing to send mDNS here: a real network interface is up. Run inside "
                     "tests/netns/run_in_private_netns.sh.\n");
        return 2;
    }
    const auto tmp = std::filesystem::temp_directory_path() /
                     ("skillcell-bench-skill-detection-" + std::to_string(::getpid()));
    std::filesystem::create_directories(tmp);

    asio::io_context io{1};
    auto work = asio::make_work_guard(io);
    std::thread thread([&] { io.run(); });
    Timeline timeline;
    mdns::MdnsConfig config;
    config.queryPeriod = 30s;
    std::string error;
    auto responder =
        asio::post(io, asio::use_future([&] {
                       return mdns::MdnsResponder::create(io.get_executor(), config, &error);
                   }))
            .get();
    if (!responder) {
        std::fprintf(stderr, "mDNS: %s\n", error.c_str());
        work.reset();
        io.stop();
        thread.join();
        return 1;
    }
    std::shared_ptr<skills::SkillDetector> detector;
    std::shared_ptr<skillcell::ua::lds::ServerWatcher> watcher;
    std::map<std::string, std::size_t> skillsAt;  // port -> skills in the map (io thread)
    asio::post(io, asio::use_future([&] {
                   (*responder)->subscribe([&](const mdns::ServiceEvent& e) {
                       if (e.kind == mdns::ServiceEvent::Kind::Announced)
                           timeline.record("announced " + e.instance.name);
                   });
                   detector = skills::SkillDetector::create(io.get_executor());
                   detector->subscribe([&](const skills::SkillEvent& e) {
                       const std::string port = portOf(e.instance.endpointUrl);
                       std::size_t& n = skillsAt[port];
                       if (e.kind == skills::SkillEvent::Kind::Added) {
                           if (++n == kSkills.size()) timeline.record("skills " + port);
                       } else if (n > 0 && --n == 0) {
                           timeline.record("removed " + port);
                       }
                   });
                   (*responder)->start();
                   watcher = skills::attachMdns(detector, *responder);
               }))
        .get();

    Samples ready, announced, detected, afterReady, goodbye, killed;
    const std::string log = (tmp / "server.log").string();
    // Run 0 warms up: it creates the certificate the others reuse, and fills the caches.
    for (int i = 0; i <= o.count; ++i) {
        const std::string name = "bench-" + std::to_string(i);
        std::vector<std::string> argv = {o.skillcell,
                                         "--log-level",
                                         "warn",
                                         "server",
                                         "--insecure",
                                         "--port",
                                         "0",
                                         "--host",
                                         "127.0.0.1",
                                         "--application-uri",
                                         "urn:skillcell:bench-component",
                                         "--mdns-name",
                                         name,
                                         "--mdns-ttl",
                                         std::to_string(o.ttl),
                                         "--pki-dir",
                                         (tmp / "pki").string()};
        for (const auto& skill : kSkills) {
            argv.emplace_back("--noop-skill");
            argv.push_back(skill);
        }
        timeline.clear();
        const auto t0 = Clock::now();
        auto child = ChildProcess::start(argv, skillcell::process::reportingChild(log));
        if (!child) {
            std::fprintf(stderr, "start %d: %s\n", i, child.error().c_str());
            return 1;
        }
        auto line = child->readLine(20s);
        const auto tReady = Clock::now();
        if (!line || line->rfind("READY ", 0) != 0) {
            std::fprintf(stderr, "start %d: no READY line (see %s)\n", i, log.c_str());
            return 1;
        }
        const std::string port = portOf(line->substr(6));
        auto tAnnounced = timeline.waitFor("announced " + name, 10s);
        auto tDetected = timeline.waitFor("skills " + port, 10s);
        if (!tAnnounced || !tDetected) {
            std::fprintf(stderr, "start %d: not %s (see %s)\n", i,
                         !tAnnounced ? "announced" : "detected", log.c_str());
            return 1;
        }
        const bool kill = i > 0 && i > o.count - o.killed;
        const auto tStop = Clock::now();
        ::kill(child->pid(), kill ? SIGKILL : SIGTERM);
        auto tGone = timeline.waitFor("removed " + port, std::chrono::seconds(o.ttl + 10));
        (void)child->terminate(5s);
        if (!tGone) {
            std::fprintf(stderr, "stop %d: its skills were never removed\n", i);
            return 1;
        }
        if (i == 0) continue;
        ready.push_back(tReady - t0);
        announced.push_back(*tAnnounced - t0);
        detected.push_back(*tDetected - t0);
        afterReady.push_back(*tDetected - tReady);
        (kill ? killed : goodbye).push_back(*tGone - tStop);
    }
    asio::post(io, asio::use_future([&] {
                   watcher->stop();
                   detector->stop();
                   (*responder)->shutdown();
               }))
        .get();
    work.reset();
    thread.join();
    std::filesystem::remove_all(tmp);

    std::printf(
        "skill detection over %d component process starts (2 no-op skills each; loopback, "
        "private network namespace)\n",
        o.count);
    std::printf("  %-38s %9s %9s %9s %5s\n", "ms", "median", "p99", "max", "n");
    printRow("start -> READY (listening)", ready);
    printRow("start -> mDNS announced", announced);
    printRow("start -> skills in the SkillDetector", detected);
    printRow("READY -> skills in the SkillDetector", afterReady);
    printRow("SIGTERM -> skills gone", goodbye);
    printRow("kill -9 -> skills gone", killed);
    const auto d = skillcell::bench::summarize(detected);
    std::printf(
        "  start -> skills detected: median %.1f ms, p99 %.1f ms; paper (Profanter et al., PC "
        "components): 211-313 ms\n",
        d.medianUs / 1000, d.p99Us / 1000);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto next = [&](int& v) {
            if (i + 1 >= argc) return false;
            v = std::atoi(argv[++i]);
            return v >= 0;
        };
        bool ok = true;
        if (arg == "--count") {
            ok = next(o.count) && o.count > 0;
        } else if (arg == "--killed") {
            ok = next(o.killed);
        } else if (arg == "--ttl") {
            ok = next(o.ttl) && o.ttl > 0;
        } else if (arg == "--skillcell" && i + 1 < argc) {
            o.skillcell = argv[++i];
        } else {
            ok = false;
        }
        if (!ok) {
            std::fprintf(stderr,
                         "usage: %s [--count N=30] [--killed K=3] [--ttl S=2] [--skillcell PATH]\n"
                         "Run it inside tests/netns/run_in_private_netns.sh.\n",
                         argv[0]);
            return arg == "--help" ? 0 : 2;
        }
    }
    o.killed = std::min(o.killed, o.count);
    spdlog::set_level(spdlog::level::warn);
    return run(o);
}
