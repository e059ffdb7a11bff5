// Discovery latency: how long after a server process starts another process hears of it,
// and how long after it stops (gracefully, or killed) it is gone. Each start is a real
// `skillcell server` process; the listener is this process (MdnsResponder + ServerWatcher).
//
//   start -> READY      the process is listening: the baseline every other row includes
//   start -> announced  its mDNS announcement reached us
//   start -> described  ... and GetEndpoints told us who it is (the "announced" callback)
//   SIGTERM -> gone     its goodbye reached us
//   kill -9 -> gone     its records expired (bounded by the TTL it announced)
//
// mDNS must not reach a real network: run it inside a private network namespace,
//   tests/netns/run_in_private_netns.sh build/bench/skillcell_bench_discovery
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
#include "ua/discovery/mdns_responder.hpp"
#include "ua/discovery/server_watcher.hpp"

namespace {

using namespace std::chrono_literals;
using skillcell::bench::Samples;
using skillcell::process::ChildProcess;
using Clock = std::chrono::steady_clock;
namespace mdns = skillcell::ua::mdns;
namespace lds = skillcell::ua::lds;

struct Options {
    int count = 50;
    int killed = 5;  // of them, how many are killed instead of stopped
    int ttl = 2;
    std::string skillcell = SKILLCELL_BINARY;
};

/// When each event was seen, by mDNS name; the main thread waits on it.
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

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::map<std::string, Clock::time_point> seen_;
};

void printRow(const char* what, const Samples& samples) {
    const auto s = skillcell::bench::summarize(samples);
    std::printf("  %-34s %9.2f %9.2f %9.2f %5zu\n", what, s.medianUs / 1000, s.p99Us / 1000,
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
                     ("skillcell-bench-discovery-" + std::to_string(::getpid()));
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
    lds::ServerWatcher::Callbacks callbacks;
    callbacks.announced = [&](const lds::AnnouncedServer& s) {
        timeline.record("described " + s.instance.name);
    };
    std::shared_ptr<lds::ServerWatcher> watcher;
    asio::post(io, asio::use_future([&] {
                   (*responder)->subscribe([&](const mdns::ServiceEvent& e) {
                       timeline.record((e.kind == mdns::ServiceEvent::Kind::Announced ? "announced "
                                                                                      : "gone ") +
                                       e.instance.name);
                   });
                   watcher = lds::ServerWatcher::create(io.get_executor(), *responder, callbacks);
                   (*responder)->start();
                   watcher->start();
               }))
        .get();

    Samples ready, announced, described, goodbye, expired;
    const std::string log = (tmp / "server.log").string();
    // Run 0 warms up: it creates the certificate the others reuse, and fills the caches.
    for (int i = 0; i <= o.count; ++i) {
        const std::string name = "bench-" + std::to_string(i);
        const auto t0 = Clock::now();
        auto child = ChildProcess::start(
            {o.skillcell, "--log-level", "warn", "server", "--insecure", "--port", "0", "--host",
             "127.0.0.1", "--application-uri", "urn:skillcell:bench", "--mdns-name", name,
             "--mdns-ttl", std::to_string(o.ttl), "--pki-dir", (tmp / "pki").string()},
            skillcell::process::reportingChild(log));
        if (!child) {
            std::fprintf(stderr, "start %d: %s\n", i, child.error().c_str());
            return 1;
        }
        auto line = child->readLine(20s);
        const auto tReady = Clock::now();
        auto tAnnounced = timeline.waitFor("announced " + name, 10s);
        auto tDescribed = timeline.waitFor("described " + name, 10s);
        if (!line || line->rfind("READY", 0) != 0 || !tAnnounced || !tDescribed) {
            std::fprintf(stderr, "start %d: not %s (see %s)\n", i,
                         !line ? "ready" : (!tAnnounced ? "announced" : "described"), log.c_str());
            return 1;
        }
        const bool kill = i > 0 && i > o.count - o.killed;
        const auto tStop = Clock::now();
        if (kill) {
            ::kill(child->pid(), SIGKILL);
        } else {
            ::kill(child->pid(), SIGTERM);
        }
        auto tGone = timeline.waitFor("gone " + name, std::chrono::seconds(o.ttl + 10));
        (void)child->terminate(5s);
        if (!tGone) {
            std::fprintf(stderr, "stop %d: never gone\n", i);
            return 1;
        }
        if (i == 0) continue;
        ready.push_back(tReady - t0);
        announced.push_back(*tAnnounced - t0);
        described.push_back(*tDescribed - t0);
        (kill ? expired : goodbye).push_back(*tGone - tStop);
    }
    asio::post(io, asio::use_future([&] {
                   watcher->stop();
                   (*responder)->shutdown();
               }))
        .get();
    work.reset();
    thread.join();
    std::filesystem::remove_all(tmp);

    std::printf("discovery over %d server process starts (loopback, private network namespace)\n",
                o.count);
    std::printf("  %-34s %9s %9s %9s %5s\n", "ms", "median", "p99", "max", "n");
    printRow("start -> READY (listening)", ready);
    printRow("start -> mDNS announced", announced);
    printRow("start -> described (callback)", described);
    printRow("SIGTERM -> gone (goodbye)", goodbye);
    char row[64];
    std::snprintf(row, sizeof row, "kill -9 -> gone (expired, TTL %d s)", o.ttl);
    printRow(row, expired);
    const auto r = skillcell::bench::summarize(ready);
    const auto d = skillcell::bench::summarize(described);
    std::printf("  discovery after listening (described - READY, medians): %.2f ms\n",
                (d.medianUs - r.medianUs) / 1000);
    std::printf("  paper (Profanter et al.): 211-313 ms from power-on to skill detection\n");
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
                         "usage: %s [--count N=50] [--killed K=5] [--ttl S=2] [--skillcell PATH]\n"
                         "Run it inside tests/netns/run_in_private_netns.sh.\n",
                         argv[0]);
            return arg == "--help" ? 0 : 2;
        }
    }
    o.killed = std::min(o.killed, o.count);
    spdlog::set_level(spdlog::level::warn);
    return run(o);
}
