// `skillcell server`: a demo OPC UA server (namespace 0, the Server object, a Demo object
// with variables and a method). Prints "READY opc.tcp://HOST:PORT" on stdout once it
// accepts connections, so scripts wait for that line instead of sleeping.
#include <spdlog/spdlog.h>

#include <asio.hpp>
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "demo_nodes.hpp"
#include "ua/server/server.hpp"

namespace skillcell::apps {

namespace {

struct ServerOptions {
    std::uint16_t port = 4840;
    std::string host = "0.0.0.0";
    std::string advertisedHost;
    std::string applicationUri = "urn:skillcell:server";
    std::uint32_t maxSessions = 100;
    std::uint32_t maxChannels = 100;
};

int runServer(const ServerOptions& options) {
    asio::io_context io{1};  // one thread runs it: no scheduler locking needed
    ua::ServerConfig config;
    config.bindAddress = options.host;
    config.description.port = options.port;
    config.description.applicationUri = options.applicationUri;
    config.description.applicationName = "skillcell demo server";
    if (!options.advertisedHost.empty()) {
        config.description.advertisedHost = options.advertisedHost;
    } else if (options.host != "0.0.0.0" && options.host != "::") {
        config.description.advertisedHost = options.host;
    }
    config.limits.maxSessions = options.maxSessions;
    config.limits.maxChannels = options.maxChannels;

    std::string error;
    auto server = ua::Server::create(io, config, &error);
    if (!server) {
        spdlog::critical("cannot build the server: {}", error);
        return 1;
    }
    auto fireDemoEvent = [&server](const ua::NodeId& source, ua::String message) {
        ua::Event event;
        event.sourceNode = source;
        event.message = {"", std::move(message)};
        event.severity = 500;
        server->fireEvent(std::move(event));
    };
    if (const auto s = addDemoNodes(server->addressSpace(), fireDemoEvent); s.isBad()) {
        spdlog::critical("cannot add the demo nodes: {}", ua::statusName(s));
        return 1;
    }
    auto port = server->listen();
    if (!port) return 1;  // listen() logged why

    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const asio::error_code& ec, int signal) {
        if (ec) return;
        spdlog::info("signal {}: shutting down", signal);
        server->stop();
        io.stop();
    });
    std::cout << "READY opc.tcp://" << server->config().description.advertisedHost << ":" << *port
              << std::endl;  // flushed: scripts wait for this line
    io.run();
    return 0;
}

}  // namespace

Command addServerCommand(CLI::App& app) {
    auto options = std::make_shared<ServerOptions>();
    CLI::App* cmd = app.add_subcommand(
        "server",
        "Run a demo OPC UA server: namespace 0, the Server object, and Objects/Demo with "
        "variables (Demo.Double, Demo.Int32, Demo.String, Demo.Boolean, Demo.DoubleArray, "
        "Demo.ReadOnly, Demo.Uptime) and a method Demo.Add(a, b). Prints 'READY <url>' on "
        "stdout when it accepts connections.");
    cmd->add_option("--port,-p", options->port, "OPC UA TCP port (0: any free port)")
        ->capture_default_str();
    cmd->add_option("--host", options->host, "address to listen on")->capture_default_str();
    cmd->add_option("--advertised-host", options->advertisedHost,
                    "host name put into endpoint URLs (default: the name the client used)");
    cmd->add_option("--application-uri", options->applicationUri, "the server's ApplicationUri")
        ->capture_default_str();
    cmd->add_option("--max-sessions", options->maxSessions, "session limit")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    cmd->add_option("--max-channels", options->maxChannels, "connection limit")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    return {cmd, [options] { return runServer(*options); }};
}

}  // namespace skillcell::apps
