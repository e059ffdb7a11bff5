#pragma once
// ComponentDiscovery: a component's presence on the network, the same for every skillcell
// component: its mDNS announcement, the LDS services when it is a discovery server, and
// its registration with the LDSs it discovers. Plus the command-line options for it.
#include <CLI/CLI.hpp>
#include <asio/awaitable.hpp>
#include <asio/io_context.hpp>
#include <memory>
#include <string>
#include <vector>

#include "ua/discovery/local_discovery_server.hpp"
#include "ua/discovery/mdns_responder.hpp"
#include "ua/discovery/server_registrar.hpp"
#include "ua/server/server.hpp"

namespace skillcell::apps {

struct DiscoveryOptions {
    bool enabled = true;
    std::string mdnsName;  // empty: derived from the application name, address and port
    int ttlSeconds = 120;
    double queryPeriodSeconds = 3600;
    int registerPeriodSeconds = 600;
    int registrationTimeoutSeconds = 660;
    std::vector<std::string> interfaces;
    std::vector<std::string> capabilities;
    std::string ipVersions = "both";  // "4", "6" or "both"
};

/// Adds --no-discovery, --mdns-name, --mdns-ttl, --mdns-query-period, --mdns-interface,
/// --caps and (for servers that register) --register-period, (for an LDS)
/// --registration-timeout.
void addDiscoveryOptions(CLI::App* cmd, DiscoveryOptions& options, bool registers, bool isLds);
/// Only the options a pure listener needs (--mdns-query-period, --mdns-interface, --mdns-ip).
void addListenerOptions(CLI::App* cmd, DiscoveryOptions& options);
[[nodiscard]] ua::mdns::MdnsConfig mdnsConfigFrom(const DiscoveryOptions& options);

class ComponentDiscovery {
public:
    /// Announces `server` (listening on `port`), installs the LDS services when `isLds`,
    /// and starts registering with discovered LDSs. A server bound to one address announces
    /// on that address's interface only (unless --mdns-interface says otherwise): one bound
    /// to loopback is not announced to the network. `registration`: the channel security of
    /// RegisterServer2 (the server's own certificate). nullptr with `error` set on failure.
    [[nodiscard]] static std::unique_ptr<ComponentDiscovery> start(
        asio::io_context& io, ua::Server& server, std::uint16_t port,
        const std::string& bindAddress, const DiscoveryOptions& options, bool isLds,
        const ua::ClientSecurity& registration, std::string* error);
    /// Unregisters, withdraws the announcement with a goodbye, closes the mDNS socket.
    asio::awaitable<void> stop();

    [[nodiscard]] const std::string& mdnsName() const { return mdnsName_; }
    /// For more listeners on the same mDNS socket (a skill detector).
    [[nodiscard]] const std::shared_ptr<ua::mdns::MdnsResponder>& responder() const {
        return responder_;
    }
    /// The LDS services, when this component is a discovery server; else null.
    [[nodiscard]] const std::shared_ptr<ua::lds::LocalDiscoveryServer>& lds() const { return lds_; }

private:
    std::shared_ptr<ua::mdns::MdnsResponder> responder_;
    std::shared_ptr<ua::lds::LocalDiscoveryServer> lds_;
    std::shared_ptr<ua::lds::ServerRegistrar> registrar_;
    std::string mdnsName_;
};

}  // namespace skillcell::apps
