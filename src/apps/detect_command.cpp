// `skillcell detect`: the skills on the network, as a SkillDetector sees them. It listens to
// mDNS (like `skillcell discover`), connects to every announced server, browses it for
// skills and keeps watching it.
//
// Output (stdout, flushed; logs go to stderr), in the format of skill_report.hpp:
//   --watch:   WATCHING, then SKILL ADDED / SKILL REMOVED lines as skills come and go
//   at the end (after --duration, or on SIGINT/SIGTERM): SNAPSHOT <n>, n SKILL lines, END
//   --json:    the same as one JSON object per line
#include <spdlog/spdlog.h>

#include <asio.hpp>
#include <iostream>
#include <utility>

#include "client_security_options.hpp"
#include "commands.hpp"
#include "component_discovery.hpp"
#include "skill_report.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::apps {

namespace {

struct DetectOptions {
    bool watch = false;
    double durationSeconds = 3;
    bool json = false;
    double connectTimeoutSeconds = 2;
    double keepAliveSeconds = 5;
    std::size_t maxConnects = skills::SkillDetectorConfig{}.maxConcurrentConnects;
    DiscoveryOptions discovery;
    ClientSecurityOptions security;
};

int runDetect(const DetectOptions& o) {
    asio::io_context io{1};
    std::string error;
    auto responder =
        ua::mdns::MdnsResponder::create(io.get_executor(), mdnsConfigFrom(o.discovery), &error);
    if (!responder) {
        std::cerr << "cannot listen to mDNS: " << error << "\n";
        return 1;
    }
    auto client = commandClientConfig(o.security, "skillcell detect");
    if (!client) return 2;
    skills::SkillDetectorConfig config;
    config.applicationUri = client->applicationUri;
    config.security = client->security;
    config.connectTimeout =
        std::chrono::milliseconds(static_cast<long>(o.connectTimeoutSeconds * 1000));
    config.keepAlivePeriod =
        std::chrono::milliseconds(static_cast<long>(o.keepAliveSeconds * 1000));
    config.maxConcurrentConnects = o.maxConnects;
    auto detector = skills::SkillDetector::create(io.get_executor(), config);
    if (o.watch) {
        detector->subscribe(
            [json = o.json](const skills::SkillEvent& e) { printSkillEvent(std::cout, e, json); });
    }
    (*responder)->start();
    auto watcher = skills::attachMdns(detector, *responder);
    if (o.watch && !o.json) std::cout << "WATCHING" << std::endl;

    bool finishing = false;
    auto finish = [&] {
        if (std::exchange(finishing, true)) return;
        printSkillSnapshot(std::cout, detector->instances(), o.json);
        watcher->stop();
        asio::co_spawn(
            io,
            [&]() -> asio::awaitable<void> {
                co_await detector->shutdown(std::chrono::seconds(1));
                (*responder)->shutdown();
                io.stop();
            },
            asio::detached);
    };
    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const asio::error_code& ec, int) {
        if (!ec) finish();
    });
    asio::steady_timer deadline(io);
    if (!o.watch || o.durationSeconds > 0) {
        deadline.expires_after(
            std::chrono::milliseconds(static_cast<long>(o.durationSeconds * 1000)));
        deadline.async_wait([&](const asio::error_code& ec) {
            if (!ec) finish();
        });
    }
    io.run();
    return 0;
}

}  // namespace

Command addDetectCommand(CLI::App& app) {
    auto o = std::make_shared<DetectOptions>();
    o->discovery.queryPeriodSeconds = 5;
    CLI::App* cmd = app.add_subcommand(
        "detect",
        "Show the skills offered on the network: every server mDNS announces is browsed for "
        "objects of a SkillType subtype and watched (SkillDetector). Prints SKILL ADDED / SKILL "
        "REMOVED lines with --watch, and the skills known at the end.");
    cmd->add_flag("--watch", o->watch, "print SKILL ADDED/REMOVED lines as skills come and go");
    cmd->add_option("--duration", o->durationSeconds,
                    "seconds to run (with --watch, 0: until SIGINT/SIGTERM)")
        ->check(CLI::Range(0.0, 86400.0))
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "one JSON object per line instead of text");
    cmd->add_option("--connect-timeout", o->connectTimeoutSeconds,
                    "seconds to wait for a server to accept a connection")
        ->check(CLI::Range(0.05, 60.0))
        ->capture_default_str();
    cmd->add_option("--keep-alive", o->keepAliveSeconds,
                    "a connected server must be heard from this often (1.5 times as long "
                    "without a word: its skills are removed)")
        ->check(CLI::Range(0.05, 600.0))
        ->capture_default_str();
    cmd->add_option("--max-connects", o->maxConnects,
                    "servers connected to and browsed at once; the others wait their turn")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    addListenerOptions(cmd, o->discovery);
    addClientSecurityOptions(cmd, o->security);
    return {cmd, [o] { return runDetect(*o); }};
}

}  // namespace skillcell::apps
