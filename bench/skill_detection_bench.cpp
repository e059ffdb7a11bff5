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

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>

#include "command_line.hpp"
#include "detection_rig.hpp"
#include "latency_stats.hpp"
#include "process/child_process.hpp"

namespace {

using namespace std::chrono_literals;
using skillcell::bench::Clock;
using skillcell::bench::DetectionRig;
using skillcell::bench::onlyLoopbackMulticast;
using skillcell::bench::portOf;
using skillcell::bench::Samples;
using skillcell::bench::Timeline;
using skillcell::process::ChildProcess;

struct Options : skillcell::bench::ProcessRun {
    Options() : ProcessRun{30, 3, 2, SKILLCELL_BINARY} {}
};

// The skills every component process offers.
const std::vector<std::string> kSkills = {"CartesianLinearMoveSkillType=Move",
                                          "GraspGripperSkillType=Grasp"};

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

    std::string error;
    auto rig = DetectionRig::start(kSkills.size(), &error);
    if (!rig) {
        std::fprintf(stderr, "mDNS: %s\n", error.c_str());
        return 1;
    }
    Timeline& timeline = rig->timeline();

    Samples ready, announced, detected, afterReady, goodbye, killed;
    const std::string log = (tmp / "server.log").string();
    // Run 0 warms up: it creates the certificate the others reuse, and fills the caches.
    for (int i = 0; i <= o.count; ++i) {
        const std::string name = "bench-" + std::to_string(i);
        const auto argv = skillcell::bench::serverArgv(o.skillcell, "urn:skillcell:bench-component",
                                                       name, tmp / "pki", o.ttl, kSkills);
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
    rig.reset();
    std::filesystem::remove_all(tmp);

    std::printf(
        "skill detection over %d component process starts (2 no-op skills each; loopback, "
        "private network namespace)\n",
        o.count);
    std::printf("  %-38s %9s %9s %9s %5s\n", "ms", "median", "p99", "max", "n");
    skillcell::bench::printLatencyRow("start -> READY (listening)", ready);
    skillcell::bench::printLatencyRow("start -> mDNS announced", announced);
    skillcell::bench::printLatencyRow("start -> skills in the SkillDetector", detected);
    skillcell::bench::printLatencyRow("READY -> skills in the SkillDetector", afterReady);
    skillcell::bench::printLatencyRow("SIGTERM -> skills gone", goodbye);
    skillcell::bench::printLatencyRow("kill -9 -> skills gone", killed);
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
    CLI::App app{
        "From a component process's start to its skills in a SkillDetector, and from "
        "its stop or kill to their removal. Run it inside "
        "tests/netns/run_in_private_netns.sh."};
    skillcell::bench::addProcessRunOptions(app, o);
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    o.killed = std::min(o.killed, o.count);
    spdlog::set_level(spdlog::level::warn);
    return run(o);
}
