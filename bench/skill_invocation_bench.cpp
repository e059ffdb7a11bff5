// skillcell_bench_skill_invocation: the latency of one whole skill invocation as a client
// sees it, for a skill that does nothing (NoOpBehaviour, 0 ms): write a parameter, call
// Start, receive the ReadyToRunning event and then the RunningToReady event (SkillClient).
// The skill machinery's own cost, without a device behind it.
//
//   skillcell_bench_skill_invocation [--count N] [--publishing-interval MS]
//
// In the same run, as the baseline: N sequential Reads (one request round trip) on the same
// connection. Prints median and p99 in microseconds and the ratio to the Read. The server
// sends event notifications at its subscription's publishing interval, so that interval is
// printed too: it bounds the invocation latency from below.
#include <cstdio>
#include <iostream>
#include <map>

#include <spdlog/spdlog.h>

#include "client_thread.hpp"
#include "common/command_line.hpp"
#include "latency_stats.hpp"
#include "running_server.hpp"
#include "skills/noop_behaviour.hpp"
#include "skills/skill_server.hpp"

namespace {

using namespace skillcell;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

struct Options {
    std::size_t count = 500;
    double publishingIntervalMs = 10;  // what SkillClient asks for by default
};

struct Measurement {
    bench::LatencyStats read;
    bench::LatencyStats invocation;
    std::size_t failures = 0;
};

/// One server (with `minPublishingIntervalMs`) and one SkillClient; N Reads, N invocations.
Measurement measure(const Options& options, double minPublishingIntervalMs,
                    double clientIntervalMs) {
    Measurement m;
    auto config = test::RunningServer::defaultConfig();
    config.limits.minPublishingIntervalMs = minPublishingIntervalMs;
    std::unique_ptr<skills::SkillServer> skillServer;
    test::RunningServer server(config, [&](ua::Server& s) {
        skillServer = skills::SkillServer::create(s, s.executor());
        const auto type = skillServer->findSkillType("CartesianLinearMoveSkillType");
        (void)skillServer->add(*type, "Move",
                               std::make_unique<skills::NoOpBehaviour>(s.executor()));
    });
    test::ClientThread t;
    const ua::NodeId skillId(1, ua::String("Skills/Move"));
    skills::SkillClientOptions o;
    o.publishingIntervalMs = clientIntervalMs;
    const auto sc = t.attach(server.url(), skillId, o);
    if (!sc) {
        m.failures = options.count;
        return m;
    }
    const std::size_t warmup = std::min<std::size_t>(50, options.count);
    bench::Samples reads, invocations;
    t.run([&]() -> asio::awaitable<int> {
        const ua::NodeId velocity(1, ua::String("Skills/Move/ParameterSet/MaxVelocity"));
        for (std::size_t i = 0; i < warmup + options.count; ++i) {
            const auto t0 = Clock::now();
            (void)co_await t.client().readValue(velocity);
            if (i >= warmup) reads.push_back(Clock::now() - t0);
        }
        for (std::size_t i = 0; i < warmup + options.count; ++i) {
            const auto t0 = Clock::now();
            std::map<std::string, ua::Variant> parameters;
            parameters.emplace("MaxVelocity", 0.1 + double(i % 10) / 10);
            const auto outcome = co_await sc->run(std::move(parameters), 5s);
            if (!outcome.ok()) ++m.failures;
            if (i >= warmup) invocations.push_back(Clock::now() - t0);
        }
        co_await sc->detach();
        co_return 0;
    });
    server.inServer([&](ua::Server&) {  // skills before the server's io_context
        skillServer.reset();
        return 0;
    });
    m.read = bench::summarize(reads);
    m.invocation = bench::summarize(invocations);
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    CLI::App app{
        "The latency of one whole invocation of a skill that does nothing, as a "
        "SkillClient sees it, beside a Read round trip"};
    app.add_option("--count", options.count, "invocations and Reads")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--publishing-interval", options.publishingIntervalMs,
                   "the publishing interval the SkillClient asks for, in ms")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    spdlog::set_level(spdlog::level::warn);

    std::printf("skill invocation (no-op skill, in-process server, loopback), %zu runs each\n",
                options.count);
    std::size_t failures = 0;
    const double defaultMin = ua::ServerLimits{}.minPublishingIntervalMs;
    for (const double minInterval : {defaultMin, 1.0}) {
        const double asked = minInterval == defaultMin ? options.publishingIntervalMs : 1.0;
        const auto m = measure(options, minInterval, asked);
        failures += m.failures;
        std::printf("\n  server minimum publishing interval %.0f ms%s, SkillClient asks %.0f ms\n",
                    minInterval, minInterval == defaultMin ? " (the default)" : "", asked);
        std::printf("    %-46s median %9.1f us   p99 %9.1f us\n", "Read round trip (baseline)",
                    m.read.medianUs, m.read.p99Us);
        std::printf("    %-46s median %9.1f us   p99 %9.1f us   (%.0fx Read)\n",
                    "write + Start + Running + Ready events", m.invocation.medianUs,
                    m.invocation.p99Us, m.invocation.medianUs / m.read.medianUs);
    }
    std::printf(
        "\n  Events travel in Publish responses, one per publishing interval: the\n"
        "  interval, not the skill machinery, sets the invocation latency.\n"
        "  failed invocations: %zu\n",
        failures);
    return failures == 0 ? 0 : 1;
}
