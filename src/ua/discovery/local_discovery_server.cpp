#include "ua/discovery/local_discovery_server.hpp"

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/ip/address_v4.hpp>
#include <asio/use_awaitable.hpp>

#include "ua/client/client.hpp"
#include "ua/pki/own_certificate.hpp"

namespace skillcell::ua::lds {

namespace {

std::string firstOpcTcpUrl(const RegisteredServer& s) {
    for (const auto& url : s.discoveryUrls) {
        if (mdns::foldCase(url).starts_with("opc.tcp://")) return url;
    }
    return {};
}

}  // namespace

std::shared_ptr<LocalDiscoveryServer> LocalDiscoveryServer::create(
    Server& server, std::shared_ptr<mdns::MdnsResponder> responder, LdsConfig config) {
    return std::shared_ptr<LocalDiscoveryServer>(
        new LocalDiscoveryServer(server, std::move(responder), config));
}

LocalDiscoveryServer::LocalDiscoveryServer(Server& server,
                                           std::shared_ptr<mdns::MdnsResponder> responder,
                                           LdsConfig config)
    : server_(server),
      responder_(std::move(responder)),
      config_(config),
      table_(config_.registrationTimeout, config_.limits),
      directory_(DateTime::now()) {}

namespace {

/// Over a secured channel, a server may register only itself: the serverUri must be the
/// application URI of the certificate the channel was opened with (OPC 10000-4, 5.4.5), or
/// any trusted component could register, or unregister, any other. The certificate itself
/// was validated when the channel opened.
StatusCode checkRegistrant(const ServiceContext& ctx, const RegisteredServer& server) {
    if (ctx.securityMode == MessageSecurityMode::None || ctx.clientCertificate == nullptr) {
        return status::Good;  // a None channel reaches here only on an --insecure LDS
    }
    const std::string uri = pki::certificateApplicationUri(*ctx.clientCertificate);
    if (uri != server.serverUri) {
        spdlog::warn("RegisterServer for {} refused: the channel's certificate names '{}'",
                     server.serverUri, uri);
        return status::BadServerUriInvalid;
    }
    return status::Good;
}

}  // namespace

LocalDiscoveryServer::~LocalDiscoveryServer() {
    if (responder_ && subscription_ != 0) responder_->unsubscribe(subscription_);
}

void LocalDiscoveryServer::start(asio::any_io_executor executor) {
    executor_ = executor;
    std::weak_ptr<LocalDiscoveryServer> weak = weak_from_this();
    auto& table = server_.services();
    using Access = ServiceTable::Access;

    table.add<RegisterServerRequest, RegisterServerResponse>(
        Access::NoSession,
        [weak](ServiceContext& ctx, const RegisterServerRequest& req, RegisterServerResponse&) {
            auto self = weak.lock();
            if (!self || self->stopped_) return status::BadShutdown;
            if (const StatusCode s = checkRegistrant(ctx, req.server); s.isBad()) return s;
            return self->registerServer(req.server, std::nullopt);
        });

    table.add<RegisterServer2Request, RegisterServer2Response>(
        Access::NoSession, [weak](ServiceContext& ctx, const RegisterServer2Request& req,
                                  RegisterServer2Response& resp) {
            auto self = weak.lock();
            if (!self || self->stopped_) return status::BadShutdown;
            if (const StatusCode s = checkRegistrant(ctx, req.server); s.isBad()) return s;
            if (req.discoveryConfiguration.size() > 16) return status::BadTooManyOperations;
            std::optional<MdnsDiscoveryConfiguration> mdns;
            for (const auto& eo : req.discoveryConfiguration) {
                MdnsDiscoveryConfiguration config;
                if (fromExtensionObject(eo, config).isBad()) {
                    // The standard defines no other configuration: not supported, per entry.
                    resp.configurationResults.push_back(status::BadNotSupported);
                    continue;
                }
                const bool nameOk = config.mdnsServerName.empty() ||
                                    mdns::validateServerName(config.mdnsServerName).isGood();
                const bool capsOk =
                    config.serverCapabilities.size() <= 32 &&
                    std::all_of(config.serverCapabilities.begin(), config.serverCapabilities.end(),
                                [](const String& c) {
                                    return !c.empty() && c.size() <= 32 &&
                                           c.find(',') == std::string::npos;
                                });
                if (!nameOk || !capsOk) {
                    resp.configurationResults.push_back(status::BadInvalidArgument);
                    continue;
                }
                resp.configurationResults.push_back(status::Good);
                if (!mdns) mdns = std::move(config);
            }
            return self->registerServer(req.server, std::move(mdns));
        });

    const ServerDescription& description = server_.config().description;
    table.add<FindServersRequest, FindServersResponse>(
        Access::NoSession, [weak, &description](ServiceContext& ctx, const FindServersRequest& req,
                                                FindServersResponse& resp) {
            auto self = weak.lock();
            if (!self) return status::BadShutdown;
            if (auto own = description.findServersEntry(req, ctx.endpointUrl)) {
                resp.servers.push_back(std::move(*own));
            }
            auto others = self->table_.describe(req.serverUris, req.localeIds);
            resp.servers.insert(resp.servers.end(), others.begin(), others.end());
            return status::Good;
        });

    table.add<FindServersOnNetworkRequest, FindServersOnNetworkResponse>(
        Access::NoSession, [weak](ServiceContext&, const FindServersOnNetworkRequest& req,
                                  FindServersOnNetworkResponse& resp) {
            auto self = weak.lock();
            if (!self) return status::BadShutdown;
            if (!self->responder_) return status::BadServiceUnsupported;
            if (req.serverCapabilityFilter.size() > 64) return status::BadTooManyOperations;
            resp.lastCounterResetTime = self->directory_.lastCounterResetTime();
            resp.servers = self->directory_.find(req);
            return status::Good;
        });

    if (responder_) {
        subscription_ = responder_->subscribe([weak](const mdns::ServiceEvent& e) {
            if (auto self = weak.lock()) self->onMdnsEvent(e);
        });
    }
    timer_ = std::make_unique<asio::steady_timer>(executor);
    asio::co_spawn(executor, expiryLoop(), asio::detached);
}

void LocalDiscoveryServer::stop() {
    if (stopped_) return;
    stopped_ = true;
    for (const auto& [uri, name] : announcedFor_) {
        if (responder_) responder_->withdraw(name);
    }
    announcedFor_.clear();
    for (const auto& [uri, t] : graceTimers_) t->cancel();
    graceTimers_.clear();
    if (timer_) timer_->cancel();
}

StatusCode LocalDiscoveryServer::registerServer(const RegisteredServer& server,
                                                std::optional<MdnsDiscoveryConfiguration> mdns) {
    if (const StatusCode s = table_.validate(server); s.isBad()) {
        spdlog::warn("LDS: registration of '{}' refused: {}", server.serverUri, statusName(s));
        return s;
    }
    const bool withMdns = mdns.has_value();
    auto change = table_.apply(server, std::move(mdns), Clock::now());
    if (!change) {
        spdlog::warn("LDS: registration of '{}' refused: {}", server.serverUri,
                     statusName(change.status()));
        return change.status();
    }
    const std::string url = server.discoveryUrls.empty() ? "" : server.discoveryUrls.front();
    switch (*change) {
        case RegisteredServerTable::Change::Added:
        case RegisteredServerTable::Change::Updated: {
            spdlog::info("LDS: {} '{}' at {}{}",
                         *change == RegisteredServerTable::Change::Added ? "registered" : "updated",
                         server.serverUri, url, withMdns ? " (with mDNS)" : "");
            const Registration* r = table_.find(server.serverUri);
            if (r != nullptr && r->mdns) scheduleAnnounceFor(*r);
            if (r != nullptr) notify(RegistrationChange::Registered, r->server);
            break;
        }
        case RegisteredServerTable::Change::Renewed:
            spdlog::debug("LDS: '{}' renewed its registration", server.serverUri);
            break;
        case RegisteredServerTable::Change::Removed:
            spdlog::info("LDS: '{}' unregistered", server.serverUri);
            withdrawFor(server.serverUri);
            notify(RegistrationChange::Unregistered, server);
            break;
        case RegisteredServerTable::Change::NotFound:
            break;
    }
    return status::Good;
}

bool LocalDiscoveryServer::announcesItself(const std::string& mdnsName) const {
    const std::string key = mdns::foldCase(mdnsName);
    const auto services = responder_->services();
    return std::any_of(services.begin(), services.end(), [&](const mdns::ServiceInstance& s) {
        return mdns::foldCase(s.name) == key;
    });
}

void LocalDiscoveryServer::scheduleAnnounceFor(const Registration& r) {
    if (!responder_ || !executor_) return;
    const std::string& uri = r.server.serverUri;
    const std::string name = mdnsNameOf(r);
    if (name.empty() || graceTimers_.contains(uri)) return;  // that timer decides
    if (announcedFor_.contains(uri) || config_.selfAnnouncementGrace.count() <= 0) {
        announceFor(r);
        return;
    }
    if (announcesItself(name)) {
        spdlog::debug("LDS: '{}' announces itself as '{}'", uri, name);
        return;
    }
    auto timer = std::make_shared<asio::steady_timer>(*executor_, config_.selfAnnouncementGrace);
    graceTimers_[uri] = timer;
    responder_->queryNow();  // a server that announces itself answers now
    asio::co_spawn(*executor_, announceAfterGrace(uri, timer), asio::detached);
}

asio::awaitable<void> LocalDiscoveryServer::announceAfterGrace(
    std::string serverUri, std::shared_ptr<asio::steady_timer> timer) {
    auto self = shared_from_this();
    co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    const auto it = graceTimers_.find(serverUri);
    if (stopped_ || it == graceTimers_.end() || it->second != timer) co_return;
    graceTimers_.erase(it);
    // The registration as it is now: it may have been updated or have ended meanwhile.
    if (const Registration* r = table_.find(serverUri); r != nullptr && r->mdns) announceFor(*r);
}

void LocalDiscoveryServer::announceFor(const Registration& r) {
    if (!responder_) return;
    const std::string name = mdnsNameOf(r);
    if (name.empty()) return;
    // A server that announces itself is left to speak for itself.
    const std::string key = mdns::foldCase(name);
    const bool ours = announcedFor_.contains(r.server.serverUri);
    if (!ours && announcesItself(name)) {
        spdlog::debug("LDS: '{}' announces itself as '{}'", r.server.serverUri, name);
        return;
    }
    const std::string url = firstOpcTcpUrl(r.server);
    auto address = parseEndpointUrl(url);
    if (!address) {
        spdlog::info("LDS: '{}' has no opc.tcp discovery URL to announce", r.server.serverUri);
        return;
    }
    mdns::ServiceAnnouncement a;
    a.name = name;
    a.port = address->port;
    a.path = address->path;
    a.capabilities = r.mdns->serverCapabilities;
    asio::error_code ec;
    const auto ip = asio::ip::make_address_v4(address->host, ec);
    // An address literal other than loopback is announced as it is; a host name, or
    // loopback, is this host: an LDS serves the servers on its own host (OPC 10000-12, 4.3).
    if (!ec && !ip.is_loopback()) a.address = ip.to_bytes();
    if (auto previous = announcedFor_.find(r.server.serverUri);
        previous != announcedFor_.end() && mdns::foldCase(previous->second) != key) {
        responder_->withdraw(previous->second);
    }
    if (const StatusCode s = responder_->announce(a); s.isBad()) {
        spdlog::warn("LDS: cannot announce '{}' for '{}': {}", name, r.server.serverUri,
                     statusName(s));
        return;
    }
    announcedFor_[r.server.serverUri] = name;
}

void LocalDiscoveryServer::withdrawFor(const std::string& serverUri) {
    if (auto t = graceTimers_.find(serverUri); t != graceTimers_.end()) {
        t->second->cancel();
        graceTimers_.erase(t);
    }
    auto it = announcedFor_.find(serverUri);
    if (it == announcedFor_.end()) return;
    if (responder_) responder_->withdraw(it->second);
    announcedFor_.erase(it);
}

void LocalDiscoveryServer::onMdnsEvent(const mdns::ServiceEvent& e) {
    directory_.apply(e);
    if (e.kind != mdns::ServiceEvent::Kind::Gone || stopped_) return;
    const Registration* r = table_.findByMdnsName(e.instance.name);
    if (r == nullptr || announcedFor_.contains(r->server.serverUri)) return;
    const RegisteredServer ended = r->server;
    spdlog::info("LDS: registration of '{}' ends with its mDNS presence ({})", ended.serverUri,
                 mdns::toString(e.reason));
    table_.remove(ended.serverUri);
    notify(e.reason == mdns::RemovalReason::Goodbye ? RegistrationChange::Unregistered
                                                    : RegistrationChange::Expired,
           ended);
}

void LocalDiscoveryServer::notify(RegistrationChange change, const RegisteredServer& server) const {
    if (observer_) observer_(change, server);
}

asio::awaitable<void> LocalDiscoveryServer::expiryLoop() {
    auto self = shared_from_this();
    while (!stopped_) {
        for (const auto& r : table_.expire(Clock::now())) {
            spdlog::info("LDS: registration of '{}' expired", r.server.serverUri);
            withdrawFor(r.server.serverUri);
            notify(RegistrationChange::Expired, r.server);
        }
        timer_->expires_after(std::chrono::seconds(1));
        co_await timer_->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    }
}

}  // namespace skillcell::ua::lds
