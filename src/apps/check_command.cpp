// `skillcell check URL`: the conformance checker (docs/conformance.md). Connects to any OPC
// UA server, checks that every skill it offers follows the skill model, prints one line per
// check (PASS / WARN / FAIL, the skill's browse path, expected versus found) and a summary.
// Exit code: 0 all passed, 1 a check failed, 2 usage or connection error.
#include <asio/co_spawn.hpp>
#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <chrono>
#include <csignal>
#include <exception>
#include <iostream>
#include <memory>
#include <string>

#include "client_security_options.hpp"
#include "commands.hpp"
#include "skills/conformance_checker.hpp"
#include "ua/client/client.hpp"

namespace skillcell::apps {

namespace {

struct CheckCommandOptions {
    std::string url;
    std::string start = "i=85";
    bool exercise = false;
    bool json = false;
    bool failuresOnly = false;
    bool strict = false;
    int connectTimeoutMs = 2000;
    int requestTimeoutMs = 5000;
    int eventTimeoutMs = 3000;
    int runTimeoutMs = 10000;
    std::size_t maxObjects = 20'000;
    ClientSecurityOptions security;
};

asio::awaitable<void> check(ua::Client& client, const CheckCommandOptions& options,
                            skills::CheckOptions checkOptions, skills::ConformanceReport& report,
                            int& exitCode) {
    auto config = commandClientConfig(options.security, "skillcell check");
    if (!config) {
        exitCode = 2;
        co_return;
    }
    config->connectTimeout = std::chrono::milliseconds(options.connectTimeoutMs);
    config->requestTimeout = std::chrono::milliseconds(options.requestTimeoutMs);
    config->sessionName = "skillcell conformance check";
    const std::string url = options.url;
    if (const auto s = co_await client.connect(url, std::move(*config)); s.isBad()) {
        std::cerr << "cannot connect to " << options.url << ": " << explainConnectFailure(s)
                  << "\n";
        exitCode = 2;
        co_return;
    }
    co_await skills::checkConformance(client, std::move(checkOptions), report);
    (void)co_await client.disconnect();
    exitCode = report.exitCode(options.strict);
}

int runCheck(const CheckCommandOptions& options) {
    auto start = ua::NodeId::parse(options.start);
    if (!start) {
        std::cerr << "invalid --start node id '" << options.start
                  << "' (expected e.g. i=85 or ns=2;s=Cell)\n";
        return 2;
    }
    skills::CheckOptions checkOptions;
    checkOptions.start = *start;
    checkOptions.exercise = options.exercise;
    checkOptions.eventTimeout = std::chrono::milliseconds(options.eventTimeoutMs);
    checkOptions.runTimeout = std::chrono::milliseconds(options.runTimeoutMs);
    checkOptions.maxObjects = options.maxObjects;

    skills::ConformanceReport report(options.url);
    if (!options.json) {
        std::cout << "skillcell check " << options.url
                  << (options.exercise ? " (static checks, then --exercise)" : " (static checks)")
                  << std::endl;
        report.setListener([&options](const skills::Finding& f) {
            if (options.failuresOnly && f.verdict == skills::Verdict::Pass) return;
            std::cout << skills::formatFinding(f) << std::endl;  // flushed: runs can be long
        });
    }

    asio::io_context io(1);
    ua::Client client(io.get_executor());
    // Ctrl-C during --exercise must not leave a skill Halted or Running: the first signal
    // asks the check to stop after the step under way (the skill is put back in Ready),
    // a second one quits at once.
    asio::signal_set signals(io, SIGINT, SIGTERM);
    bool stopRequested = false;
    signals.async_wait([&](const asio::error_code& ec, int) {
        if (ec) return;
        stopRequested = true;
        std::cerr << "stopping after the current step (the skill is left in Ready); again to "
                     "quit at once\n";
        signals.async_wait([&io](const asio::error_code& again, int) {
            if (!again) io.stop();
        });
    });
    checkOptions.stopRequested = [&stopRequested] { return stopRequested; };
    int exitCode = 2;
    bool crashed = false;
    asio::co_spawn(io, check(client, options, std::move(checkOptions), report, exitCode),
                   [&crashed, &signals](const std::exception_ptr& e) {
                       crashed = e != nullptr;
                       signals.cancel();  // the last work: io.run() returns
                   });
    io.run();
    if (crashed) {
        std::cerr << "the check stopped on an internal error\n";
        return 2;
    }
    if (exitCode == 2) return 2;  // no connection: no report
    if (options.json) {
        std::cout << skills::toJson(report, options.strict);
    } else {
        std::cout << skills::formatSummary(report, options.strict) << std::endl;
    }
    return exitCode;
}

}  // namespace

Command addCheckCommand(CLI::App& app) {
    auto options = std::make_shared<CheckCommandOptions>();
    CLI::App* cmd = app.add_subcommand(
        "check",
        "Check that the skills of an OPC UA server follow the skillcell skill model: skill "
        "types, mandatory children, parameter data types and ranges, CurrentState and "
        "LastTransition, events; with --exercise also the state machine (methods refused "
        "in the wrong state, transitions and their events). Prints one line per check "
        "(PASS/WARN/FAIL, the skill's browse path, expected vs found) and a summary. Exit "
        "code 0 when nothing failed, 1 when a check failed, 2 on usage or connection errors. "
        "See docs/conformance.md.");
    cmd->add_option("url", options->url, "server endpoint, e.g. opc.tcp://localhost:4840")
        ->required();
    cmd->add_flag("--exercise", options->exercise,
                  "also drive every skill through its state machine: Halt, Reset, Start with "
                  "its current parameters (this runs the skill: only on a cell where that is "
                  "safe); the skill is left in Ready");
    cmd->add_option("--timeout", options->runTimeoutMs,
                    "--exercise: milliseconds a run (Start to Ready or Halted) may take")
        ->check(CLI::Range(1, 3'600'000))
        ->capture_default_str();
    cmd->add_option("--event-timeout", options->eventTimeoutMs,
                    "--exercise: milliseconds to wait for a transition event")
        ->check(CLI::Range(1, 600'000))
        ->capture_default_str();
    cmd->add_option("--connect-timeout", options->connectTimeoutMs,
                    "milliseconds to connect (TCP and Hello)")
        ->check(CLI::Range(1, 600'000))
        ->capture_default_str();
    cmd->add_option("--request-timeout", options->requestTimeoutMs,
                    "milliseconds each request may take")
        ->check(CLI::Range(1, 600'000))
        ->capture_default_str();
    cmd->add_option("--start", options->start,
                    "node below which skills are searched (forward hierarchical references)")
        ->capture_default_str();
    cmd->add_option("--max-objects", options->maxObjects,
                    "objects visited at most while searching for skills")
        ->check(CLI::Range(1, 10'000'000))
        ->capture_default_str();
    cmd->add_flag("--json", options->json, "print the report as one JSON document at the end");
    cmd->add_flag("-q,--failures-only", options->failuresOnly,
                  "print only WARN and FAIL lines (and the summary)");
    cmd->add_flag("--strict", options->strict, "count warnings as failures (exit code 1)");
    addClientSecurityOptions(cmd, options->security);
    return {cmd, [options] { return runCheck(*options); }};
}

}  // namespace skillcell::apps
