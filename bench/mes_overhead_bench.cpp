// skillcell_bench_mes_overhead: the semantic MES's own cost per process step, the time not
// spent inside skills. A process of N steps, each a no-op skill (NoOpBehaviour, 0 ms) on an
// in-process server, runs through ProcessExecutor with a real SkillDetector and a SQLite
// journal on disk; the process description is given directly (the KB's query is a separate
// cost, see skillcell_bench_kb_query).
//
//   skillcell_bench_mes_overhead [--steps N] [--orders K,K,...]
//
// In the same run, as the baseline: N invocations of the same skill through an attached
// SkillClient (write, Start, Running and Ready events), what a step costs at the least. A
// MES step adds choosing the instance, taking its kept session (a read proves it answers),
// reserving the component, reading LastTransition, two journal writes (fsync'd, grouped with
// other orders') and releasing. Prints median and p99 of both, the difference (the overhead)
// and the ratio. Both end on events published every 10 ms: differences below that are within
// the measurement's resolution.
//
// Then concurrent orders (default 1, 10 and 50 at once): K in-process servers, each with a
// no-op Move, and K orders of a 10-step process submitted together. Each order holds the
// component it runs on, so all K run at once, one per component. The baseline there is the
// same load without the MES: K SkillClients on one thread, each invoking its component's skill
// 10 times, all at once. Prints the step time, the baseline's invocation time, the overhead
// per step (median and p99) and orders per second.
#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <map>
#include <random>
#include <vector>

#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>

#include "client_thread.hpp"
#include "common/command_line.hpp"
#include "kb/component_graph.hpp"
#include "latency_stats.hpp"
#include "mes/process_executor.hpp"
#include "noop_component.hpp"

namespace {

using namespace skillcell;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

constexpr const char* kMoveType =
    "http://skillcell.dev/UA/RoboticSkills/CartesianLinearMoveSkillType";

mes::ProcessDescription process(std::size_t steps,
                                std::string iri = "urn:skillcell:bench:process") {
    mes::ProcessDescription p;
    p.iri = std::move(iri);
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

struct OrdersResult {
    bench::LatencyStats steps;
    bench::LatencyStats invocations;  // the baseline at the same concurrency
    double ordersPerSecond = 0;
    // The baseline's: K sequences of `steps` invocations, all at once, per second. The
    // median step hides what the MES costs between and around steps; this does not.
    double baselineOrdersPerSecond = 0;
    std::size_t completed = 0;
};

// K orders of a `steps`-step process at once, on K components (in-process servers), through
// one executor with a journal in `dir`.
OrdersResult concurrentOrders(std::size_t k, std::size_t steps, const fs::path& dir) {
    OrdersResult result;
    std::vector<std::unique_ptr<test::NoOpComponent>> servers;
    for (std::size_t i = 0; i < k; ++i) {
        servers.push_back(std::make_unique<test::NoOpComponent>(
            "urn:skillcell:bench:component" + std::to_string(i), 0ms));
    }
    auto journal = mes::Journal::open((dir / ("orders-" + std::to_string(k) + ".sqlite")).string());
    if (!journal) return result;
    test::ClientThread mesThread;
    auto detector = skills::SkillDetector::create(mesThread.io().get_executor());
    std::promise<void> detected;
    mesThread.run([&]() -> asio::awaitable<int> {
        // The count outside the listener: the detector calls copies of its listeners.
        auto left = std::make_shared<std::size_t>(k);
        detector->subscribe([&detected, left](const skills::SkillEvent& e) {
            if (e.kind == skills::SkillEvent::Kind::Added && *left > 0 && --*left == 0) {
                detected.set_value();
            }
        });
        for (std::size_t i = 0; i < k; ++i) {
            ua::ApplicationDescription app;
            app.applicationUri = "urn:skillcell:bench:component" + std::to_string(i);
            detector->appeared(app.applicationUri, app, servers[i]->url());
        }
        co_return 0;
    });
    if (detected.get_future().wait_for(30s) != std::future_status::ready) return result;
    // The baseline at this concurrency: K SkillClients on one thread, as the MES is, each
    // attached once to its own component and invoking its no-op skill `steps` times, all at
    // once. What K servers and one client thread cost without the MES.
    result.invocations = mesThread.run([&]() -> asio::awaitable<bench::LatencyStats> {
        std::vector<std::unique_ptr<ua::Client>> clients;
        std::vector<std::shared_ptr<skills::SkillClient>> skills;
        for (std::size_t i = 0; i < k; ++i) {
            clients.push_back(std::make_unique<ua::Client>(mesThread.io().get_executor()));
            if ((co_await clients.back()->connect(servers[i]->url())).isBad())
                co_return bench::LatencyStats{};
            auto sc = co_await skills::SkillClient::attach(*clients.back(),
                                                           test::NoOpComponent::moveSkill());
            if (!sc) co_return bench::LatencyStats{};
            skills.push_back(*sc);
        }
        bench::Samples times;
        auto left = std::make_shared<std::size_t>(k);
        asio::steady_timer allDone(mesThread.io(), Clock::time_point::max());
        // The coroutine's state as parameters, which its frame copies (a lambda's captures
        // would dangle once the lambda object is gone).
        auto invoke = [&times, &allDone](
                          std::shared_ptr<skills::SkillClient> sc, std::size_t n,
                          std::shared_ptr<std::size_t> running) -> asio::awaitable<void> {
            for (std::size_t i = 0; i < n; ++i) {
                const auto t0 = Clock::now();
                std::map<std::string, ua::Variant> parameters;
                parameters.emplace("MaxVelocity", 0.1 + double(i % 10) / 10);
                const auto outcome = co_await sc->run(std::move(parameters), 5s);
                if (!outcome.ok()) {
                    std::fprintf(stderr, "baseline invocation: %s %s\n",
                                 std::string(skills::name(outcome.kind)).c_str(),
                                 outcome.reason.c_str());
                }
                times.push_back(Clock::now() - t0);
            }
            if (--*running == 0) allDone.cancel();
        };
        const auto began = Clock::now();
        for (std::size_t i = 0; i < k; ++i) {
            asio::co_spawn(mesThread.io(), invoke(skills[i], steps, left), asio::detached);
        }
        (void)co_await allDone.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        result.baselineOrdersPerSecond =
            static_cast<double>(k) / std::chrono::duration<double>(Clock::now() - began).count();
        skills.clear();
        for (auto& c : clients) (void)co_await c->disconnect();
        co_return bench::summarize(times);
    });
    const auto description = process(steps, "urn:skillcell:bench:orders");
    mes::ProcessReader reader =
        [&description](std::string) -> asio::awaitable<kb::Expected<mes::ProcessDescription>> {
        co_return description;
    };
    auto executor =
        mes::ProcessExecutor::create(detector, **journal, mes::KnowledgeReaders{reader, {}});
    std::map<std::pair<std::int64_t, int>, Clock::time_point> began;
    bench::Samples stepTimes;
    executor->onProgress = [&](const mes::Progress& p) {
        const auto key = std::pair(p.run, p.step);
        if (p.state == "choosing" && !began.contains(key)) began[key] = Clock::now();
        if (p.state == "finished" && began.contains(key)) {
            stepTimes.push_back(Clock::now() - began.at(key));
        }
    };
    const auto t0 = Clock::now();
    result.completed = mesThread.run([&]() -> asio::awaitable<std::size_t> {
        std::vector<std::int64_t> ids;
        for (std::size_t i = 0; i < k; ++i) {
            auto s = executor->submit(description.iri);
            if (s) ids.push_back(s->order);
        }
        std::size_t done = 0;
        for (auto id : ids) done += (co_await executor->outcome(id)).completed ? 1 : 0;
        detector->stop();
        co_return done;
    });
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    result.ordersPerSecond = static_cast<double>(result.completed) / seconds;
    result.steps = bench::summarize(stepTimes);
    return result;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t steps = 200;
    std::vector<std::size_t> orderCounts{1, 10, 50};
    CLI::App app{
        "The semantic MES's own cost per process step on no-op skills, beside a "
        "SkillClient's invocation of the same skill, alone and with K orders at once"};
    app.add_option("--steps", steps, "steps of the process run alone")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--orders", orderCounts, "how many orders at once, comma-separated (1..200)")
        ->delimiter(',')
        ->check(CLI::Range(1, 200))
        ->capture_default_str();
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
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

    test::NoOpComponent server("urn:skillcell:bench:server", 0ms);

    // The baseline: the same skill, invoked through a SkillClient attached once.
    test::ClientThread baselineClient;
    const auto sc = baselineClient.attach(server.url(), test::NoOpComponent::moveSkill());
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
        ua::ApplicationDescription announced;
        announced.applicationUri = "urn:skillcell:bench:server";
        detector->appeared("bench", announced, server.url());
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
                "MES step (choose, reserve, journal, invoke)", mesSteps.medianUs, mesSteps.p99Us,
                mesSteps.n);
    std::printf("  %-52s median %9.1f us   p99 %9.1f us   (%.1fx the invocation)\n",
                "MES overhead (step - invocation)", mesSteps.medianUs - base.medianUs,
                mesSteps.p99Us - base.p99Us, mesSteps.medianUs / base.medianUs);
    std::printf("\n  process %s, failed invocations %zu\n",
                outcome.completed ? "completed" : ("stopped: " + outcome.reason).c_str(), failures);

    constexpr std::size_t kOrderSteps = 10;
    std::printf("\nconcurrent orders (%zu steps each, one no-op component per order)\n\n",
                kOrderSteps);
    std::printf("  %7s  %12s  %12s  %14s  %14s  %14s  %10s  %10s  %5s\n", "orders", "step median",
                "step p99", "invocation med.", "overhead med.", "overhead p99", "orders/s",
                "base o/s", "ratio");
    bool allCompleted = true;
    for (const std::size_t k : orderCounts) {
        const auto r = concurrentOrders(k, kOrderSteps, dir);
        allCompleted = allCompleted && r.completed == k;
        std::printf(
            "  %7zu  %9.1f us  %9.1f us  %12.1f us  %11.1f us  %11.1f us  %10.1f  %10.1f  "
            "%5.2f%s\n",
            k, r.steps.medianUs, r.steps.p99Us, r.invocations.medianUs,
            r.steps.medianUs - r.invocations.medianUs, r.steps.p99Us - r.invocations.medianUs,
            r.ordersPerSecond, r.baselineOrdersPerSecond,
            r.baselineOrdersPerSecond > 0 ? r.ordersPerSecond / r.baselineOrdersPerSecond : 0.0,
            r.completed == k ? "" : "  (not all completed)");
    }
    std::printf(
        "\n  invocation = the no-op skill through K SkillClients at once on one thread, no MES "
        "(the baseline at that concurrency)\n  overhead = step time - that invocation's "
        "median\n  base o/s = the baseline's K sequences of %zu invocations per second; "
        "ratio = orders/s / base o/s\n",
        kOrderSteps);
    return outcome.completed && failures == 0 && mesSteps.n == steps && allCompleted ? 0 : 1;
}
