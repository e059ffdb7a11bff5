// skillcell_bench_cell_scale: a cell of N components on one network segment, each a real
// process (`skillcell server --noop-skill` x2, --insecure), for each N of --sizes:
//
//   all READY          from the first start to the last component listening (all started at once)
//   cold detection     a new detector, started once all N are up, until it has every skill
//   plug               one more component started until its skills are in that detector
//                      (--plugs times, p50 and p99), and until its READY line
//   unplug             SIGTERM, and kill -9, until its skills are gone (alternately)
//   idle               over --idle-seconds with nothing happening: packets per second on the
//                      segment (the loopback's counters, mDNS and OPC UA alike), and each
//                      component's CPU (the scheduler's ns, not ticks) and RSS (from /proc)
//
// Components are told apart by their application URIs: each has a PKI directory of its own,
// made before the clock starts (an RSA key per component, kept in --pki-cache for the next
// run). The KB's time to record a plugged component is not measured here: it needs the KB
// and Virtuoso (bench/kb_query_bench.cpp, docs/knowledge_base.md).
//
// Run it inside a private network namespace (it refuses to send mDNS anywhere else):
//   tests/netns/run_in_private_netns.sh build/bench/skillcell_bench_cell_scale --sizes 50,100
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "common/command_line.hpp"
#include "detection_rig.hpp"
#include "latency_stats.hpp"
#include "process/child_process.hpp"
#include "process/cpu_time.hpp"
#include "ua/pki/own_certificate.hpp"

namespace {

using namespace std::chrono_literals;
using skillcell::bench::Clock;
using skillcell::bench::DetectionRig;
using skillcell::bench::portOf;
using skillcell::bench::Samples;
using skillcell::process::ChildProcess;
namespace fs = std::filesystem;

struct Options {
    std::vector<int> sizes = {20};
    int plugs = 10;
    int idleSeconds = 10;
    std::string skillcell = SKILLCELL_BINARY;
    fs::path pkiCache = fs::temp_directory_path() / "skillcell-bench-cell-scale-pki";
};

const std::vector<std::string> kSkills = {"CartesianLinearMoveSkillType=Move",
                                          "GraspGripperSkillType=Grasp"};

std::string uriOf(int i) {
    return "urn:skillcell:bench-cell-scale:" + std::to_string(i);
}

/// Each component's certificate, made before any clock starts (two threads: RSA key
/// generation is most of it).
bool commission(const Options& o, int count) {
    std::atomic<int> next{0};
    std::atomic<bool> ok{true};
    auto work = [&] {
        for (int i = next++; i < count && ok; i = next++) {
            skillcell::ua::pki::CertificateSubject subject;
            subject.applicationUri = uriOf(i);
            subject.commonName = "bench component " + std::to_string(i);
            subject.dnsNames = {"localhost"};
            std::string why;
            if (!skillcell::ua::pki::loadOrCreateOwnCertificate(o.pkiCache / std::to_string(i),
                                                                subject, &why)) {
                std::fprintf(stderr, "certificate %d: %s\n", i, why.c_str());
                ok = false;
            }
        }
    };
    std::thread helper(work);
    work();
    helper.join();
    return ok;
}

std::vector<std::string> argvOf(const Options& o, int i) {
    return skillcell::bench::serverArgv(o.skillcell, uriOf(i), "scale-" + std::to_string(i),
                                        o.pkiCache / std::to_string(i), 0, kSkills);
}

struct Component {
    ChildProcess process;
    std::string port;
};

/// Starts component `i`; nothing when it does not start or print READY within `timeout`.
std::optional<ChildProcess> launch(const Options& o, int i, const fs::path& log) {
    auto child = ChildProcess::start(argvOf(o, i), skillcell::process::reportingChild(log));
    if (!child) {
        std::fprintf(stderr, "component %d: %s\n", i, child.error().c_str());
        return std::nullopt;
    }
    return std::move(*child);
}

std::optional<std::string> readyPort(ChildProcess& child, int i, const fs::path& log) {
    auto line = child.readLine(120s);
    if (!line || line->rfind("READY ", 0) != 0) {
        std::fprintf(stderr, "component %d: no READY line (see %s)\n", i, log.c_str());
        return std::nullopt;
    }
    return portOf(line->substr(6));
}

/// A process's CPU time in ns (process/cpu_time.hpp says why schedstat, not ticks).
long long cpuNanoseconds(pid_t pid) {
    return skillcell::process::cpuTime(pid).count();
}

/// A field of a /proc file in kB ("VmRSS:" of status, "Pss:" of smaps_rollup), 0 if absent.
long procKb(pid_t pid, const char* file, std::string_view field) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/" + file);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind(field, 0) == 0) return std::stol(line.substr(field.size()));
    }
    return 0;
}

/// Resident set size in kB.
long rssKb(pid_t pid) {
    return procKb(pid, "status", "VmRSS:");
}

/// Packets the loopback carried so far (each is sent and received once on it), from
/// /proc/net/dev, which shows the reader's network namespace (/sys would show the host's).
long loopbackPackets() {
    std::ifstream in("/proc/net/dev");
    std::string line;
    while (std::getline(in, line)) {
        const auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        std::string name = line.substr(0, colon);
        name.erase(0, name.find_first_not_of(' '));
        if (name != "lo") continue;
        // receive: bytes packets errs drop fifo frame compressed multicast; transmit: bytes
        // packets ...
        std::istringstream fields(line.substr(colon + 1));
        long value = 0;
        for (int k = 0; k < 10 && fields >> value; ++k) {
            if (k == 9) return value;  // transmit packets
        }
    }
    return 0;
}

/// UDP datagrams this network namespace dropped because a socket's receive buffer was full
/// (/proc/net/snmp, Udp: RcvbufErrors): mDNS answers that a burst lost.
long udpReceiveBufferErrors() {
    std::ifstream in("/proc/net/snmp");
    std::string names;
    std::string values;
    while (std::getline(in, names) && std::getline(in, values)) {
        if (names.rfind("Udp:", 0) != 0) continue;
        std::istringstream n(names.substr(4));
        std::istringstream v(values.substr(4));
        std::string name;
        long value = 0;
        while (n >> name && v >> value) {
            if (name == "RcvbufErrors") return value;
        }
    }
    return 0;
}

void printLatency(const char* what, const Samples& samples) {
    const auto s = skillcell::bench::summarize(samples);
    std::printf("  %-34s p50 %9.2f  p99 %9.2f  max %9.2f ms  (n=%zu)\n", what, s.medianUs / 1000,
                s.p99Us / 1000, s.maxUs / 1000, s.n);
}

double msSince(Clock::time_point t0, Clock::time_point t1) {
    return std::chrono::duration<double, std::milli>(t1 - t0).count();
}

int runSize(const Options& o, int n, const fs::path& logs) {
    std::printf("\nN = %d components (each a process with %zu no-op skills)\n", n, kSkills.size());
    // All at once, as a cell powered on.
    std::vector<Component> cell;
    cell.reserve(static_cast<std::size_t>(n));
    const long packetsBefore = loopbackPackets();
    const long dropsBefore = udpReceiveBufferErrors();
    const auto t0 = Clock::now();
    std::vector<ChildProcess> starting;
    for (int i = 0; i < n; ++i) {
        auto child = launch(o, i, logs / ("component-" + std::to_string(i) + ".log"));
        if (!child) return 1;
        starting.push_back(std::move(*child));
    }
    for (int i = 0; i < n; ++i) {
        auto port = readyPort(starting[static_cast<std::size_t>(i)], i,
                              logs / ("component-" + std::to_string(i) + ".log"));
        if (!port) return 1;
        cell.push_back({std::move(starting[static_cast<std::size_t>(i)]), *port});
    }
    const auto tReady = Clock::now();
    std::printf("  all READY                          %9.1f ms after the first start\n",
                msSince(t0, tReady));

    // Cold detection by a new detector, in a cell that has been up a while: right after the
    // components' announcements (sent twice, 1 s apart), RFC 6762's one-second rule (6.2)
    // would hold their answers back, which no detector of a running cell meets.
    std::this_thread::sleep_for(3s);  // the scenario's condition, not a synchronisation
    std::printf(
        "  packets from the first start to 3 s after the last READY: %ld (%.1f per "
        "component)\n",
        loopbackPackets() - packetsBefore,
        static_cast<double>(loopbackPackets() - packetsBefore) / n);
    std::printf("  UDP datagrams dropped, receive buffer full: %ld\n",
                udpReceiveBufferErrors() - dropsBefore);
    const long coldDropsBefore = udpReceiveBufferErrors();
    std::string error;
    const long rssBefore = rssKb(::getpid());
    const long long cpuBefore = cpuNanoseconds(::getpid());
    const auto tDetector = Clock::now();
    auto rig = DetectionRig::start(kSkills.size(), &error);
    if (!rig) {
        std::fprintf(stderr, "mDNS: %s\n", error.c_str());
        return 1;
    }
    auto& timeline = rig->timeline();
    const auto coldLimit = std::chrono::milliseconds(30'000 + 100 * n);
    if (!timeline.waitForDetected(static_cast<std::size_t>(n), coldLimit)) {
        std::fprintf(stderr, "cold detection: %zu of %d detected after %lld ms\n",
                     timeline.detectedCount(), n, static_cast<long long>(coldLimit.count()));
        return 1;
    }
    std::printf("  cold detection of all N            %9.1f ms (a new detector)\n",
                msSince(tDetector, Clock::now()));
    std::printf("    UDP datagrams dropped meanwhile, receive buffer full: %ld\n",
                udpReceiveBufferErrors() - coldDropsBefore);
    {  // where the time went: the components' mDNS answers, then their sessions and browses
        Samples heard;
        Samples detected;
        for (int i = 0; i < n; ++i) {
            if (auto t = timeline.waitFor("announced scale-" + std::to_string(i), 0ms)) {
                heard.push_back(*t - tDetector);
            }
            if (auto t =
                    timeline.waitFor("skills " + cell[static_cast<std::size_t>(i)].port, 0ms)) {
                detected.push_back(*t - tDetector);
            }
        }
        printLatency("  of which: mDNS answer heard", heard);
        printLatency("  of which: skills detected", detected);
    }
    std::printf("  the detector's CPU for it          %9.1f ms\n",
                static_cast<double>(cpuNanoseconds(::getpid()) - cpuBefore) / 1e6);
    std::printf("  the detector's memory              %9.1f MB more RSS with N components\n",
                static_cast<double>(rssKb(::getpid()) - rssBefore) / 1024);

    // Plug and unplug one more, --plugs times.
    Samples plug;
    Samples ready;  // the plugged component's own start, to its READY line
    Samples unplugTerm;
    Samples unplugKill;
    for (int k = 0; k < o.plugs; ++k) {
        const int i = n + k;
        const fs::path log = logs / ("component-" + std::to_string(i) + ".log");
        timeline.clear();
        const auto tStart = Clock::now();
        auto child = launch(o, i, log);
        if (!child) return 1;
        auto port = readyPort(*child, i, log);
        if (!port) return 1;
        ready.push_back(Clock::now() - tStart);
        auto tDetected = timeline.waitFor("skills " + *port, 30s);
        if (!tDetected) {
            std::fprintf(stderr, "plug %d: not detected within 30 s (see %s)\n", k, log.c_str());
            return 1;
        }
        plug.push_back(*tDetected - tStart);
        const bool kill = k % 2 == 1;
        const auto tStop = Clock::now();
        ::kill(child->pid(), kill ? SIGKILL : SIGTERM);
        auto tGone = timeline.waitFor("removed " + *port, 60s);
        (void)child->terminate(5s);
        if (!tGone) {
            std::fprintf(stderr, "unplug %d: its skills were never removed\n", k);
            return 1;
        }
        (kill ? unplugKill : unplugTerm).push_back(*tGone - tStop);
    }
    printLatency("plug (start -> skills detected)", plug);
    printLatency("  of which: start -> READY", ready);
    printLatency("unplug, SIGTERM -> skills gone", unplugTerm);
    printLatency("unplug, kill -9 -> skills gone", unplugKill);

    // Idle: nothing starts or stops; the detector keeps its sessions.
    std::this_thread::sleep_for(2s);  // what the last unplug set off settles (not a sync)
    std::vector<long long> busy;
    busy.reserve(cell.size());
    for (const auto& c : cell) busy.push_back(cpuNanoseconds(c.process.pid()));
    const long packets = loopbackPackets();
    const auto tIdle = Clock::now();
    std::this_thread::sleep_for(std::chrono::seconds(o.idleSeconds));  // the idle period itself
    const double seconds = msSince(tIdle, Clock::now()) / 1000;
    const long idlePackets = loopbackPackets() - packets;
    std::vector<double> cpu;
    std::vector<double> rss;
    // RSS counts the pages of the binary and libraries that every component shares; the
    // proportional set size divides them among their users, and the anonymous part is what
    // each component costs on its own.
    std::vector<double> pss;
    std::vector<double> anon;
    for (std::size_t k = 0; k < cell.size(); ++k) {
        const auto pid = cell[k].process.pid();
        cpu.push_back(100.0 * static_cast<double>(cpuNanoseconds(pid) - busy[k]) / 1e9 / seconds);
        rss.push_back(static_cast<double>(rssKb(pid)) / 1024);
        pss.push_back(static_cast<double>(procKb(pid, "smaps_rollup", "Pss:")) / 1024);
        anon.push_back(static_cast<double>(procKb(pid, "status", "RssAnon:")) / 1024);
    }
    const auto busiest = static_cast<std::size_t>(
        std::distance(cpu.begin(), std::max_element(cpu.begin(), cpu.end())));
    std::sort(cpu.begin(), cpu.end());
    std::sort(rss.begin(), rss.end());
    std::sort(pss.begin(), pss.end());
    std::sort(anon.begin(), anon.end());
    auto median = [](const std::vector<double>& v) { return v[v.size() / 2]; };
    double cpuSum = 0;
    for (double c : cpu) cpuSum += c;
    std::printf("  idle packets on the segment        %9.1f /s (%.2f per component)\n",
                static_cast<double>(idlePackets) / seconds,
                static_cast<double>(idlePackets) / seconds / n);
    std::printf(
        "  idle CPU per component             median %.3f %%, p99 %.3f %%, max %.3f %% (all: "
        "%.1f %% of one core; the busiest: scale-%zu)\n",
        median(cpu), cpu[cpu.size() * 99 / 100], cpu.back(), cpuSum, busiest);
    std::printf("  RSS per component                  median %.1f MB, max %.1f MB\n", median(rss),
                rss.back());
    std::printf("    of which its own (RssAnon)       median %.1f MB, max %.1f MB\n", median(anon),
                anon.back());
    std::printf("  PSS per component                  median %.1f MB, max %.1f MB\n", median(pss),
                pss.back());

    rig.reset();
    for (auto& c : cell) ::kill(c.process.pid(), SIGTERM);
    for (auto& c : cell) (void)c.process.terminate(10s);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "A cell of N component processes on one segment (each `skillcell server` with "
        "two no-op skills): all READY, cold detection, plug and unplug latency, idle "
        "traffic, CPU and memory. Run it inside tests/netns/run_in_private_netns.sh."};
    app.add_option("--sizes", o.sizes, "cell sizes N, comma-separated (1..2000)")
        ->delimiter(',')
        ->check(CLI::Range(1, 2000))
        ->capture_default_str();
    app.add_option("--plugs", o.plugs, "components plugged into each cell, one at a time")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--idle-seconds", o.idleSeconds, "how long the idle cell is measured")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--skillcell", o.skillcell,
                   "the program the components run (skillcell-component, or skillcell)")
        ->capture_default_str();
    app.add_option("--pki-cache", o.pkiCache,
                   "where the components' certificates are kept between runs")
        ->capture_default_str();
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    if (!skillcell::bench::onlyLoopbackMulticast()) {
        std::fprintf(stderr,
                     "refusing to send mDNS here: a real network interface is up. Run inside "
                     "tests/netns/run_in_private_netns.sh.\n");
        return 2;
    }
    spdlog::set_level(spdlog::level::warn);
    const int most = *std::max_element(o.sizes.begin(), o.sizes.end()) + o.plugs;
    std::printf("commissioning %d certificates in %s ...\n", most, o.pkiCache.c_str());
    std::fflush(stdout);
    if (!commission(o, most)) return 1;
    const fs::path logs =
        fs::temp_directory_path() / ("skillcell-bench-cell-scale-" + std::to_string(::getpid()));
    fs::create_directories(logs);
    std::printf(
        "cell scale on one segment (loopback of a private network namespace, --insecure)\n");
    for (int n : o.sizes) {
        if (const int s = runSize(o, n, logs); s != 0) {
            std::fprintf(stderr, "the logs are in %s\n", logs.c_str());
            return s;
        }
    }
    fs::remove_all(logs);
    return 0;
}
