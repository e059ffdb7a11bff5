#include "server_process.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>
#include <asio.hpp>
#include <iostream>

#include "skill_report.hpp"
#include "skills/skill_detector.hpp"
#include "ua/discovery/network_interfaces.hpp"
#include "ua/pki/own_certificate.hpp"

namespace skillcell::apps {

void addServerProcessOptions(CLI::App* cmd, ServerProcessOptions& o) {
    cmd->add_option("--port,-p", o.port, "OPC UA TCP port (0: any free port)")
        ->capture_default_str();
    cmd->add_option("--host", o.host, "address to listen on")->capture_default_str();
    cmd->add_option("--advertised-host", o.advertisedHost,
                    "host name put into endpoint URLs (default: the name the client used)");
    cmd->add_option("--application-uri", o.applicationUri, "the server's ApplicationUri")
        ->capture_default_str();
    cmd->add_option("--pki-dir", o.pkiDir,
                    "PKI directory (own/, trusted/, rejected/, issuers/); the application "
                    "certificate is created there on first start (default: $SKILLCELL_PKI_DIR, "
                    "else ~/.local/share/skillcell/pki/<application URI>)");
    cmd->add_option("--max-sessions", o.maxSessions, "session limit")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    cmd->add_option("--max-channels", o.maxChannels, "connection limit")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    cmd->add_flag("--detect", o.detect,
                  "detect the skills of every component discovery finds (this one included) "
                  "and print SKILL ADDED/REMOVED lines on stdout, and SNAPSHOT..END on exit");
}

int runServerProcess(const ServerProcessOptions& options, const PopulateServer& populate) {
    asio::io_context io{1};  // one thread runs it: no scheduler locking needed
    ua::ServerConfig config;
    config.bindAddress = options.host;
    config.description.port = options.port;
    config.description.applicationUri = options.applicationUri;
    config.description.applicationName = options.applicationName;
    config.description.applicationType = options.applicationType;
    if (!options.advertisedHost.empty()) {
        config.description.advertisedHost = options.advertisedHost;
    } else if (options.host != "0.0.0.0" && options.host != "::") {
        config.description.advertisedHost = options.host;
    }
    config.limits.maxSessions = options.maxSessions;
    config.limits.maxChannels = options.maxChannels;

    std::string error;
    const auto pkiDir = options.pkiDir.empty()
                            ? ua::pki::defaultPkiDirectory(options.applicationUri)
                            : std::filesystem::path(options.pkiDir);
    ua::pki::CertificateSubject subject;
    subject.applicationUri = options.applicationUri;
    subject.commonName = options.applicationName;
    char hostname[256] = {};
    if (gethostname(hostname, sizeof hostname - 1) == 0) subject.dnsNames.emplace_back(hostname);
    subject.dnsNames.emplace_back("localhost");
    for (const auto& nic : ua::mdns::listIpv4Interfaces()) {
        subject.ipAddresses.push_back(ua::mdns::toString(nic.address));
    }
    auto certificate = ua::pki::loadOrCreateOwnCertificate(pkiDir, subject, &error);
    if (!certificate) {
        spdlog::critical("application certificate in {}: {}", pkiDir.string(), error);
        return 1;
    }
    spdlog::info("{} application certificate {}", certificate->created ? "created" : "using",
                 certificate->certificateFile.string());
    config.description.certificate = certificate->der;

    auto server = ua::Server::create(io, config, &error);
    if (!server) {
        spdlog::critical("cannot build the server: {}", error);
        return 1;
    }
    ComponentContent content;  // after the server: destroyed before it
    if (populate) {
        auto populated = populate(*server, io);
        if (!populated) {
            spdlog::critical("cannot add the component's nodes: {}",
                             ua::statusName(populated.status()));
            return 1;
        }
        content = std::move(*populated);
    }
    auto port = server->listen();
    if (!port) return 1;  // listen() logged why

    std::unique_ptr<ComponentDiscovery> discovery;
    if (options.discovery.enabled || options.isLds) {
        discovery = ComponentDiscovery::start(io, *server, *port, options.host, options.discovery,
                                              options.isLds, &error);
        if (!discovery && options.isLds) {
            spdlog::critical("LDS-ME: {}", error);
            return 1;
        }
        if (!discovery) {
            // Still a working server, reachable by its address; say loudly what is missing.
            spdlog::error("discovery is off: {} (--no-discovery silences this)", error);
        }
    }

    // The skills of the cell, from what discovery finds (and what registers with our LDS).
    std::shared_ptr<skills::SkillDetector> detector;
    std::shared_ptr<ua::lds::ServerWatcher> detectorWatcher;
    if (options.detect && discovery) {
        detector = skills::SkillDetector::create(io.get_executor());
        detector->subscribe(
            [](const skills::SkillEvent& e) { printSkillEvent(std::cout, e, false); });
        detectorWatcher = skills::attachMdns(detector, discovery->responder());
        if (discovery->lds()) skills::attachLds(detector, *discovery->lds());
    } else if (options.detect) {
        spdlog::error("--detect needs discovery: no skills will be detected");
    }

    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const asio::error_code& ec, int signal) {
        if (ec) return;
        spdlog::info("signal {}: shutting down", signal);
        asio::co_spawn(
            io,
            [&]() -> asio::awaitable<void> {
                if (detector) {
                    printSkillSnapshot(std::cout, detector->instances(), false);
                    detectorWatcher->stop();
                    detector->stop();
                }
                if (discovery) co_await discovery->stop();
                server->stop();
                io.stop();
            },
            asio::detached);
    });
    std::cout << "READY opc.tcp://" << server->config().description.advertisedHost << ":" << *port
              << std::endl;  // flushed: scripts wait for this line
    io.run();
    return 0;
}

}  // namespace skillcell::apps
