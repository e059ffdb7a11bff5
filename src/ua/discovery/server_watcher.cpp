#include "ua/discovery/server_watcher.hpp"

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include "ua/client/client.hpp"

namespace skillcell::ua::lds {

std::shared_ptr<ServerWatcher> ServerWatcher::create(asio::any_io_executor executor,
                                                     std::shared_ptr<mdns::MdnsResponder> responder,
                                                     Callbacks callbacks,
                                                     std::chrono::milliseconds timeout) {
    return std::shared_ptr<ServerWatcher>(new ServerWatcher(
        std::move(executor), std::move(responder), std::move(callbacks), timeout));
}

ServerWatcher::ServerWatcher(asio::any_io_executor executor,
                             std::shared_ptr<mdns::MdnsResponder> responder, Callbacks callbacks,
                             std::chrono::milliseconds timeout)
    : executor_(std::move(executor)),
      responder_(std::move(responder)),
      callbacks_(std::move(callbacks)),
      timeout_(timeout) {}

ServerWatcher::~ServerWatcher() {
    if (responder_ && subscription_ != 0) responder_->unsubscribe(subscription_);
}

void ServerWatcher::start() {
    std::weak_ptr<ServerWatcher> weak = weak_from_this();
    subscription_ = responder_->subscribe([weak](const mdns::ServiceEvent& e) {
        if (auto self = weak.lock()) self->onMdnsEvent(e);
    });
}

void ServerWatcher::stop() {
    stopped_ = true;
    if (subscription_ != 0) responder_->unsubscribe(subscription_);
    subscription_ = 0;
}

void ServerWatcher::onMdnsEvent(const mdns::ServiceEvent& e) {
    if (stopped_) return;
    const std::string key = mdns::foldCase(e.instance.name);
    auto it = entries_.find(key);
    if (e.kind == mdns::ServiceEvent::Kind::Gone) {
        if (it == entries_.end()) return;
        const Entry gone = std::move(it->second);
        entries_.erase(it);
        if (gone.described && callbacks_.gone) callbacks_.gone(gone.server, e.reason);
        return;
    }
    if (it != entries_.end()) {
        // The cache reports any change of the records, such as another responder naming
        // another SRV target for the same address. What the callbacks report (the URL, the
        // capabilities, the server's description) only changes with the URL or the caps.
        Entry& known = it->second;
        const bool same = known.server.discoveryUrl == e.instance.discoveryUrl() &&
                          known.server.instance.capabilities == e.instance.capabilities;
        if (same && (known.described || known.describing)) {
            known.server.instance = e.instance;
            return;
        }
    }
    Entry& entry = entries_[key];
    entry.generation = nextGeneration_++;
    entry.describing = true;
    ++describesStarted_;
    entry.server.instance = e.instance;
    entry.server.discoveryUrl = e.instance.discoveryUrl();
    asio::co_spawn(executor_, describe(key, entry.generation), asio::detached);
}

asio::awaitable<void> ServerWatcher::describe(std::string key, std::uint64_t generation) {
    auto self = shared_from_this();
    auto current = [&]() -> Entry* {
        auto it = entries_.find(key);
        return (stopped_ || it == entries_.end() || it->second.generation != generation)
                   ? nullptr
                   : &it->second;
    };
    asio::steady_timer backoff(executor_);
    auto delay = std::chrono::milliseconds(100);
    for (int attempt = 0; attempt < 4; ++attempt) {
        Entry* entry = current();
        if (entry == nullptr) co_return;
        const std::string url = entry->server.discoveryUrl;
        Client client(executor_);
        ClientConfig config;
        config.createSession = false;
        config.connectTimeout = timeout_;
        config.requestTimeout = timeout_;
        StatusCode s = co_await client.connect(url, config);
        std::optional<ApplicationDescription> app;
        std::vector<EndpointDescription> described;
        if (s.isGood()) {
            auto endpoints = co_await client.getEndpoints(url);
            if (endpoints && !endpoints->empty()) {
                app = endpoints->front().server;
                described = std::move(*endpoints);
            } else {
                s = endpoints ? status::BadUnknownResponse : endpoints.status();
            }
            co_await client.disconnect();
        }
        entry = current();
        if (entry == nullptr) co_return;
        if (app) {
            if (app->discoveryUrls.empty()) app->discoveryUrls = {url};
            entry->server.application = std::move(*app);
            entry->server.endpoints = std::move(described);
            entry->described = true;
            entry->describing = false;
            if (callbacks_.announced) callbacks_.announced(entry->server);
            co_return;
        }
        spdlog::debug("describing '{}' at {} failed: {}", entry->server.instance.name, url,
                      statusName(s));
        backoff.expires_after(delay);
        delay *= 3;
        co_await backoff.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    }
    if (Entry* entry = current()) {
        entry->describing = false;  // the next announcement tries again
        spdlog::warn("'{}' is announced at {} but does not answer GetEndpoints",
                     entry->server.instance.name, entry->server.discoveryUrl);
    }
}

std::vector<AnnouncedServer> ServerWatcher::servers() const {
    std::vector<AnnouncedServer> out;
    for (const auto& [key, e] : entries_) {
        if (e.described) out.push_back(e.server);
    }
    return out;
}

}  // namespace skillcell::ua::lds
