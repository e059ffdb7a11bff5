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
// Then the idle traffic: --idle N servers run together, each a browser (its registrar looks
// for an LDS) and a responder; once all are described and their announcements are over, every
// datagram on the mDNS group is counted for --idle-seconds: queries, answers, and per server.
// Before RFC 6762's rules were followed (every server queried every 30 s and every server
// answered every query), 30 idle servers made 1 query and 30 responses a second.
//
// mDNS must not reach a real network: run it inside a private network namespace,
//   tests/netns/run_in_private_netns.sh build/bench/skillcell_bench_discovery
// (it refuses to run where a non-loopback multicast interface is up).
#include <spdlog/spdlog.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <asio.hpp>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "command_line.hpp"
#include "detection_rig.hpp"
#include "latency_stats.hpp"
#include "process/child_process.hpp"
#include "ua/discovery/mdns_responder.hpp"
#include "ua/discovery/server_watcher.hpp"

namespace {

using namespace std::chrono_literals;
using skillcell::bench::Clock;
using skillcell::bench::onlyLoopbackMulticast;
using skillcell::bench::Samples;
using skillcell::bench::Timeline;
using skillcell::process::ChildProcess;
namespace mdns = skillcell::ua::mdns;
namespace lds = skillcell::ua::lds;

struct Options : skillcell::bench::ProcessRun {
    Options() : ProcessRun{50, 5, 2, SKILLCELL_BINARY} {}
    int idle = 30;         // servers of the idle-traffic run (0: none)
    int idleSeconds = 60;  // how long it counts
    int idleTtl = 120;     // the TTL they announce
    int idleSettle = 8;    // seconds before counting: libmdnsd announces 4 times, 2 s apart
};

/// One `skillcell server` process announcing `name` with `ttl`, its output appended to `log`.
auto startServer(const Options& o, const std::string& name, int ttl,
                 const std::filesystem::path& tmp, const std::string& log) {
    return ChildProcess::start(
        skillcell::bench::serverArgv(o.skillcell, "urn:skillcell:bench", name, tmp / "pki", ttl),
        skillcell::process::reportingChild(log));
}

struct Traffic {
    std::uint64_t queries = 0;
    std::uint64_t responses = 0;
    std::uint64_t knownAnswers = 0;  // records carried by queries
    std::uint64_t answers = 0;       // records carried by responses
};

/// Every datagram on the mDNS group for `window`, sorted into queries and responses.
Traffic countTraffic(std::chrono::seconds window) {
    Traffic t;
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) return t;
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEPORT, &one, sizeof one);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = htons(5353);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
        ::close(fd);
        return t;
    }
    for (const auto& nic : mdns::chooseMdnsInterfaces(mdns::listIpv4Interfaces(), {})) {
        ip_mreq m{};
        m.imr_multiaddr.s_addr = inet_addr("224.0.0.251");
        std::memcpy(&m.imr_interface.s_addr, nic.address.data(), 4);
        ::setsockopt(fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &m, sizeof m);
    }
    timeval tick{0, 100'000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tick, sizeof tick);
    std::vector<std::uint8_t> buf(9000);
    const auto end = Clock::now() + window;
    while (Clock::now() < end) {
        const auto n = ::recv(fd, buf.data(), buf.size(), 0);
        if (n <= 0) continue;
        auto m = mdns::parseDnsMessage(std::span(buf.data(), static_cast<std::size_t>(n)));
        if (!m) continue;
        if (m->isResponse) {
            ++t.responses;
            t.answers += m->records.size();
        } else {
            ++t.queries;
            t.knownAnswers += m->records.size();
        }
    }
    ::close(fd);
    return t;
}

/// Starts `o.idle` servers together, waits until all are described, then counts the traffic.
int idleTraffic(const Options& o, const std::filesystem::path& tmp, Timeline& timeline) {
    std::vector<ChildProcess> servers;
    const std::string log = (tmp / "idle.log").string();
    for (int i = 0; i < o.idle; ++i) {
        const std::string name = "idle-" + std::to_string(i);
        auto child = startServer(o, name, o.idleTtl, tmp, log);
        if (!child) {
            std::fprintf(stderr, "idle start %d: %s\n", i, child.error().c_str());
            return 1;
        }
        servers.push_back(std::move(*child));
    }
    for (int i = 0; i < o.idle; ++i) {
        if (!timeline.waitFor("described idle-" + std::to_string(i), 30s)) {
            std::fprintf(stderr, "idle server %d never described (see %s)\n", i, log.c_str());
            return 1;
        }
    }
    // Not synchronisation: the count is of the idle cell, after the start-up announcements.
    std::this_thread::sleep_for(std::chrono::seconds(o.idleSettle));
    const auto t = countTraffic(std::chrono::seconds(o.idleSeconds));
    for (auto& s : servers) (void)s.terminate(5s);
    const double secs = o.idleSeconds;
    std::printf("idle traffic: %d servers (TTL %d s) and this listener, over %d s\n", o.idle,
                o.idleTtl, o.idleSeconds);
    std::printf("  %-34s %9.2f /s  (%.1f known answers each)\n", "queries",
                static_cast<double>(t.queries) / secs,
                t.queries == 0
                    ? 0.0
                    : static_cast<double>(t.knownAnswers) / static_cast<double>(t.queries));
    std::printf(
        "  %-34s %9.2f /s  (%.1f records each)\n", "responses",
        static_cast<double>(t.responses) / secs,
        t.responses == 0 ? 0.0 : static_cast<double>(t.answers) / static_cast<double>(t.responses));
    std::printf("  %-34s %9.3f /s\n", "datagrams per server",
                static_cast<double>(t.queries + t.responses) / secs / o.idle);
    std::printf("  before RFC 6762's rules, measured with 30 servers: 1 query/s, 30 responses/s\n");
    return 0;
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
        auto child = startServer(o, name, o.ttl, tmp, log);
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
    const int idleResult = o.idle > 0 ? idleTraffic(o, tmp, timeline) : 0;
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
    skillcell::bench::printLatencyRow("start -> READY (listening)", ready, 34);
    skillcell::bench::printLatencyRow("start -> mDNS announced", announced, 34);
    skillcell::bench::printLatencyRow("start -> described (callback)", described, 34);
    skillcell::bench::printLatencyRow("SIGTERM -> gone (goodbye)", goodbye, 34);
    char row[64];
    std::snprintf(row, sizeof row, "kill -9 -> gone (expired, TTL %d s)", o.ttl);
    skillcell::bench::printLatencyRow(row, expired, 34);
    const auto r = skillcell::bench::summarize(ready);
    const auto d = skillcell::bench::summarize(described);
    std::printf("  discovery after listening (described - READY, medians): %.2f ms\n",
                (d.medianUs - r.medianUs) / 1000);
    std::printf("  paper (Profanter et al.): 211-313 ms from power-on to skill detection\n");
    return idleResult;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "mDNS discovery between processes: start to described, stop (goodbye) and "
        "kill (TTL) to gone, and the idle traffic of a cell. Run it inside "
        "tests/netns/run_in_private_netns.sh."};
    skillcell::bench::addProcessRunOptions(app, o);
    app.add_option("--idle", o.idle, "servers of the idle-traffic run (0: none)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--idle-seconds", o.idleSeconds, "how long the idle traffic is counted")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--idle-ttl", o.idleTtl, "the TTL the idle servers announce, in seconds")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--idle-settle", o.idleSettle, "seconds before counting")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    o.killed = std::min(o.killed, o.count);
    spdlog::set_level(spdlog::level::warn);
    return run(o);
}
