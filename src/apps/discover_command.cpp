// `skillcell discover`: what discovery sees. Without --lds it listens to mDNS itself (and
// describes each announced server with GetEndpoints); with --lds it asks a Local Discovery
// Server (FindServersOnNetwork, or FindServers with --registered).
//
// Output, one line each (stdout, flushed; logs go to stderr):
//   --watch:       WATCHING, then ANNOUNCED <mdnsName> <url> <applicationUri> caps=<a,b>
//                  and GONE <mdnsName> <goodbye|expired>
//   (default):     SERVER <mdnsName> <url> <applicationUri> caps=<a,b>, after --duration
//   --lds URL:     RECORD <recordId> <serverName> <discoveryUrl> caps=<a,b>
//   --registered:  REGISTERED <applicationUri> <discoveryUrl>...
#include <spdlog/spdlog.h>

#include <asio.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <iostream>

#include "commands.hpp"
#include "component_discovery.hpp"
#include "ua/client/client.hpp"
#include "ua/discovery/server_watcher.hpp"

namespace skillcell::apps {

namespace {

struct DiscoverOptions {
    bool watch = false;
    double durationSeconds = 3;
    std::string lds;
    bool registered = false;
    std::vector<std::string> caps;
    std::uint32_t startingRecordId = 0;
    std::uint32_t maxRecords = 0;
    DiscoveryOptions discovery;
};

std::string joined(const std::vector<std::string>& items) {
    std::string out;
    for (const auto& i : items) out += (out.empty() ? "" : ",") + i;
    return out;
}

std::string describe(const ua::lds::AnnouncedServer& s) {
    return s.instance.name + " " + s.discoveryUrl + " " +
           (s.application.applicationUri.empty() ? "-" : s.application.applicationUri) +
           " caps=" + joined(s.instance.capabilities);
}

asio::awaitable<int> askLds(asio::any_io_executor executor, const DiscoverOptions& o) {
    ua::Client client(executor);
    ua::ClientConfig config;
    config.createSession = false;
    if (const auto s = co_await client.connect(o.lds, config); s.isBad()) {
        std::cerr << "cannot connect to " << o.lds << ": " << ua::statusName(s) << "\n";
        co_return 1;
    }
    int rc = 0;
    if (o.registered) {
        auto servers = co_await client.findServers(o.lds);
        if (!servers) {
            std::cerr << "FindServers failed: " << ua::statusName(servers.status()) << "\n";
            rc = 1;
        } else {
            for (const auto& s : *servers) {
                std::cout << "REGISTERED " << s.applicationUri;
                for (const auto& url : s.discoveryUrls) std::cout << " " << url;
                std::cout << "\n";
            }
        }
    } else {
        ua::FindServersOnNetworkRequest req;
        req.startingRecordId = o.startingRecordId;
        req.maxRecordsToReturn = o.maxRecords;
        req.serverCapabilityFilter = o.caps;
        auto resp =
            co_await client
                .request<ua::FindServersOnNetworkRequest, ua::FindServersOnNetworkResponse>(req);
        if (!resp) {
            std::cerr << "FindServersOnNetwork failed: " << ua::statusName(resp.status()) << "\n";
            rc = 1;
        } else {
            for (const auto& r : resp->servers) {
                std::cout << "RECORD " << r.recordId << " " << r.serverName << " " << r.discoveryUrl
                          << " caps=" << joined(r.serverCapabilities) << "\n";
            }
        }
    }
    std::cout.flush();
    co_await client.disconnect();
    co_return rc;
}

int runDiscover(const DiscoverOptions& o) {
    asio::io_context io{1};
    if (!o.lds.empty()) {
        int rc = 1;
        asio::co_spawn(io, askLds(io.get_executor(), o),
                       [&](std::exception_ptr, int r) { rc = r; });
        io.run();
        return rc;
    }
    std::string error;
    auto responder =
        ua::mdns::MdnsResponder::create(io.get_executor(), mdnsConfigFrom(o.discovery), &error);
    if (!responder) {
        std::cerr << "cannot listen to mDNS: " << error << "\n";
        return 1;
    }
    ua::lds::ServerWatcher::Callbacks callbacks;
    if (o.watch) {
        callbacks.announced = [](const ua::lds::AnnouncedServer& s) {
            std::cout << "ANNOUNCED " << describe(s) << std::endl;
        };
        callbacks.gone = [](const ua::lds::AnnouncedServer& s, ua::mdns::RemovalReason why) {
            std::cout << "GONE " << s.instance.name << " " << ua::mdns::toString(why) << std::endl;
        };
    }
    auto watcher = ua::lds::ServerWatcher::create(io.get_executor(), *responder, callbacks);
    (*responder)->start();
    watcher->start();
    if (o.watch) std::cout << "WATCHING" << std::endl;

    auto finish = [&] {
        watcher->stop();
        (*responder)->shutdown();
        io.stop();
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
            if (ec) return;
            if (!o.watch) {
                for (const auto& s : watcher->servers())
                    std::cout << "SERVER " << describe(s) << "\n";
                std::cout.flush();
            }
            finish();
        });
    }
    io.run();
    return 0;
}

}  // namespace

Command addDiscoverCommand(CLI::App& app) {
    auto o = std::make_shared<DiscoverOptions>();
    o->discovery.queryPeriodSeconds = 5;
    CLI::App* cmd = app.add_subcommand(
        "discover",
        "Show the OPC UA servers on the network: by listening to mDNS (default; --watch for "
        "every change as it happens) or by asking an LDS (--lds URL).");
    cmd->add_flag("--watch", o->watch, "print ANNOUNCED/GONE lines as servers come and go");
    cmd->add_option("--duration", o->durationSeconds,
                    "seconds to listen (with --watch, 0: until SIGINT/SIGTERM)")
        ->check(CLI::Range(0.0, 86400.0))
        ->capture_default_str();
    cmd->add_option("--lds", o->lds, "ask this LDS (opc.tcp://host:port) instead of listening");
    cmd->add_flag("--registered", o->registered,
                  "with --lds: the registered servers (FindServers), not the network's");
    cmd->add_option("--caps", o->caps, "with --lds: only servers with all these capabilities");
    cmd->add_option("--starting-record-id", o->startingRecordId, "with --lds: first record id");
    cmd->add_option("--max-records", o->maxRecords, "with --lds: at most this many (0: all)");
    addListenerOptions(cmd, o->discovery);
    return {cmd, [o] { return runDiscover(*o); }};
}

}  // namespace skillcell::apps
