#include "ua/discovery/server_registrar.hpp"

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/use_awaitable.hpp>

#include "ua/client/client.hpp"

namespace skillcell::ua::lds {

std::shared_ptr<ServerRegistrar> ServerRegistrar::create(
    asio::any_io_executor executor, std::shared_ptr<mdns::MdnsResponder> responder,
    RegisteredServer self, MdnsDiscoveryConfiguration mdns, RegistrarConfig config) {
    return std::shared_ptr<ServerRegistrar>(new ServerRegistrar(
        std::move(executor), std::move(responder), std::move(self), std::move(mdns), config));
}

ServerRegistrar::ServerRegistrar(asio::any_io_executor executor,
                                 std::shared_ptr<mdns::MdnsResponder> responder,
                                 RegisteredServer self, MdnsDiscoveryConfiguration mdns,
                                 RegistrarConfig config)
    : executor_(std::move(executor)),
      responder_(std::move(responder)),
      self_(std::move(self)),
      mdns_(std::move(mdns)),
      config_(config) {}

ServerRegistrar::~ServerRegistrar() {
    if (responder_ && subscription_ != 0) responder_->unsubscribe(subscription_);
}

void ServerRegistrar::start() {
    std::weak_ptr<ServerRegistrar> weak = weak_from_this();
    // LDSes only: on a segment of many servers, browsing for all of them would make every
    // registering server a browser of the whole cell (see MdnsResponder).
    subscription_ = responder_->subscribe(
        [weak](const mdns::ServiceEvent& e) {
            if (auto self = weak.lock()) self->onMdnsEvent(e);
        },
        mdns::BrowseScope::DiscoveryServers);
}

void ServerRegistrar::onMdnsEvent(const mdns::ServiceEvent& e) {
    if (stopped_) return;
    const std::string key = mdns::foldCase(e.instance.name);
    if (key == mdns::foldCase(mdns_.mdnsServerName) ||
        !e.instance.hasCapability(mdns::kLdsCapability)) {
        return;
    }
    auto it = targets_.find(key);
    if (e.kind == mdns::ServiceEvent::Kind::Gone) {
        if (it == targets_.end()) return;
        spdlog::info("LDS '{}' is gone ({}): no longer registered there", e.instance.name,
                     mdns::toString(e.reason));
        it->second.timer->cancel();
        targets_.erase(it);  // its loop sees the generation change and ends
        return;
    }
    const std::string url = e.instance.discoveryUrl();
    if (it != targets_.end() && it->second.url == url) return;  // known, unchanged
    if (it != targets_.end()) it->second.timer->cancel();
    Target t;
    t.url = url;
    t.timer = std::make_shared<asio::steady_timer>(executor_);
    t.generation = nextGeneration_++;
    const auto generation = t.generation;
    targets_[key] = std::move(t);
    asio::co_spawn(executor_, registrationLoop(key, generation), asio::detached);
}

asio::awaitable<void> ServerRegistrar::registrationLoop(std::string key, std::uint64_t generation) {
    auto self = shared_from_this();
    auto current = [&]() -> Target* {
        auto it = targets_.find(key);
        return (it == targets_.end() || it->second.generation != generation || stopped_)
                   ? nullptr
                   : &it->second;
    };
    auto retry = std::chrono::milliseconds(250);
    while (Target* t = current()) {
        const std::string url = t->url;
        const auto timer = t->timer;
        const StatusCode s = co_await sendRegistration(url, true);
        t = current();
        if (t == nullptr) co_return;
        std::chrono::milliseconds wait = config_.period;
        if (s.isGood()) {
            if (!t->registered) spdlog::info("registered with the LDS at {}", url);
            t->registered = true;
            retry = std::chrono::milliseconds(250);
        } else {
            spdlog::warn("registration with the LDS at {} failed: {}", url, statusName(s));
            t->registered = false;
            wait = std::min<std::chrono::milliseconds>(retry, config_.period);
            retry = std::min<std::chrono::milliseconds>(retry * 2, std::chrono::seconds(30));
        }
        timer->expires_after(wait);
        co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    }
}

asio::awaitable<StatusCode> ServerRegistrar::sendRegistration(std::string url, bool online) {
    Client client(executor_);
    // A periodic registration is listed while it runs (also when its coroutine is destroyed
    // suspended), so that stop() can end it.
    struct Listed {
        ServerRegistrar& registrar;
        Client* client;
        bool online;
        Listed(ServerRegistrar& r, Client* c, bool o) : registrar(r), client(c), online(o) {
            if (online) registrar.registering_.insert(client);
        }
        ~Listed() {
            if (!online) return;
            registrar.registering_.erase(client);
            if (registrar.registering_.empty() && registrar.registrationsEnded_) {
                registrar.registrationsEnded_->cancel();
            }
        }
        Listed(const Listed&) = delete;
        Listed& operator=(const Listed&) = delete;
    };
    const Listed listed(*this, &client, online);
    ClientConfig config;
    config.createSession = false;
    config.connectTimeout = config_.timeout;
    config.requestTimeout = config_.timeout;
    config.applicationUri = self_.serverUri;
    config.security = config_.security;
    if (const StatusCode s = co_await client.connect(url, config); s.isBad()) co_return s;
    RegisterServer2Request req;
    req.server = self_;
    req.server.isOnline = online;
    req.discoveryConfiguration.push_back(toExtensionObject(mdns_));
    auto resp = co_await client.request<RegisterServer2Request, RegisterServer2Response>(req);
    StatusCode result = resp.status();
    if (result == status::BadServiceUnsupported) {
        // An LDS without the multicast extension.
        RegisterServerRequest plain;
        plain.server = req.server;
        auto r = co_await client.request<RegisterServerRequest, RegisterServerResponse>(plain);
        result = r.status();
    }
    co_await client.disconnect();
    co_return result;
}

asio::awaitable<void> ServerRegistrar::stop() {
    if (stopped_) co_return;
    stopped_ = true;
    auto self = shared_from_this();
    std::vector<std::string> urls;
    for (auto& [key, t] : targets_) {
        t.timer->cancel();
        if (t.registered) urls.push_back(t.url);
    }
    targets_.clear();
    if (!registering_.empty()) {
        registrationsEnded_ = std::make_shared<asio::steady_timer>(executor_);
        registrationsEnded_->expires_after(config_.timeout);
        const auto ended = registrationsEnded_;
        // A copy: a client's end may come while the list is walked.
        const std::vector<Client*> inFlight(registering_.begin(), registering_.end());
        for (Client* client : inFlight) client->abort();
        co_await ended->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        if (!registering_.empty()) {
            spdlog::warn("{} registration(s) with an LDS still in flight after {} ms",
                         registering_.size(), config_.timeout.count());
        }
    }
    for (const auto& url : urls) {
        const StatusCode s = co_await sendRegistration(url, false);
        if (s.isGood()) {
            spdlog::info("unregistered from the LDS at {}", url);
        } else {
            spdlog::warn("unregistering from the LDS at {} failed: {}", url, statusName(s));
        }
    }
}

std::vector<std::string> ServerRegistrar::registeredWith() const {
    std::vector<std::string> out;
    for (const auto& [key, t] : targets_) {
        if (t.registered) out.push_back(t.url);
    }
    return out;
}

}  // namespace skillcell::ua::lds
