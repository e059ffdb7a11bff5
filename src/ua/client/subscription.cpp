// Client side of subscriptions: the publish loop of a Client (SubscriptionEngine), the
// Subscription's services, and Client::createSubscription. The behaviour on timeouts, gaps
// and lost sessions is described in README.md.
#include "ua/client/subscription.hpp"

#include <algorithm>
#include <exception>
#include <limits>
#include <utility>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/client/client.hpp"
#include "ua/transport/no_throw.hpp"

namespace skillcell::ua {

namespace {

using Clock = std::chrono::steady_clock;

/// Publish requests kept at the server while subscriptions exist: one can be answered
/// while the next is already waiting there, so no publishing interval is lost in transit.
constexpr int kOutstandingPublishes = 2;
/// Missing sequence numbers asked for again per detected gap, and remembered at most.
constexpr std::uint32_t kMaxRepublishPerGap = 8;
constexpr std::size_t kMaxMissing = 64;
/// Publish failures in a row that are neither timeouts nor known conditions before the
/// subscriptions are given up (a server answering garbage would otherwise keep us busy).
constexpr unsigned kMaxConsecutiveErrors = 5;
/// The watchdog allows a keep-alive period times this, plus the slack below, between two
/// responses for a subscription: delivery and scheduling take time too.
constexpr double kWatchdogFactor = 1.5;
constexpr std::chrono::milliseconds kWatchdogSlack{100};

/// Statuses after which the session (and so every subscription in it) is gone.
bool isSessionLost(StatusCode s) {
    for (StatusCode lost :
         {status::BadSessionIdInvalid, status::BadSessionClosed, status::BadSessionNotActivated,
          status::BadConnectionClosed, status::BadSecureChannelClosed,
          status::BadSecureChannelIdInvalid, status::BadServerNotConnected,
          status::BadCommunicationError, status::BadShutdown, status::BadServerHalted,
          status::BadNoCommunication}) {
        if (s == lost) return true;
    }
    return false;
}

/// The sequence number after `n`: they run 1..2^32-1, then start again at 1 (0 is never
/// used, OPC 10000-4 7.21).
std::uint32_t nextSequenceNumber(std::uint32_t n) {
    return n == std::numeric_limits<std::uint32_t>::max() ? 1 : n + 1;
}

/// How many steps `seq` lies after `last`; 0 when it does not lie after it (a repeat or an
/// older message), judged within half the number space as for any wrapping counter.
std::uint32_t stepsAfter(std::uint32_t last, std::uint32_t seq) {
    const std::uint32_t forward = seq - last;
    if (forward == 0 || forward >= 0x80000000u) return 0;
    return seq < last ? forward - 1 : forward;  // a wrap skipped 0
}

template <class F, class... Args>
void invokeCallback(const F& f, const Args&... args) {
    if (!f) return;
    // A callback is user code: whatever it throws must not end the publish loop, which
    // would silently stop every subscription of the Client.
    try {
        f(args...);
    } catch (...) {
    }
}

}  // namespace

// The publish loop of one Client. Coroutines hold it by shared_ptr; `client` is reset when
// the Client ends the loop (disconnect, abort, destruction), and every coroutine checks
// `ended` after each co_await before touching the Client again.
struct client_detail::SubscriptionEngine {
    explicit SubscriptionEngine(Client& c) : client(&c), timer(std::in_place, c.executor()) {}

    Client* client;
    bool ended = false;
    StatusCode endReason = status::Good;
    std::map<std::uint32_t, std::shared_ptr<Subscription>> subscriptions;  // by id
    std::vector<SubscriptionAcknowledgement> acks;  // sent with the next Publish
    int workers = 0;  // publisher coroutines, each with at most one Publish outstanding
    int wanted = kOutstandingPublishes;
    bool paused = false;  // BadNoSubscription: until the next subscription is created
    unsigned consecutiveErrors = 0;
    bool watchdogRunning = false;
    std::uint32_t nextClientHandle = 1;
    // Optional so that end() can release it while the executor still exists: callers may
    // keep a Subscription (and so this engine) beyond the Client and its io_context.
    std::optional<asio::steady_timer> timer;  // the keep-alive watchdog

    [[nodiscard]] bool mayPublish() const {
        return !ended && client != nullptr && !paused && !subscriptions.empty();
    }

    /// How long a Publish may wait for its response: the server holds each queued Publish
    /// up to a keep-alive period of the slowest subscription per request ahead of it.
    [[nodiscard]] std::chrono::milliseconds publishTimeout() const {
        std::chrono::milliseconds longest{0};
        for (const auto& [id, sub] : subscriptions) {
            longest = std::max(longest, sub->keepAlivePeriod());
        }
        return longest * wanted + client->requestTimeout();
    }

    void start(const std::shared_ptr<SubscriptionEngine>& self) {
        paused = false;
        while (mayPublish() && workers < wanted) {
            ++workers;
            asio::co_spawn(client->executor(), publishWorker(self), asio::detached);
        }
        if (!watchdogRunning && timer) {
            watchdogRunning = true;
            asio::co_spawn(client->executor(), watchdog(self), asio::detached);
        } else if (timer) {
            timer->cancel();  // recompute deadlines: a subscription was added or changed
        }
    }

    /// Ends everything; with `report`, every subscription's status callback hears `reason`.
    void end(StatusCode reason, bool report) {
        if (ended) return;
        ended = true;
        endReason = reason;
        auto lost = std::exchange(subscriptions, {});
        acks.clear();
        timer.reset();
        for (auto& [id, sub] : lost) {
            sub->status_ = reason;
            sub->items_.clear();
            if (report) invokeCallback(sub->onStatusChange_, reason);
        }
    }

    /// Drops one subscription (deleted here, or ended by the server).
    void forget(std::uint32_t id, StatusCode reason) {
        auto it = subscriptions.find(id);
        if (it == subscriptions.end()) return;
        it->second->status_ = reason;
        it->second->items_.clear();
        subscriptions.erase(it);
        std::erase_if(acks, [id](const auto& a) { return a.subscriptionId == id; });
    }

    static asio::awaitable<void> publishWorker(std::shared_ptr<SubscriptionEngine> e) {
        try {
            co_await e->publishLoop();
        } catch (...) {
            // Only allocation failures get here; without a loop the subscriptions are dead.
            e->end(status::BadOutOfMemory, true);
        }
        --e->workers;
    }

    // Runs inside publishWorker, whose frame holds the engine alive.
    asio::awaitable<void> publishLoop() {
        while (mayPublish() && workers <= wanted) {
            PublishRequest req;
            req.subscriptionAcknowledgements = std::exchange(acks, {});
            const auto sent = req.subscriptionAcknowledgements;
            const auto timeout = publishTimeout();
            auto resp = co_await client->requestWithin<PublishRequest, PublishResponse>(
                std::move(req), timeout);
            if (ended || client == nullptr) co_return;
            if (resp) {
                consecutiveErrors = 0;
                co_await handle(std::move(*resp));
                continue;
            }
            const StatusCode s = resp.status();
            if (s == status::BadNoSubscription) {
                // The server has none (left): acknowledgements are moot, and asking again
                // would only fail again until a subscription is created.
                paused = true;
                co_return;
            }
            // The server may never have seen these acknowledgements; sending one twice only
            // earns a BadSequenceNumberUnknown in the results.
            acks.insert(acks.begin(), sent.begin(), sent.end());
            if (s == status::BadTimeout) continue;  // re-issue; the watchdog reports a silence
            if (s == status::BadTooManyPublishRequests) {
                if (workers > 1) {
                    wanted = workers - 1;
                    co_return;
                }
                co_await pause();  // never fewer than one: without it nothing arrives
                continue;
            }
            if (isSessionLost(s) || !client->isConnected()) {
                end(s, true);
                co_return;
            }
            if (++consecutiveErrors >= kMaxConsecutiveErrors) {
                end(s, true);
                co_return;
            }
            co_await pause();
        }
    }

    /// Waits one publishing interval before trying again after an error, so that a
    /// persistent failure cannot turn into a busy loop.
    asio::awaitable<void> pause() {
        double interval = 100;
        for (const auto& [id, sub] : subscriptions) {
            interval = std::max(interval, sub->publishingInterval_);
        }
        asio::steady_timer t(client->executor());
        t.expires_after(std::chrono::milliseconds(static_cast<std::int64_t>(interval)));
        co_await t.async_wait(kNoThrow);
    }

    asio::awaitable<void> handle(PublishResponse r) {
        auto it = subscriptions.find(r.subscriptionId);
        if (it == subscriptions.end()) co_return;  // deleted here meanwhile
        auto sub = it->second;
        heard(*sub);
        auto& msg = r.notificationMessage;
        // A keep-alive carries the next sequence number without using it: nothing to
        // acknowledge, and no gap to judge.
        if (msg.notificationData.empty()) co_return;
        acks.push_back({sub->id_, msg.sequenceNumber});

        const auto seq = msg.sequenceNumber;
        if (sub->lastSequenceNumber_ == 0) {
            sub->lastSequenceNumber_ = seq;
            dispatch(*sub, msg);
            co_return;
        }
        const auto steps = stepsAfter(sub->lastSequenceNumber_, seq);
        if (steps == 0) {
            // Older than the newest: delivered here only if it is a gap being republished.
            auto m = std::find(sub->missing_.begin(), sub->missing_.end(), seq);
            if (m == sub->missing_.end()) co_return;
            sub->missing_.erase(m);
            dispatch(*sub, msg);
            co_return;
        }
        std::vector<std::uint32_t> gap;
        for (auto n = nextSequenceNumber(sub->lastSequenceNumber_);
             n != seq && gap.size() < kMaxRepublishPerGap; n = nextSequenceNumber(n)) {
            gap.push_back(n);
        }
        // More missing than are asked for again: those notifications are lost.
        bool lost = steps - 1 > kMaxRepublishPerGap;
        sub->lastSequenceNumber_ = seq;
        for (auto n : gap) sub->missing_.push_back(n);
        if (sub->missing_.size() > kMaxMissing) {
            sub->missing_.erase(sub->missing_.begin(),
                                sub->missing_.end() - static_cast<std::ptrdiff_t>(kMaxMissing));
        }
        // The missing messages first, so that callbacks see changes in order.
        for (auto n : gap) {
            RepublishRequest req;
            req.subscriptionId = sub->id_;
            req.retransmitSequenceNumber = n;
            auto again =
                co_await client->request<RepublishRequest, RepublishResponse>(std::move(req));
            if (ended || client == nullptr || sub->status_.isBad()) co_return;
            auto m = std::find(sub->missing_.begin(), sub->missing_.end(), n);
            if (m == sub->missing_.end()) continue;  // arrived meanwhile
            // Whatever the outcome, this number is settled: BadMessageNotAvailable means
            // the server no longer has it, and the notifications in it are lost.
            sub->missing_.erase(m);
            if (!again) {
                lost = true;
                continue;
            }
            if (again->notificationMessage.notificationData.empty()) continue;
            acks.push_back({sub->id_, n});
            dispatch(*sub, again->notificationMessage);
        }
        if (sub->status_.isGood()) dispatch(*sub, msg);
        // The subscription goes on; a user that must not miss a change reads the current
        // values now (the status callback hears BadMessageNotAvailable).
        if (lost && sub->status_.isGood()) {
            invokeCallback(sub->onStatusChange_, status::BadMessageNotAvailable);
        }
    }

    /// Liveness: the server answered for this subscription.
    void heard(Subscription& sub) {
        sub.lastHeard_ = Clock::now();
        if (!sub.watchdogReported_) return;
        sub.watchdogReported_ = false;
        if (timer) timer->cancel();  // its deadline counts again
        invokeCallback(sub.onStatusChange_, status::Good);
    }

    void dispatch(Subscription& sub, const NotificationMessage& msg) {
        for (const auto& data : msg.notificationData) {
            if (sub.status_.isBad()) return;  // a callback deleted it, or it ended
            const auto& type = data.typeId;
            if (type == NodeId(DataChangeNotification::kBinaryEncodingId)) {
                DataChangeNotification n;
                if (fromExtensionObject(data, n).isBad()) continue;
                for (const auto& item : n.monitoredItems) {
                    auto found = sub.items_.find(item.clientHandle);
                    if (found == sub.items_.end()) continue;
                    auto keep = found->second;  // the callback may delete the item
                    invokeCallback(keep->onDataChange, item.value);
                }
            } else if (type == NodeId(EventNotificationList::kBinaryEncodingId)) {
                EventNotificationList n;
                if (fromExtensionObject(data, n).isBad()) continue;
                for (const auto& event : n.events) {
                    auto found = sub.items_.find(event.clientHandle);
                    if (found == sub.items_.end()) continue;
                    auto keep = found->second;
                    invokeCallback(keep->onEvent, event.eventFields);
                }
            } else if (type == NodeId(StatusChangeNotification::kBinaryEncodingId)) {
                StatusChangeNotification n;
                if (fromExtensionObject(data, n).isBad()) continue;
                // Bad: the server ended the subscription (e.g. BadTimeout when its lifetime
                // ran out); GoodSubscriptionTransferred: another session has it now. Either
                // way it is over here (the caller of dispatch holds `sub` alive).
                if (n.status != status::Good) forget(sub.id_, n.status);
                invokeCallback(sub.onStatusChange_, n.status);
            }
        }
    }

    static asio::awaitable<void> watchdog(std::shared_ptr<SubscriptionEngine> e) {
        try {
            while (!e->ended && e->timer && !e->subscriptions.empty()) {
                const auto now = Clock::now();
                auto next = now + std::chrono::hours(1);
                std::vector<std::shared_ptr<Subscription>> due;
                for (const auto& [id, sub] : e->subscriptions) {
                    if (sub->watchdogReported_) continue;
                    const auto allowed = std::chrono::duration_cast<Clock::duration>(
                                             sub->keepAlivePeriod() * kWatchdogFactor) +
                                         kWatchdogSlack;
                    const auto deadline = sub->lastHeard_ + allowed;
                    if (now >= deadline) {
                        due.push_back(sub);
                    } else {
                        next = std::min(next, deadline);
                    }
                }
                for (auto& sub : due) {
                    // Reported once per silence; the loop and the subscription carry on, and
                    // the next response reports Good.
                    if (e->ended || sub->status_.isBad()) continue;
                    sub->watchdogReported_ = true;
                    invokeCallback(sub->onStatusChange_, status::BadTimeout);
                }
                if (e->ended || !e->timer) break;
                e->timer->expires_at(next);
                co_await e->timer->async_wait(kNoThrow);
            }
        } catch (...) {
            // Allocation failure only; the watchdog is advisory, publishing goes on.
        }
        e->watchdogRunning = false;
    }
};

// ---- Subscription ----

Subscription::Subscription(std::shared_ptr<client_detail::SubscriptionEngine> engine,
                           std::uint32_t subscriptionId, StatusCallback onStatusChange)
    : engine_(std::move(engine)),
      id_(subscriptionId),
      onStatusChange_(std::move(onStatusChange)),
      lastHeard_(Clock::now()) {}

Subscription::~Subscription() = default;

std::chrono::milliseconds Subscription::keepAlivePeriod() const {
    return std::chrono::milliseconds(
        static_cast<std::int64_t>(publishingInterval_ * static_cast<double>(maxKeepAliveCount_)));
}

void Subscription::applyRevised(double publishingInterval, std::uint32_t lifetimeCount,
                                std::uint32_t maxKeepAliveCount) {
    // Guard against a server revising to nonsense: the watchdog and the Publish timeout
    // are computed from these.
    publishingInterval_ = publishingInterval > 0 ? publishingInterval : 1;
    lifetimeCount_ = lifetimeCount;
    maxKeepAliveCount_ = std::max<std::uint32_t>(maxKeepAliveCount, 1);
}

Client* Subscription::client(StatusCode& why) const {
    if (status_.isBad()) {
        why = status_;
        return nullptr;
    }
    if (engine_->ended || engine_->client == nullptr) {
        why = engine_->ended && engine_->endReason.isBad() ? engine_->endReason
                                                           : status::BadServerNotConnected;
        return nullptr;
    }
    return engine_->client;
}

asio::awaitable<Result<Subscription::MonitoredItem>> Subscription::createItem(
    ReadValueId what, MonitoringParameters parameters, DataChangeCallback onDataChange,
    EventCallback onEvent) {
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    const auto handle = engine_->nextClientHandle++;
    parameters.clientHandle = handle;
    // Registered before the request: a Publish response may overtake our handling of the
    // CreateMonitoredItems response.
    auto item = std::make_shared<Item>();
    item->onDataChange = std::move(onDataChange);
    item->onEvent = std::move(onEvent);
    item->filter = parameters.filter;
    items_[handle] = item;

    MonitoredItemCreateRequest create;
    create.itemToMonitor = std::move(what);
    create.monitoringMode = MonitoringMode::Reporting;
    create.requestedParameters = std::move(parameters);
    CreateMonitoredItemsRequest req;
    req.subscriptionId = id_;
    req.timestampsToReturn = TimestampsToReturn::Both;
    req.itemsToCreate.push_back(std::move(create));
    auto resp = co_await c->request<CreateMonitoredItemsRequest, CreateMonitoredItemsResponse>(
        std::move(req));
    const auto fail = [&](StatusCode s) -> Result<MonitoredItem> {
        items_.erase(handle);
        return s;
    };
    if (!resp) co_return fail(resp.status());
    if (resp->results.size() != 1) co_return fail(status::BadUnknownResponse);
    auto& r = resp->results[0];
    if (r.statusCode.isBad()) co_return fail(r.statusCode);
    item->monitoredItemId = r.monitoredItemId;
    MonitoredItem out;
    out.monitoredItemId = r.monitoredItemId;
    out.clientHandle = handle;
    out.revisedSamplingInterval = r.revisedSamplingInterval;
    out.revisedQueueSize = r.revisedQueueSize;
    out.filterResult = std::move(r.filterResult);
    co_return out;
}

asio::awaitable<Result<Subscription::MonitoredItem>> Subscription::monitorDataChange(
    NodeId nodeId, AttributeId attribute, double samplingInterval, std::uint32_t queueSize,
    std::optional<DataChangeFilter> filter, DataChangeCallback callback) {
    ReadValueId what;
    what.nodeId = std::move(nodeId);
    what.attributeId = static_cast<std::uint32_t>(attribute);
    MonitoringParameters parameters;
    parameters.samplingInterval = samplingInterval;
    parameters.queueSize = queueSize;
    parameters.discardOldest = true;
    if (filter) parameters.filter = toExtensionObject(*filter);
    co_return co_await createItem(std::move(what), std::move(parameters), std::move(callback),
                                  EventCallback{});
}

asio::awaitable<Result<Subscription::MonitoredItem>> Subscription::monitorEvents(
    NodeId notifier, EventFilter filter, EventCallback callback, std::uint32_t queueSize) {
    ReadValueId what;
    what.nodeId = std::move(notifier);
    what.attributeId = static_cast<std::uint32_t>(AttributeId::EventNotifier);
    MonitoringParameters parameters;
    parameters.samplingInterval = 0;  // events are reported as they happen
    parameters.queueSize = queueSize;
    parameters.discardOldest = true;
    parameters.filter = toExtensionObject(filter);
    co_return co_await createItem(std::move(what), std::move(parameters), DataChangeCallback{},
                                  std::move(callback));
}

asio::awaitable<Result<Subscription::MonitoredItem>> Subscription::modifyMonitoredItem(
    std::uint32_t monitoredItemId, double samplingInterval, std::uint32_t queueSize,
    std::optional<ExtensionObject> filter) {
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    auto found = std::find_if(items_.begin(), items_.end(), [&](const auto& entry) {
        return entry.second->monitoredItemId == monitoredItemId;
    });
    if (found == items_.end()) co_return status::BadMonitoredItemIdInvalid;
    const auto handle = found->first;
    auto item = found->second;
    MonitoredItemModifyRequest modify;
    modify.monitoredItemId = monitoredItemId;
    modify.requestedParameters.clientHandle = handle;
    modify.requestedParameters.samplingInterval = samplingInterval;
    modify.requestedParameters.queueSize = queueSize;
    modify.requestedParameters.discardOldest = true;
    // The server replaces the filter with what the request carries; an event item without
    // its EventFilter would be refused, so the current one travels again.
    modify.requestedParameters.filter = filter ? *filter : item->filter;
    ModifyMonitoredItemsRequest req;
    req.subscriptionId = id_;
    req.timestampsToReturn = TimestampsToReturn::Both;
    req.itemsToModify.push_back(std::move(modify));
    auto resp = co_await c->request<ModifyMonitoredItemsRequest, ModifyMonitoredItemsResponse>(
        std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    auto& r = resp->results[0];
    if (r.statusCode.isBad()) co_return r.statusCode;
    if (filter) item->filter = std::move(*filter);
    MonitoredItem out;
    out.monitoredItemId = monitoredItemId;
    out.clientHandle = handle;
    out.revisedSamplingInterval = r.revisedSamplingInterval;
    out.revisedQueueSize = r.revisedQueueSize;
    out.filterResult = std::move(r.filterResult);
    co_return out;
}

asio::awaitable<Result<std::vector<StatusCode>>> Subscription::setMonitoringMode(
    std::vector<std::uint32_t> monitoredItemIds, MonitoringMode mode) {
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    const auto count = monitoredItemIds.size();
    SetMonitoringModeRequest req;
    req.subscriptionId = id_;
    req.monitoringMode = mode;
    req.monitoredItemIds = std::move(monitoredItemIds);
    auto resp =
        co_await c->request<SetMonitoringModeRequest, SetMonitoringModeResponse>(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != count) co_return status::BadUnknownResponse;
    co_return std::move(resp->results);
}

asio::awaitable<Result<std::vector<StatusCode>>> Subscription::deleteMonitoredItems(
    std::vector<std::uint32_t> monitoredItemIds) {
    // Forgotten first: no callback runs for an item its owner is deleting.
    std::erase_if(items_, [&](const auto& entry) {
        return std::find(monitoredItemIds.begin(), monitoredItemIds.end(),
                         entry.second->monitoredItemId) != monitoredItemIds.end();
    });
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    const auto count = monitoredItemIds.size();
    DeleteMonitoredItemsRequest req;
    req.subscriptionId = id_;
    req.monitoredItemIds = std::move(monitoredItemIds);
    auto resp = co_await c->request<DeleteMonitoredItemsRequest, DeleteMonitoredItemsResponse>(
        std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != count) co_return status::BadUnknownResponse;
    co_return std::move(resp->results);
}

asio::awaitable<StatusCode> Subscription::modify(SubscriptionSettings settings) {
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    ModifySubscriptionRequest req;
    req.subscriptionId = id_;
    req.requestedPublishingInterval = settings.publishingInterval;
    req.requestedLifetimeCount = settings.lifetimeCount;
    req.requestedMaxKeepAliveCount = settings.maxKeepAliveCount;
    req.maxNotificationsPerPublish = settings.maxNotificationsPerPublish;
    req.priority = settings.priority;
    auto resp =
        co_await c->request<ModifySubscriptionRequest, ModifySubscriptionResponse>(std::move(req));
    if (!resp) co_return resp.status();
    applyRevised(resp->revisedPublishingInterval, resp->revisedLifetimeCount,
                 resp->revisedMaxKeepAliveCount);
    // The watchdog and the next Publish timeout follow the new keep-alive period.
    if (!engine_->ended && engine_->timer) engine_->timer->cancel();
    co_return status::Good;
}

asio::awaitable<StatusCode> Subscription::setPublishingMode(bool enabled) {
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    SetPublishingModeRequest req;
    req.publishingEnabled = enabled;
    req.subscriptionIds.push_back(id_);
    auto resp =
        co_await c->request<SetPublishingModeRequest, SetPublishingModeResponse>(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    co_return resp->results[0];
}

asio::awaitable<StatusCode> Subscription::remove() {
    StatusCode why;
    Client* c = client(why);
    if (c == nullptr) co_return why;
    // Stopped here first: no callback after the owner asked for the end, whatever the
    // server answers (it also forgets the subscription when the session ends).
    engine_->forget(id_, status::BadNoSubscription);
    status_ = status::BadNoSubscription;
    DeleteSubscriptionsRequest req;
    req.subscriptionIds.push_back(id_);
    auto resp = co_await c->request<DeleteSubscriptionsRequest, DeleteSubscriptionsResponse>(
        std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    co_return resp->results[0];
}

// ---- Client ----

asio::awaitable<Result<std::shared_ptr<Subscription>>> Client::createSubscription(
    SubscriptionSettings settings, Subscription::StatusCallback onStatusChange) {
    CreateSubscriptionRequest req;
    req.requestedPublishingInterval = settings.publishingInterval;
    req.requestedLifetimeCount = settings.lifetimeCount;
    req.requestedMaxKeepAliveCount = settings.maxKeepAliveCount;
    req.maxNotificationsPerPublish = settings.maxNotificationsPerPublish;
    req.publishingEnabled = settings.publishingEnabled;
    req.priority = settings.priority;
    auto resp =
        co_await request<CreateSubscriptionRequest, CreateSubscriptionResponse>(std::move(req));
    if (!resp) co_return resp.status();
    if (!subscriptions_ || subscriptions_->ended) {
        subscriptions_ = std::make_shared<client_detail::SubscriptionEngine>(*this);
    }
    auto sub = std::make_shared<Subscription>(subscriptions_, resp->subscriptionId,
                                              std::move(onStatusChange));
    sub->applyRevised(resp->revisedPublishingInterval, resp->revisedLifetimeCount,
                      resp->revisedMaxKeepAliveCount);
    subscriptions_->subscriptions[sub->id()] = sub;
    subscriptions_->start(subscriptions_);
    co_return sub;
}

void Client::endSubscriptions(StatusCode reason) {
    if (!subscriptions_) return;
    subscriptions_->end(reason, false);
    subscriptions_->client = nullptr;
    subscriptions_.reset();
}

EventFilter makeEventFilter(const std::vector<std::string>& baseEventFields) {
    EventFilter filter;
    for (const auto& field : baseEventFields) {
        SimpleAttributeOperand op;
        op.typeDefinitionId = NodeId(ns0::BaseEventType);
        op.browsePath.push_back(QualifiedName{0, String(field)});
        op.attributeId = static_cast<std::uint32_t>(AttributeId::Value);
        filter.selectClauses.push_back(std::move(op));
    }
    return filter;
}

}  // namespace skillcell::ua
