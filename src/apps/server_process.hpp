#pragma once
// The life of a server process, shared by `skillcell server` and `skillcell lds` (and later
// every component): build the server, let the caller add its nodes, listen, announce and
// register (ComponentDiscovery), print "READY <url>", optionally detect the cell's skills
// (--detect), and on SIGINT/SIGTERM unregister, send the mDNS goodbye and stop.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "component_discovery.hpp"
#include "ua/server/server.hpp"

namespace skillcell::apps {

struct ServerProcessOptions {
    std::uint16_t port = 4840;
    std::string host = "0.0.0.0";
    std::string advertisedHost;
    std::string applicationUri = "urn:skillcell:server";
    std::string applicationName = "skillcell server";
    ua::ApplicationType applicationType = ua::ApplicationType::Server;
    std::uint32_t maxSessions = 100;
    std::uint32_t maxChannels = 100;
    DiscoveryOptions discovery;
    bool isLds = false;
    std::string pkiDir;  // empty: ua::pki::defaultPkiDirectory()
    bool detect = false;  // run a SkillDetector and print its SKILL lines (skill_report.hpp)
};

/// --port, --host, --advertised-host, --application-uri, --pki-dir, --max-sessions,
/// --max-channels, --detect.
void addServerProcessOptions(CLI::App* cmd, ServerProcessOptions& options);

/// Runs until a signal. `populate` adds the component's nodes (may be empty).
int runServerProcess(const ServerProcessOptions& options,
                     const std::function<ua::StatusCode(ua::Server&)>& populate);

}  // namespace skillcell::apps
