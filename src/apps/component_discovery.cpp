#include "component_discovery.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace skillcell::apps {

namespace {

std::string defaultMdnsName(const std::string& applicationName, const ua::mdns::Ipv4& address,
                            std::uint16_t port) {
    // Unique on the network without configuration: the address and port are.
    std::string name;
    for (char c : applicationName) name.push_back(c == '.' || c == ' ' ? '-' : c);
    for (std::uint8_t byte : address) name += "-" + std::to_string(byte);
    name += "-" + std::to_string(port);
    if (name.size() > 63) name.erase(0, name.size() - 63);
    return name;
}

}  // namespace

void addListenerOptions(CLI::App* cmd, DiscoveryOptions& o) {
    cmd->add_option("--mdns-query-period", o.queryPeriodSeconds,
                    "longest interval, in seconds, between this component's mDNS queries for "
                    "every OPC UA server: they go out at once, then after 1, 2, 4 ... s up "
                    "to this (RFC 6762 5.2)")
        ->check(CLI::Range(0.1, 3600.0))
        ->capture_default_str();
    cmd->add_option("--mdns-interface", o.interfaces,
                    "network interface for mDNS (repeatable; default: every multicast-capable "
                    "one, loopback only when it is the only one)");
    cmd->add_option("--mdns-ip", o.ipVersions,
                    "IP versions that carry mDNS: 4 (224.0.0.251), 6 (ff02::fb) or both (IPv6 "
                    "where an interface has it)")
        ->check(CLI::IsMember({"4", "6", "both"}))
        ->capture_default_str();
}

void addDiscoveryOptions(CLI::App* cmd, DiscoveryOptions& o, bool registers, bool isLds) {
    if (!isLds) {
        cmd->add_flag("!--no-discovery", o.enabled, "no mDNS announcement and no LDS registration");
    }
    cmd->add_option("--mdns-name", o.mdnsName,
                    "mDNS server name, one DNS label (default: application name, address and "
                    "port)");
    cmd->add_option("--mdns-ttl", o.ttlSeconds,
                    "TTL of our mDNS records in seconds: peers drop us this long after a "
                    "crash or a lost link")
        ->check(CLI::Range(1, 86400))
        ->capture_default_str();
    addListenerOptions(cmd, o);
    cmd->add_option("--caps", o.capabilities,
                    "server capability identifiers to announce (OPC 10000-12 Annex D)");
    if (registers) {
        cmd->add_option("--register-period", o.registerPeriodSeconds,
                        "seconds between re-registrations with each discovered LDS")
            ->check(CLI::Range(1, 86400))
            ->capture_default_str();
    }
    if (isLds) {
        cmd->add_option("--registration-timeout", o.registrationTimeoutSeconds,
                        "seconds after which a registration that was not renewed ends")
            ->check(CLI::Range(1, 86400))
            ->capture_default_str();
    }
}

ua::mdns::MdnsConfig mdnsConfigFrom(const DiscoveryOptions& o) {
    ua::mdns::MdnsConfig c;
    c.recordTtl = std::chrono::seconds(o.ttlSeconds);
    c.queryPeriod = std::chrono::milliseconds(static_cast<long>(o.queryPeriodSeconds * 1000));
    c.interfaces = o.interfaces;
    c.ipv4 = o.ipVersions != "6";
    c.ipv6 = o.ipVersions != "4";
    return c;
}

std::unique_ptr<ComponentDiscovery> ComponentDiscovery::start(
    asio::io_context& io, ua::Server& server, std::uint16_t port, const std::string& bindAddress,
    const DiscoveryOptions& options, bool isLds, const ua::ClientSecurity& registration,
    std::string* error) {
    auto d = std::make_unique<ComponentDiscovery>();
    auto config = mdnsConfigFrom(options);
    if (config.interfaces.empty() && bindAddress != "0.0.0.0" && bindAddress != "::") {
        for (const auto& nic : ua::mdns::listIpv4Interfaces()) {
            if (ua::mdns::toString(nic.address) == bindAddress)
                config.interfaces.push_back(nic.name);
        }
        if (config.interfaces.empty()) {
            if (error != nullptr) *error = "no interface has the address " + bindAddress;
            return nullptr;
        }
    }
    auto responder = ua::mdns::MdnsResponder::create(io.get_executor(), config, error);
    if (!responder) return nullptr;
    d->responder_ = *responder;
    const auto& description = server.config().description;
    const auto address = d->responder_->interfaces().front().address;
    d->mdnsName_ = options.mdnsName.empty()
                       ? defaultMdnsName(description.applicationName, address, port)
                       : options.mdnsName;
    ua::mdns::ServiceAnnouncement announcement;
    announcement.name = d->mdnsName_;
    announcement.port = port;
    announcement.capabilities = options.capabilities;
    if (isLds && std::find(announcement.capabilities.begin(), announcement.capabilities.end(),
                           "LDS") == announcement.capabilities.end()) {
        announcement.capabilities.emplace_back("LDS");
    }
    if (announcement.capabilities.empty()) announcement.capabilities.emplace_back("NA");
    if (ua::mdns::validateServerName(d->mdnsName_).isBad()) {
        if (error != nullptr)
            *error = "bad mDNS name '" + d->mdnsName_ + "': one label of 1..63 bytes, no dots";
        return nullptr;
    }

    if (isLds) {
        ua::lds::LdsConfig ldsConfig;
        ldsConfig.registrationTimeout = std::chrono::seconds(options.registrationTimeoutSeconds);
        d->lds_ = ua::lds::LocalDiscoveryServer::create(server, d->responder_, ldsConfig);
        d->lds_->start(io.get_executor());
    }
    d->responder_->start();
    if (const auto s = d->responder_->announce(announcement); s.isBad()) {
        if (error != nullptr) *error = "cannot announce: " + std::string(ua::statusName(s));
        return nullptr;
    }

    ua::RegisteredServer self;
    self.serverUri = description.applicationUri;
    self.productUri = description.productUri;
    self.serverNames = {ua::LocalizedText{"en", description.applicationName}};
    self.serverType = description.applicationType;
    self.discoveryUrls = {"opc.tcp://" + ua::mdns::toString(address) + ":" + std::to_string(port)};
    ua::MdnsDiscoveryConfiguration mdns;
    mdns.mdnsServerName = d->mdnsName_;
    mdns.serverCapabilities = announcement.capabilities;
    ua::lds::RegistrarConfig rc;
    rc.period = std::chrono::seconds(options.registerPeriodSeconds);
    rc.security = registration;
    d->registrar_ = ua::lds::ServerRegistrar::create(io.get_executor(), d->responder_,
                                                     std::move(self), std::move(mdns), rc);
    d->registrar_->start();
    return d;
}

asio::awaitable<void> ComponentDiscovery::stop() {
    if (registrar_) co_await registrar_->stop();
    if (lds_) lds_->stop();
    if (responder_) responder_->shutdown();
}

}  // namespace skillcell::apps
