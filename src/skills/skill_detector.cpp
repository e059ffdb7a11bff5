#include "skills/skill_detector.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <optional>
#include <set>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/discovery/dns_message.hpp"

namespace skillcell::skills {

namespace {

using ua::StatusCode;
namespace status = ua::status;
using asio::experimental::as_tuple;

RemovalReason removalFor(GoneReason reason) {
    switch (reason) {
        case GoneReason::Goodbye:
            return RemovalReason::Goodbye;
        case GoneReason::Unregistered:
            return RemovalReason::Unregistered;
        case GoneReason::Expired:
            break;
    }
    return RemovalReason::Expired;
}

/// A failure that means the component is gone or silent (rather than "the server does not
/// offer subscriptions", which polling replaces).
bool gaveUp(StatusCode s) {
    return s == status::BadTimeout || s == status::BadConnectionClosed ||
           s == status::BadServerNotConnected || s == status::BadSecureChannelClosed ||
           s == status::BadSessionIdInvalid || s == status::BadSessionClosed ||
           s == status::BadRequestCancelledByClient || s == status::BadShutdown;
}

/// What tells one run of a server from another, and what a browse of it starts from.
struct ServerState {
    ua::DateTime startTime;
    std::vector<std::string> namespaces;
};

/// The server's StartTime and NamespaceArray, in one Read: each browse needs both.
asio::awaitable<ua::Result<ServerState>> readServerState(ua::Client& client) {
    ua::ReadRequest req;
    req.timestampsToReturn = ua::TimestampsToReturn::Neither;
    for (const std::uint32_t node :
         {ua::ns0::Server_ServerStatus_StartTime, ua::ns0::Server_NamespaceArray}) {
        ua::ReadValueId id;
        id.nodeId = ua::NodeId(node);
        id.attributeId = static_cast<std::uint32_t>(ua::AttributeId::Value);
        req.nodesToRead.push_back(std::move(id));
    }
    auto resp = co_await client.read(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 2) co_return status::BadUnknownResponse;
    for (const auto& result : resp->results) {
        if (result.statusOrGood().isBad()) co_return result.statusOrGood();
    }
    const auto* time =
        resp->results[0].value ? resp->results[0].value->get<ua::DateTime>() : nullptr;
    if (time == nullptr || !resp->results[1].value) co_return status::BadTypeMismatch;
    co_return ServerState{*time, RemoteSkillBrowser::namespacesOf(*resp->results[1].value)};
}

}  // namespace

/// One component's connection and the coroutine (run) that keeps it. Executor only.
struct SkillDetector::Watch {
    Watch(const asio::any_io_executor& executor, std::string component, std::string key,
          std::string endpoint, RemoteBrowseLimits limits)
        : componentId(std::move(component)),
          urlKey(std::move(key)),
          url(std::move(endpoint)),
          wake(executor),
          browser(limits) {}

    void signal() { wake.cancel(); }

    /// The key and URL of the most recent sighting whose URL is not in `except`.
    [[nodiscard]] std::optional<std::pair<std::string, std::string>> newestSighting(
        const std::set<std::string>& except) const {
        const std::pair<const std::string, Sighting>* newest = nullptr;
        for (const auto& entry : sightings) {
            if (except.contains(entry.second.url)) continue;
            if (newest == nullptr || entry.second.seq > newest->second.seq) newest = &entry;
        }
        if (newest == nullptr) return std::nullopt;
        return std::make_pair(newest->first, newest->second.url);
    }

    struct Sighting {
        std::string url;
        std::uint64_t seq = 0;  // larger: more recent
        // The source's GetEndpoints answer from that URL, for the next connect only: a
        // connection that failed or ended asks the server itself next time.
        std::vector<ua::EndpointDescription> endpoints;
    };

    std::string componentId;
    std::shared_ptr<TurnWaiter> turnWaiter;     // while it waits for a turn
    std::map<std::string, Sighting> sightings;  // source key -> what it said last
    std::uint64_t sightingSeq = 0;
    std::string urlKey;  // the sighting whose URL we use
    std::string url;     // where to connect next
    std::string applicationUri;
    bool ended = false;              // gone or stopped: the coroutine only cleans up
    bool recheck = false;            // seen again, or StartTime changed: compare StartTime
    bool moved = false;              // url changed: reconnect there
    bool busy = false;               // inside connect or a browse (ending it aborts them)
    bool connected = false;          // browsed and watched: the current URL works
    StatusCode lost = status::Good;  // the keep-alive subscription reported a loss
    asio::steady_timer wake;         // cancelled to wake the coroutine
    std::unique_ptr<ua::Client> client;
    RemoteSkillBrowser browser;
    ua::DateTime startTime;         // of the server the skills were browsed from
    std::uint64_t browses = 0;      // complete browses, over every connection
    std::uint64_t connections = 0;  // connection attempts: callbacks of older ones are ignored
};

bool SkillInstance::isA(const GlobalNodeId& type) const {
    return std::any_of(types.begin(), types.end(), [&](const auto& t) { return t.id == type; });
}

std::string_view toString(RemovalReason reason) {
    switch (reason) {
        case RemovalReason::Goodbye:
            return "goodbye";
        case RemovalReason::Expired:
            return "expired";
        case RemovalReason::Unregistered:
            return "unregistered";
        case RemovalReason::Disconnected:
            return "disconnected";
        case RemovalReason::Timeout:
            return "timeout";
        case RemovalReason::Restarted:
            return "restarted";
    }
    return "unknown";
}

std::shared_ptr<SkillDetector> SkillDetector::create(asio::any_io_executor executor,
                                                     SkillDetectorConfig config) {
    return std::shared_ptr<SkillDetector>(
        new SkillDetector(std::move(executor), std::move(config)));
}

SkillDetector::SkillDetector(asio::any_io_executor executor, SkillDetectorConfig config)
    : executor_(std::move(executor)), config_(std::move(config)) {}

SkillDetector::~SkillDetector() = default;

void SkillDetector::appeared(const std::string& key, const ua::ApplicationDescription& application,
                             const std::string& discoveryUrl,
                             std::vector<ua::EndpointDescription> endpoints) {
    if (stopped_ || discoveryUrl.empty()) return;
    // The application URI identifies a server (OPC 10000-4, 7.1): two sources that list the
    // same server make one component.
    const std::string id =
        application.applicationUri.empty() ? "key:" + key : application.applicationUri;
    if (auto k = keys_.find(key); k != keys_.end() && k->second != id) {
        dropSighting(key, RemovalReason::Restarted);  // another server answers there now
    }
    keys_[key] = id;
    std::shared_ptr<Watch>& watch = components_[id];
    if (!watch) {
        watch = std::make_shared<Watch>(executor_, id, key, discoveryUrl, config_.limits);
        watch->applicationUri = application.applicationUri;
        watch->sightings[key] = {discoveryUrl, ++watch->sightingSeq, std::move(endpoints)};
        setStatus(id, [&](ComponentStatus& s) {
            s.state = ComponentStatus::State::Connecting;
            s.endpointUrl = discoveryUrl;
        });
        asio::co_spawn(executor_, run(watch), asio::detached);
        return;
    }
    Watch& w = *watch;
    w.sightings[key] = {discoveryUrl, ++w.sightingSeq, std::move(endpoints)};
    if (discoveryUrl != w.url && (key == w.urlKey || !w.connected)) {
        // The server moved (restarted at another address or port), or the address in use
        // does not work: the newest word counts.
        w.urlKey = key;
        w.url = discoveryUrl;
        w.moved = true;
        if (w.busy && w.client) w.client->abort();
    } else {
        w.recheck = true;  // announced again: restarted? (StartTime tells)
    }
    w.signal();
}

void SkillDetector::gone(const std::string& key, GoneReason reason) {
    if (stopped_) return;
    dropSighting(key, removalFor(reason));
}

void SkillDetector::dropSighting(const std::string& key, RemovalReason reason) {
    auto k = keys_.find(key);
    if (k == keys_.end()) return;
    const std::string id = k->second;
    keys_.erase(k);
    auto c = components_.find(id);
    if (c == components_.end()) return;
    Watch& w = *c->second;
    w.sightings.erase(key);
    if (w.sightings.empty()) {
        endWatch(w);
        components_.erase(c);
        replaceSkills(id, {}, reason);
        ComponentEvent event;
        event.forgotten = true;
        event.reason = reason;
        {
            std::lock_guard lock(mutex_);
            auto st = status_.find(id);
            if (st != status_.end()) {
                event.status = std::move(st->second);
                status_.erase(st);
            }
        }
        event.status.id = id;
        notifyComponent(event);
        return;
    }
    if (w.urlKey == key) {
        auto newest = w.newestSighting({});
        w.urlKey = newest->first;
        if (newest->second != w.url) {
            w.url = newest->second;
            w.moved = true;
            if (w.busy && w.client) w.client->abort();
            w.signal();
        }
    }
}

void SkillDetector::endWatch(Watch& w) {
    w.ended = true;
    if (w.turnWaiter) w.turnWaiter->timer.cancel();  // its run() leaves the queue
    // A connection in the middle of something is cut; an idle one says goodbye (run()).
    if (w.busy && w.client) w.client->abort();
    w.signal();
}

void SkillDetector::stop() {
    if (stopped_) return;
    stopped_ = true;
    for (auto& [id, watch] : components_) endWatch(*watch);
    components_.clear();
    keys_.clear();
    listeners_.clear();
    componentListeners_.clear();
    std::lock_guard lock(mutex_);
    instances_.clear();
    snapshot_.reset();
    byType_.clear();
    status_.clear();
}

asio::awaitable<void> SkillDetector::shutdown(std::chrono::milliseconds grace) {
    auto self = shared_from_this();
    std::vector<std::weak_ptr<Watch>> watches;
    for (const auto& [id, watch] : components_) watches.push_back(watch);
    stop();
    for (int round = 0; round < 2 && running_ > 0; ++round) {
        if (round == 1) {
            spdlog::debug("skill detector: {} connection(s) still closing after {} ms: cut",
                          running_, grace.count());
            for (const auto& weak : watches) {
                if (auto w = weak.lock(); w && w->client) w->client->abort();
            }
        }
        drained_.emplace(executor_);
        drained_->expires_after(grace);
        co_await drained_->async_wait(as_tuple(asio::use_awaitable));
    }
    drained_.reset();
}

asio::awaitable<bool> SkillDetector::takeTurn(Watch& w) {
    const std::size_t turns = std::max<std::size_t>(1, config_.maxConcurrentConnects);
    if (turnsTaken_ < turns && turnQueue_.empty()) {
        ++turnsTaken_;
        co_return true;
    }
    setStatus(w.componentId, [](ComponentStatus& s) { s.state = ComponentStatus::State::Waiting; });
    auto waiter = std::make_shared<TurnWaiter>(executor_);
    waiter->timer.expires_at(asio::steady_timer::time_point::max());
    turnQueue_.push_back(waiter);
    w.turnWaiter = waiter;
    co_await waiter->timer.async_wait(as_tuple(asio::use_awaitable));
    w.turnWaiter.reset();
    if (!waiter->granted) {  // ended while it waited: out of the queue
        std::erase(turnQueue_, waiter);
        co_return false;
    }
    if (w.ended) {
        giveTurn();
        co_return false;
    }
    co_return true;
}

void SkillDetector::giveTurn() {
    // Handed straight to the oldest waiter: the count stays, so that nobody overtakes it.
    if (turnQueue_.empty()) {
        --turnsTaken_;
        return;
    }
    auto next = std::move(turnQueue_.front());
    turnQueue_.pop_front();
    next->granted = true;
    next->timer.cancel();
}

asio::awaitable<void> SkillDetector::run(std::shared_ptr<Watch> w) {
    auto self = shared_from_this();  // alive while this runs
    // Counted for shutdown(); the guard also counts a frame destroyed without finishing.
    struct Running {
        SkillDetector& detector;
        explicit Running(SkillDetector& d) : detector(d) { ++detector.running_; }
        Running(const Running&) = delete;
        Running& operator=(const Running&) = delete;
        ~Running() {
            if (--detector.running_ == 0 && detector.drained_) detector.drained_->cancel();
        }
    } running(*this);
    auto delay = config_.retryDelay;
    std::set<std::string> tried;  // addresses that failed since the last back-off
    while (!w->ended) {
        // One turn for the connect and the first browse (serve() gives it back then), or
        // until this attempt fails.
        if (!co_await takeTurn(*w)) break;
        Turn turn(*this);
        w->moved = false;
        w->recheck = false;
        w->lost = status::Good;
        const std::string url = w->url;
        setStatus(w->componentId, [&](ComponentStatus& s) {
            s.state = ComponentStatus::State::Connecting;
            s.endpointUrl = url;
        });
        w->client = std::make_unique<ua::Client>(executor_);
        ++w->connections;
        ua::ClientConfig cc;
        cc.connectTimeout = config_.connectTimeout;
        cc.requestTimeout = config_.requestTimeout;
        cc.applicationUri = config_.applicationUri;
        cc.applicationName = "skillcell skill detector";
        cc.sessionName = "skill detector";
        cc.security = config_.security;
        if (auto sighting = w->sightings.find(w->urlKey);
            sighting != w->sightings.end() && sighting->second.url == url) {
            cc.endpoints = std::move(sighting->second.endpoints);
            sighting->second.endpoints.clear();
        }
        // The keep-alive subscription keeps the session busy; a detector that vanished
        // leaves its session behind only this long.
        cc.sessionTimeoutMs = 30'000;
        w->busy = true;
        StatusCode s = co_await w->client->connect(url, cc);
        w->busy = false;
        const std::uint64_t browsesBefore = w->browses;
        if (s.isGood() && !w->ended && !w->moved) s = co_await serve(w, turn);
        turn.giveBack();
        w->connected = false;
        const bool browsed = w->browses != browsesBefore;
        if (w->ended) break;
        w->client->abort();
        // The connection is over, and the skills with it: the next connection browses again.
        const RemovalReason reason = w->moved                  ? RemovalReason::Restarted
                                     : s == status::BadTimeout ? RemovalReason::Timeout
                                                               : RemovalReason::Disconnected;
        replaceSkills(w->componentId, {}, reason);
        setStatus(w->componentId, [&](ComponentStatus& st) {
            st.state = ComponentStatus::State::Unreachable;
            st.lastError = s.isBad() ? s : StatusCode(status::BadConnectionClosed);
            st.skills = 0;
        });
        if (w->moved) {
            delay = config_.retryDelay;
            continue;
        }
        // Every address the sources gave is tried, newest first, before backing off (a
        // restarted server may have a new one; two sources may disagree).
        tried.insert(w->url);
        if (auto untried = w->newestSighting(tried)) {
            w->urlKey = untried->first;
            w->url = untried->second;
            continue;
        }
        tried.clear();
        if (auto newest = w->newestSighting({})) {
            w->urlKey = newest->first;
            w->url = newest->second;
        }
        if (browsed) {
            delay = config_.retryDelay;  // it worked a while: start backing off anew
            tried.clear();
        }
        spdlog::debug("skill detector: {} at {}: {}, again in {} ms", w->componentId, url,
                      ua::statusName(s), delay.count());
        if (!w->recheck) {
            w->wake.expires_after(delay);
            co_await w->wake.async_wait(as_tuple(asio::use_awaitable));
            delay = std::min(delay * 2, config_.maxRetryDelay);
        }
    }
    if (w->client) {
        // Ended from outside while idle: close the session politely (bounded by the request
        // timeout); otherwise endWatch() has cut the connection already.
        if (w->client->isConnected()) co_await w->client->disconnect();
        w->client.reset();
    }
}

asio::awaitable<StatusCode> SkillDetector::serve(const std::shared_ptr<Watch>& w, Turn& turn) {
    ua::Client& client = *w->client;
    w->busy = true;
    auto state = co_await readServerState(client);
    if (!state) {
        w->busy = false;
        co_return state.status();
    }
    if (w->ended || w->moved) {
        w->busy = false;
        co_return status::Good;
    }
    if (state->startTime != w->startTime) w->browser.forgetTypes();  // another run of the server
    StatusCode s = co_await browseInto(w, state->startTime, std::move(state->namespaces),
                                       RemovalReason::Restarted);
    if (s.isBad() || w->ended || w->moved) {
        w->busy = false;
        co_return s;
    }

    // Liveness: keep-alives at least every keepAlivePeriod (the client's watchdog reports a
    // silence as BadTimeout, a lost connection with its status), and StartTime monitored.
    // Callbacks are named before co_await: GCC 12 destroys a closure temporary inside a
    // co_await expression twice (see ua::ClientConfig).
    const std::weak_ptr<Watch> weak = w;
    // Published every interval when StartTime changes; a keep-alive every keepAlivePeriod
    // otherwise (a whole number of intervals); the lifetime the standard's 3 keep-alives.
    const auto interval = std::min(config_.publishingInterval, config_.keepAlivePeriod);
    const auto keepAliveCount = static_cast<std::uint32_t>(std::max<std::int64_t>(
        1, config_.keepAlivePeriod.count() / std::max<std::int64_t>(1, interval.count())));
    const auto period = static_cast<double>(interval.count());
    const ua::SubscriptionSettings settings(period, std::max<std::uint32_t>(10, 3 * keepAliveCount),
                                            keepAliveCount);
    const std::uint64_t connection = w->connections;
    ua::Subscription::StatusCallback onStatus = [weak, connection](StatusCode st) {
        auto watch = weak.lock();
        if (!watch || st.isGood() || watch->connections != connection) return;
        if (st == status::BadMessageNotAvailable) {
            watch->recheck = true;  // a StartTime change may be among what was lost
        } else if (watch->lost.isGood()) {
            watch->lost = st;
        }
        watch->signal();
    };
    auto subscription = co_await client.createSubscription(settings, std::move(onStatus));
    bool polling = !subscription;
    if (subscription) {
        ua::Subscription::DataChangeCallback onStartTime = [weak,
                                                            connection](const ua::DataValue& dv) {
            auto watch = weak.lock();
            const auto* t = dv.value ? dv.value->get<ua::DateTime>() : nullptr;
            if (!watch || watch->connections != connection || t == nullptr ||
                *t == watch->startTime)
                return;
            watch->recheck = true;
            watch->signal();
        };
        const ua::NodeId startTime(ua::ns0::Server_ServerStatus_StartTime);
        const std::optional<ua::DataChangeFilter> noFilter;
        auto item = co_await (*subscription)
                        ->monitorDataChange(startTime, ua::AttributeId::Value, period, 1, noFilter,
                                            std::move(onStartTime));
        if (!item && gaveUp(item.status())) {
            w->busy = false;
            co_return item.status();
        }
        polling = !item;
    } else if (gaveUp(subscription.status())) {
        w->busy = false;
        co_return subscription.status();
    }
    w->busy = false;
    if (polling) {
        spdlog::debug("skill detector: {} offers no subscription; polling StartTime",
                      w->componentId);
    }
    w->connected = true;
    turn.giveBack();  // browsed and watched: the next component's turn
    setStatus(w->componentId,
              [](ComponentStatus& st) { st.state = ComponentStatus::State::Connected; });

    while (true) {
        if (w->ended || w->moved) co_return status::Good;
        if (w->lost.isBad()) co_return w->lost;
        if (w->recheck) {
            w->recheck = false;
            w->busy = true;
            auto now = co_await readServerState(client);
            if (!now) {
                w->busy = false;
                co_return now.status();
            }
            if (!w->ended && !w->moved && now->startTime != w->startTime) {
                spdlog::info("skill detector: {} restarted, browsing it again", w->componentId);
                w->browser.forgetTypes();
                s = co_await browseInto(w, now->startTime, std::move(now->namespaces),
                                        RemovalReason::Restarted);
                if (s.isBad()) {
                    w->busy = false;
                    co_return s;
                }
            }
            w->busy = false;
            continue;
        }
        if (polling) {
            w->wake.expires_after(config_.keepAlivePeriod);
        } else {
            w->wake.expires_at(asio::steady_timer::time_point::max());
        }
        auto [ec] = co_await w->wake.async_wait(as_tuple(asio::use_awaitable));
        if (!ec && polling) w->recheck = true;  // time to ask again: alive? restarted?
    }
}

asio::awaitable<StatusCode> SkillDetector::browseInto(const std::shared_ptr<Watch>& w,
                                                      ua::DateTime startTime,
                                                      std::vector<std::string> namespaces,
                                                      RemovalReason reason) {
    const auto requestsBefore = w->client->requestsSent();
    auto skills = co_await w->browser.browse(*w->client, std::move(namespaces));
    if (!skills) {
        spdlog::warn("skill detector: browsing {} at {} failed: {}", w->componentId,
                     w->client->endpointUrl(), ua::statusName(skills.status()));
        co_return skills.status();
    }
    spdlog::debug(
        "skill detector: {} has {} skill(s), browsed in {} request(s) after the "
        "connection's {}",
        w->componentId, skills->size(), w->client->requestsSent() - requestsBefore, requestsBefore);
    if (w->ended || w->moved) co_return status::Good;
    std::string applicationUri = w->applicationUri;
    const auto& endpoints = w->client->serverEndpoints();
    if (!endpoints.empty() && !endpoints.front().server.applicationUri.empty())
        applicationUri = endpoints.front().server.applicationUri;
    if (applicationUri.empty()) applicationUri = w->componentId;
    std::vector<SkillInstance> next;
    next.reserve(skills->size());
    for (auto& skill : *skills) {
        SkillInstance instance;
        static_cast<RemoteSkill&>(instance) = std::move(skill);
        instance.componentUri = applicationUri;
        instance.endpointUrl = w->client->endpointUrl();
        instance.componentStartTime = startTime;
        next.push_back(std::move(instance));
    }
    w->startTime = startTime;
    ++w->browses;
    const std::size_t count = next.size();
    replaceSkills(w->componentId, std::move(next), reason);
    setStatus(w->componentId, [&](ComponentStatus& s) {
        s.endpointUrl = w->client->endpointUrl();
        s.lastError = status::Good;
        s.startTime = startTime;
        s.skills = count;
        ++s.browses;
    });
    co_return status::Good;
}

void SkillDetector::replaceSkills(const std::string& componentId, std::vector<SkillInstance> next,
                                  RemovalReason reason) {
    std::vector<SkillEvent> events;
    {
        std::lock_guard lock(mutex_);
        const auto erase = [&](std::map<InstanceKey, SkillInstance>::iterator it) {
            for (const auto& t : it->second.types) {
                auto byType = byType_.find(t.id);
                if (byType == byType_.end()) continue;
                byType->second.erase(it->first);
                if (byType->second.empty()) byType_.erase(byType);
            }
            return instances_.erase(it);
        };
        auto it = instances_.lower_bound(InstanceKey(componentId, ua::NodeId()));
        while (it != instances_.end() && it->first.first == componentId) {
            auto same = std::find_if(next.begin(), next.end(), [&](const SkillInstance& n) {
                return n.nodeId == it->first.second;
            });
            if (same != next.end() && *same == it->second) {
                next.erase(same);  // unchanged: no event
                ++it;
                continue;
            }
            events.push_back({SkillEvent::Kind::Removed, it->second, reason});
            it = erase(it);
        }
        for (auto& instance : next) {
            if (instance.types.empty()) continue;
            InstanceKey key(componentId, instance.nodeId);
            for (const auto& t : instance.types) byType_[t.id].insert(key);
            events.push_back({SkillEvent::Kind::Added, instance, reason});
            instances_.insert_or_assign(std::move(key), std::move(instance));
        }
        if (!events.empty()) snapshot_.reset();
    }
    notify(events);
}

void SkillDetector::setStatus(const std::string& componentId,
                              const std::function<void(ComponentStatus&)>& f) {
    ComponentEvent event;
    {
        std::lock_guard lock(mutex_);
        ComponentStatus& s = status_[componentId];
        s.id = componentId;
        f(s);
        if (componentListeners_.empty()) return;
        event.status = s;
    }
    notifyComponent(event);
}

void SkillDetector::notifyComponent(const ComponentEvent& event) {
    std::vector<std::size_t> ids;
    ids.reserve(componentListeners_.size());
    for (const auto& [id, listener] : componentListeners_) ids.push_back(id);
    for (const std::size_t id : ids) {
        auto it = componentListeners_.find(id);  // a listener may unsubscribe another
        if (it == componentListeners_.end()) continue;
        const ComponentListener listener = it->second;  // and itself, while it runs
        listener(event);
    }
}

void SkillDetector::notify(const std::vector<SkillEvent>& events) {
    for (const auto& event : events) {
        std::vector<std::size_t> ids;
        ids.reserve(listeners_.size());
        for (const auto& [id, listener] : listeners_) ids.push_back(id);
        for (const std::size_t id : ids) {
            auto it = listeners_.find(id);  // a listener may unsubscribe another
            if (it == listeners_.end()) continue;
            const Listener listener = it->second;  // and itself, while it runs
            listener(event);
        }
    }
}

std::size_t SkillDetector::subscribe(Listener listener) {
    const std::size_t id = nextListener_++;
    for (auto& instance : instances()) {
        SkillEvent event;
        event.instance = std::move(instance);
        listener(event);
    }
    listeners_.emplace(id, std::move(listener));
    return id;
}

std::size_t SkillDetector::subscribeComponents(ComponentListener listener) {
    const std::size_t id = nextListener_++;
    for (auto& status : components()) {
        ComponentEvent event;
        event.status = std::move(status);
        listener(event);
    }
    componentListeners_.emplace(id, std::move(listener));
    return id;
}

void SkillDetector::unsubscribe(std::size_t id) {
    listeners_.erase(id);
    componentListeners_.erase(id);
}

std::vector<SkillInstance> SkillDetector::find(const GlobalNodeId& type) const {
    std::lock_guard lock(mutex_);
    std::vector<SkillInstance> out;
    auto it = byType_.find(type);
    if (it == byType_.end()) return out;
    out.reserve(it->second.size());
    for (const auto& key : it->second) out.push_back(instances_.at(key));
    return out;
}

std::vector<SkillInstance> SkillDetector::instances() const {
    return *snapshot();
}

std::shared_ptr<const std::vector<SkillInstance>> SkillDetector::snapshot() const {
    std::lock_guard lock(mutex_);
    if (!snapshot_) {
        std::vector<SkillInstance> all;
        all.reserve(instances_.size());
        for (const auto& [key, instance] : instances_) all.push_back(instance);
        snapshot_ = std::make_shared<const std::vector<SkillInstance>>(std::move(all));
    }
    return snapshot_;
}

std::vector<ComponentStatus> SkillDetector::components() const {
    std::lock_guard lock(mutex_);
    std::vector<ComponentStatus> out;
    out.reserve(status_.size());
    for (const auto& [id, s] : status_) out.push_back(s);
    return out;
}

// --- Sources -------------------------------------------------------------------------------

std::shared_ptr<ua::lds::ServerWatcher> attachMdns(
    const std::shared_ptr<SkillDetector>& detector,
    std::shared_ptr<ua::mdns::MdnsResponder> responder, const std::string& itself) {
    const std::weak_ptr<SkillDetector> weak = detector;
    ua::lds::ServerWatcher::Callbacks callbacks;
    const std::string self = itself.empty() ? std::string() : ua::mdns::foldCase(itself);
    callbacks.announced = [weak, self](const ua::lds::AnnouncedServer& s) {
        const std::string name = ua::mdns::foldCase(s.instance.name);
        if (name == self) return;
        if (auto d = weak.lock()) {
            d->appeared("mdns:" + name, s.application, s.discoveryUrl, s.endpoints);
        }
    };
    callbacks.gone = [weak](const ua::lds::AnnouncedServer& s, ua::mdns::RemovalReason why) {
        if (auto d = weak.lock())
            d->gone("mdns:" + ua::mdns::foldCase(s.instance.name),
                    why == ua::mdns::RemovalReason::Goodbye ? GoneReason::Goodbye
                                                            : GoneReason::Expired);
    };
    auto watcher =
        ua::lds::ServerWatcher::create(detector->executor(), std::move(responder), callbacks);
    watcher->start();
    return watcher;
}

namespace {

std::string opcTcpUrl(const std::vector<std::string>& urls) {
    for (const auto& url : urls) {
        if (ua::mdns::foldCase(url).starts_with("opc.tcp://")) return url;
    }
    return {};
}

ua::ApplicationDescription describe(const ua::RegisteredServer& s) {
    ua::ApplicationDescription app;
    app.applicationUri = s.serverUri;
    app.productUri = s.productUri;
    if (!s.serverNames.empty()) app.applicationName = s.serverNames.front();
    app.applicationType = s.serverType;
    app.gatewayServerUri = s.gatewayServerUri;
    app.discoveryUrls = s.discoveryUrls;
    return app;
}

}  // namespace

void attachLds(const std::shared_ptr<SkillDetector>& detector, ua::lds::LocalDiscoveryServer& lds) {
    const std::weak_ptr<SkillDetector> weak = detector;
    lds.setRegistrationObserver(
        [weak](ua::lds::RegistrationChange change, const ua::RegisteredServer& s) {
            auto d = weak.lock();
            if (!d) return;
            const std::string key = "lds:" + s.serverUri;
            switch (change) {
                case ua::lds::RegistrationChange::Registered:
                    d->appeared(key, describe(s), opcTcpUrl(s.discoveryUrls));
                    break;
                case ua::lds::RegistrationChange::Unregistered:
                    d->gone(key, GoneReason::Unregistered);
                    break;
                case ua::lds::RegistrationChange::Expired:
                    d->gone(key, GoneReason::Expired);
                    break;
            }
        });
    for (const auto& app : lds.registrations().describe({}, {})) {
        detector->appeared("lds:" + app.applicationUri, app, opcTcpUrl(app.discoveryUrls));
    }
}

}  // namespace skillcell::skills
