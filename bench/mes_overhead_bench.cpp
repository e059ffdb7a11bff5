// skillcell_bench_mes_overhead: the semantic MES's own cost per process step, the time not
// spent inside skills. A process of N steps, each a no-op skill (NoOpBehaviour, 0 ms) on an
// in-process server, runs through ProcessExecutor with a real SkillDetector and a SQLite
// journal on disk; the process description is given directly (the KB's query is a separate
// cost, see skillcell_bench_kb_query).
//
//   skillcell_bench_mes_overhead [--steps N]
//
// In the same run, as the baseline: N invocations of the same skill through an attached
// SkillClient (write, Start, Running and Ready events), what a step costs at the least. A
// MES step adds choosing the instance, a session and attach per step, reading LastTransition,
// two journal writes (fsync'd) and closing. Prints median and p99 of both, the difference
// (the overhead) and the ratio.
#include <spdlog/spdlog.h>

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <map>
#include <random>
#include <string_view>

#include "client_thread.hpp"
#include "kb/component_graph.hpp"
#include "latency_stats.hpp"
#include "mes/process_executor.hpp"
#include "running_server.hpp"
#include "skills/noop_behaviour.hpp"
#include "skills/skill_server.hpp"

namespace {

using namespace skillcell;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

constexpr const char* kMoveType =
    "http://skillcell.dev/UA/RoboticSkills/CartesianLinearMoveSkillType";

bool parse(int argc, char** argv, std::size_t& steps) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view a = argv[i];
        if (a == "--steps" && i + 1 < argc) {
            const std::string_view v = argv[++i];
            if (std::from_chars(v.data(), v.data() + v.size(), steps).ec == std::errc{} &&
                steps > 0) {
                continue;
            }
        }
        std::cerr << "usage: skillcell_bench_mes_overhead [--steps N]\n";
        return false;
    }
    return true;
}

mes::ProcessDescription process(std::size_t steps) {
    mes::ProcessDescription p;
    p.iri = "urn:skillcell:bench:process";
    for (std::size_t i = 1; i <= steps; ++i) {
        mes::ProcessStep s;
        s.iri = p.iri + "#step" + std::to_string(i);
        s.index = static_cast<int>(i);
        s.skillTypeIri = kMoveType;
        s.parameters.push_back({"MaxVelocity", 0.1 + double(i % 10) / 10});
        p.steps.push_back(std::move(s));
    }
    return p;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t steps = 200;
    if (!parse(argc, argv, steps)) return 2;
    spdlog::set_level(spdlog::level::warn);
    std::random_device rd;
    const fs::path dir =
        fs::temp_directory_path() / ("skillcell-mes-bench-" + std::to_string(rd()));
    fs::create_directories(dir);
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{dir};

    std::unique_ptr<skills::SkillServer> skillServer;
    test::RunningServer server(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
        skillServer = skills::SkillServer::create(s, s.executor());
        const auto type = skillServer->findSkillType("CartesianLinearMoveSkillType");
        (void)skillServer->add(*type, "Move",
                               std::make_unique<skills::NoOpBehaviour>(s.executor()));
    });

    // The baseline: the same skill, invoked through a SkillClient attached once.
    test::ClientThread baselineClient;
    const auto sc = baselineClient.attach(server.url(), ua::NodeId(1, ua::String("Skills/Move")));
    if (!sc) {
        std::fprintf(stderr, "cannot attach to the no-op skill\n");
        return 1;
    }
    bench::Samples invocations;
    std::size_t failures = 0;
    baselineClient.run([&]() -> asio::awaitable<int> {
        for (std::size_t i = 0; i < steps + 20; ++i) {
            const auto t0 = Clock::now();
            std::map<std::string, ua::Variant> parameters;
            parameters.emplace("MaxVelocity", 0.1 + double(i % 10) / 10);
            const auto outcome = co_await sc->run(std::move(parameters), 5s);
            if (!outcome.ok()) ++failures;
            if (i >= 20) invocations.push_back(Clock::now() - t0);  // 20 to warm up
        }
        co_return 0;
    });

    // The MES: a detector told of the server, a journal on disk, the process given directly.
    test::ClientThread mesThread;  // its io_context is the MES's executor
    auto journal = mes::Journal::open((dir / "journal.sqlite").string());
    if (!journal) {
        std::fprintf(stderr, "%s\n", journal.error().c_str());
        return 1;
    }
    auto detector = skills::SkillDetector::create(mesThread.io().get_executor());
    std::promise<void> detected;
    mesThread.run([&]() -> asio::awaitable<int> {
        detector->subscribe([&detected, done = false](const skills::SkillEvent& e) mutable {
            if (!done && e.kind == skills::SkillEvent::Kind::Added) {
                done = true;
                detected.set_value();
            }
        });
        ua::ApplicationDescription app;
        app.applicationUri = "urn:skillcell:bench:server";
        detector->appeared("bench", app, server.url());
        co_return 0;
    });
    if (detected.get_future().wait_for(10s) != std::future_status::ready) {
        std::fprintf(stderr, "the detector did not find the no-op skill\n");
        return 1;
    }
    const auto description = process(steps);
    mes::ProcessReader reader =
        [&description](std::string) -> asio::awaitable<kb::Expected<mes::ProcessDescription>> {
        co_return description;
    };
    // No fact reader: the benchmark's steps have no requirements.
    auto executor =
        mes::ProcessExecutor::create(detector, **journal, mes::KnowledgeReaders{reader, {}});
    std::map<int, Clock::time_point> began;
    bench::Samples stepTimes;
    executor->onProgress = [&](const mes::Progress& p) {
        if (p.state == "choosing" && !began.contains(p.step)) began[p.step] = Clock::now();
        if (p.state == "finished") stepTimes.push_back(Clock::now() - began.at(p.step));
    };
    const mes::ProcessOutcome outcome =
        mesThread.run([&]() -> asio::awaitable<mes::ProcessOutcome> {
            auto o = co_await executor->execute(description.iri);
            detector->stop();
            co_return o;
        });
    server.inServer([&](ua::Server&) {
        skillServer.reset();
        return 0;
    });

    const auto base = bench::summarize(invocations);
    const auto mesSteps = bench::summarize(stepTimes);
    std::printf(
        "semantic MES, overhead per step (no-op skill, in-process server, loopback, "
        "journal on %s)\n\n",
        dir.string().c_str());
    std::printf("  %-52s median %9.1f us   p99 %9.1f us   (n=%zu)\n",
                "skill invocation through a SkillClient (baseline)", base.medianUs, base.p99Us,
                base.n);
    std::printf("  %-52s median %9.1f us   p99 %9.1f us   (n=%zu)\n",
                "MES step (choose, connect, attach, journal, invoke)", mesSteps.medianUs,
                mesSteps.p99Us, mesSteps.n);
    std::printf("  %-52s median %9.1f us   p99 %9.1f us   (%.1fx the invocation)\n",
                "MES overhead (step - invocation)", mesSteps.medianUs - base.medianUs,
                mesSteps.p99Us - base.p99Us, mesSteps.medianUs / base.medianUs);
    std::printf("\n  process %s, failed invocations %zu\n",
                outcome.completed ? "completed" : ("stopped: " + outcome.reason).c_str(), failures);
    return outcome.completed && failures == 0 && mesSteps.n == steps ? 0 : 1;
}
