#include "ua/server/subscriptions/subscription_engine.hpp"

#include <algorithm>
#include <unordered_set>

#include "ua/encoding/codec.hpp"
#include "ua/server/services/attribute_service.hpp"

namespace skillcell::ua {
namespace {

using Ms = std::chrono::duration<double, std::milli>;

std::chrono::steady_clock::duration toDuration(double ms) {
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(Ms(ms));
}

bool validMode(MonitoringMode m) {
    return m == MonitoringMode::Disabled || m == MonitoringMode::Sampling ||
           m == MonitoringMode::Reporting;
}

/// The filter of a monitored item after validation: one of the two, or neither.
struct FilterSetup {
    std::optional<DataChangeFilter> data;
    std::optional<CompiledEventFilter> event;
};

Result<FilterSetup> setupFilter(const AddressSpace& as, const Node& node, std::uint32_t attributeId,
                                const ExtensionObject& filter, ExtensionObject& filterResult) {
    FilterSetup out;
    const NodeId& type = filter.typeId;
    const bool isEvent = type == NodeId(EventFilter::kBinaryEncodingId);
    const bool isData = type == NodeId(DataChangeFilter::kBinaryEncodingId);
    const bool isAggregate = type == NodeId(AggregateFilter::kBinaryEncodingId);
    if (static_cast<AttributeId>(attributeId) == AttributeId::EventNotifier) {
        if (!filter.empty() && (isData || isAggregate)) return status::BadFilterNotAllowed;
        if (filter.empty() || !isEvent) return status::BadMonitoredItemFilterInvalid;
        EventFilter ef;
        if (fromExtensionObject(filter, ef).isBad()) return status::BadMonitoredItemFilterInvalid;
        EventFilterResult result;
        auto compiled = compileEventFilter(as, ef, result);
        filterResult = toExtensionObject(result);
        if (!compiled) return compiled.status();
        out.event = std::move(*compiled);
        return out;
    }
    if (filter.empty()) {
        out.data = DataChangeFilter{};
        return out;
    }
    if (isEvent) return status::BadFilterNotAllowed;
    if (isAggregate) return status::BadMonitoredItemFilterUnsupported;
    if (!isData) return status::BadMonitoredItemFilterInvalid;
    if (static_cast<AttributeId>(attributeId) != AttributeId::Value)
        return status::BadFilterNotAllowed;
    DataChangeFilter dcf;
    if (fromExtensionObject(filter, dcf).isBad()) return status::BadMonitoredItemFilterInvalid;
    const auto trigger = static_cast<std::int32_t>(dcf.trigger);
    if (trigger < 0 || trigger > 2 || dcf.deadbandType > 2)
        return status::BadMonitoredItemFilterInvalid;
    const auto deadband = static_cast<DeadbandType>(dcf.deadbandType);
    // Percent needs the EURange property, which this server does not evaluate.
    if (deadband == DeadbandType::Percent) return status::BadMonitoredItemFilterUnsupported;
    if (deadband == DeadbandType::Absolute) {
        if (!(dcf.deadbandValue >= 0)) return status::BadMonitoredItemFilterInvalid;
        // A deadband only means something for numbers.
        if (!as.isSubtypeOf(node.dataType, NodeId(ns0::Number))) return status::BadFilterNotAllowed;
    }
    out.data = dcf;
    return out;
}

}  // namespace

ServerSubscriptionEngine::ServerSubscriptionEngine(AddressSpace& as, const ServerLimits& limits)
    : as_(as), limits_(limits) {
    std::random_device rd;
    std::seed_seq seed{rd(), rd(), rd(), rd()};
    random_.seed(seed);
    as_.setValueObserver([this](const Node& node) { onValueChanged(node); });
}

ServerSubscriptionEngine::~ServerSubscriptionEngine() {
    as_.setValueObserver({});
}

Result<ServerSubscription*> ServerSubscriptionEngine::createSubscription(
    const NodeId& session, const CreateSubscriptionRequest& req, TimePoint now) {
    SessionState& state = sessions_[session];
    if (state.subscriptions.size() >= limits_.maxSubscriptionsPerSession) {
        return status::BadTooManySubscriptions;
    }
    const auto settings = reviseSettings(limits_, req.requestedPublishingInterval,
                                         req.requestedLifetimeCount, req.requestedMaxKeepAliveCount,
                                         req.maxNotificationsPerPublish, req.priority);
    const std::uint32_t id = nextSubscriptionId_++;
    auto sub = std::make_unique<ServerSubscription>(id, session, settings, req.publishingEnabled,
                                                    limits_.maxRetransmissionQueueSize, now);
    ServerSubscription* raw = sub.get();
    subscriptions_.emplace(id, std::move(sub));
    state.subscriptions.push_back(id);
    wake();
    return raw;
}

ServerSubscription* ServerSubscriptionEngine::find(const NodeId& session,
                                                   std::uint32_t subscriptionId) {
    auto it = subscriptions_.find(subscriptionId);
    if (it == subscriptions_.end() || it->second->sessionId() != session) return nullptr;
    return it->second.get();
}

StatusCode ServerSubscriptionEngine::deleteSubscription(const NodeId& session,
                                                        std::uint32_t subscriptionId) {
    if (find(session, subscriptionId) == nullptr) return status::BadSubscriptionIdInvalid;
    removeSubscription(subscriptionId);
    return status::Good;
}

void ServerSubscriptionEngine::removeSubscription(std::uint32_t id) {
    auto it = subscriptions_.find(id);
    if (it == subscriptions_.end()) return;
    for (const auto& [itemId, item] : it->second->items()) unindex(*item);
    auto st = sessions_.find(it->second->sessionId());
    subscriptions_.erase(it);
    if (st == sessions_.end()) return;
    std::erase(st->second.subscriptions, id);
    // Publish requests of a session without subscriptions would wait forever.
    if (st->second.subscriptions.empty()) {
        for (auto& p : st->second.requests) p.response.fail(status::BadNoSubscription);
        st->second.requests.clear();
    }
}

void ServerSubscriptionEngine::closeSession(const NodeId& session) {
    auto st = sessions_.find(session);
    if (st == sessions_.end()) return;
    for (auto& p : st->second.requests) p.response.fail(status::BadSessionClosed);
    st->second.requests.clear();
    const auto ids = st->second.subscriptions;
    for (const auto id : ids) removeSubscription(id);
    sessions_.erase(session);
}

std::size_t ServerSubscriptionEngine::queuedPublishRequests(const NodeId& session) const {
    auto st = sessions_.find(session);
    return st == sessions_.end() ? 0 : st->second.requests.size();
}

void ServerSubscriptionEngine::publish(const NodeId& session, const PublishRequest& req,
                                       Deferred<PublishResponse> response, TimePoint now) {
    auto st = sessions_.find(session);
    if (st == sessions_.end() || st->second.subscriptions.empty()) {
        response.fail(status::BadNoSubscription);
        return;
    }
    SessionState& state = st->second;
    if (state.requests.size() >= limits_.maxPublishRequestsPerSession) {
        response.fail(status::BadTooManyPublishRequests);
        return;
    }
    catchUp(now);  // the cycles so far passed without this request
    PendingPublish p;
    p.response = std::move(response);
    p.ackResults.reserve(req.subscriptionAcknowledgements.size());
    for (const auto& ack : req.subscriptionAcknowledgements) {
        ServerSubscription* sub = find(session, ack.subscriptionId);
        p.ackResults.push_back(sub == nullptr ? status::BadSubscriptionIdInvalid
                                              : sub->acknowledge(ack.sequenceNumber));
    }
    const auto hint = req.requestHeader.timeoutHint;
    p.deadline = hint == 0 ? TimePoint::max() : now + std::chrono::milliseconds(hint);
    state.requests.push_back(std::move(p));
    for (const auto id : state.subscriptions) subscriptions_.at(id)->resetLifetime();
    serveLate(state);
    wake();  // with a request waiting, a keep-alive is due (and perhaps its timeout)
}

void ServerSubscriptionEngine::modifySubscription(ServerSubscription& sub,
                                                  const ServerSubscriptionSettings& settings,
                                                  TimePoint now) {
    catchUp(now);
    sub.modify(settings, now);
    wake();
}

void ServerSubscriptionEngine::setPublishingEnabled(ServerSubscription& sub, bool enabled,
                                                    TimePoint now) {
    catchUp(now);
    sub.setPublishingEnabled(enabled);
    wake();
}

void ServerSubscriptionEngine::catchUp(TimePoint now) {
    for (auto& [id, sub] : subscriptions_) sub->catchUp(now, requestQueued(*sub));
}

bool ServerSubscriptionEngine::requestQueued(const ServerSubscription& sub) const {
    const auto st = sessions_.find(sub.sessionId());
    return st != sessions_.end() && !st->second.requests.empty();
}

void ServerSubscriptionEngine::serveLate(SessionState& state) {
    while (!state.requests.empty()) {
        ServerSubscription* best = nullptr;
        for (const auto id : state.subscriptions) {
            ServerSubscription* s = subscriptions_.at(id).get();
            if (s->isLate() &&
                (best == nullptr || s->settings().priority > best->settings().priority)) {
                best = s;
            }
        }
        if (best == nullptr) return;
        const bool notifications = best->publishingEnabled() && best->hasNotifications();
        send(state, *best,
             notifications ? ServerSubscription::Action::Notifications
                           : ServerSubscription::Action::KeepAlive);
    }
}

void ServerSubscriptionEngine::send(SessionState& state, ServerSubscription& sub,
                                    ServerSubscription::Action action) {
    PendingPublish p = std::move(state.requests.front());
    state.requests.pop_front();
    PublishResponse resp;
    resp.subscriptionId = sub.id();
    const DateTime now = DateTime::now();
    if (action == ServerSubscription::Action::Notifications) {
        resp.notificationMessage = sub.nextMessage(now, resp.moreNotifications);
    } else if (action == ServerSubscription::Action::Expired) {
        resp.notificationMessage = sub.statusChange(status::BadTimeout, now);
    } else {
        resp.notificationMessage = sub.keepAlive(now);
    }
    resp.availableSequenceNumbers = sub.availableSequenceNumbers();
    resp.results = std::move(p.ackResults);
    p.response.send(std::move(resp));
}

void ServerSubscriptionEngine::expire(ServerSubscription& sub) {
    auto st = sessions_.find(sub.sessionId());
    // Tell the client why its subscription is gone, if it left a request to answer.
    if (st != sessions_.end() && !st->second.requests.empty()) {
        send(st->second, sub, ServerSubscription::Action::Expired);
    }
    removeSubscription(sub.id());
}

void ServerSubscriptionEngine::tick(TimePoint now) {
    catchUp(now);
    for (MonitoredItem* item : polledItems_) {
        if (item->mode() == MonitoringMode::Disabled || now < item->nextSample) continue;
        sample(*item, as_.find(item->itemToMonitor().nodeId));
        item->nextSample += toDuration(item->samplingIntervalMs());
        if (item->nextSample <= now)
            item->nextSample = now + toDuration(item->samplingIntervalMs());
    }
    std::vector<std::uint32_t> ids;
    ids.reserve(subscriptions_.size());
    for (const auto& [id, sub] : subscriptions_) ids.push_back(id);
    for (const auto id : ids) {
        auto it = subscriptions_.find(id);
        if (it == subscriptions_.end() || now < it->second->nextCycle()) continue;
        ServerSubscription& sub = *it->second;
        SessionState& state = sessions_[sub.sessionId()];
        const auto action = sub.onPublishingTimer(now, !state.requests.empty());
        switch (action) {
            case ServerSubscription::Action::None:
                break;
            case ServerSubscription::Action::Notifications:
            case ServerSubscription::Action::KeepAlive:
                send(state, sub, action);
                serveLate(state);  // more notifications than one message holds
                break;
            case ServerSubscription::Action::Expired:
                expire(sub);
                break;
        }
    }
    for (auto& [session, state] : sessions_) {
        std::erase_if(state.requests, [now](PendingPublish& p) {
            if (p.deadline > now) return false;
            p.response.fail(status::BadTimeout);
            return true;
        });
    }
}

ServerSubscriptionEngine::TimePoint ServerSubscriptionEngine::nextDeadline() const {
    TimePoint next = TimePoint::max();
    for (const auto& [id, sub] : subscriptions_) {
        next = std::min(next, sub->nextDue(requestQueued(*sub)));
    }
    for (const MonitoredItem* item : polledItems_) {
        if (item->mode() != MonitoringMode::Disabled) next = std::min(next, item->nextSample);
    }
    for (const auto& [session, state] : sessions_) {
        for (const auto& p : state.requests) next = std::min(next, p.deadline);
    }
    return next;
}

void ServerSubscriptionEngine::onValueChanged(const Node& node) {
    auto [begin, end] = valueItems_.equal_range(node.nodeId);
    if (begin == end) return;
    catchUp(clock_());
    bool becameDue = false;
    for (auto it = begin; it != end; ++it) {
        MonitoredItem& item = *it->second;
        if (static_cast<AttributeId>(item.itemToMonitor().attributeId) != AttributeId::Value) {
            continue;
        }
        const bool had = item.hasNotifications();
        sample(item, &node);
        becameDue = becameDue || (!had && item.hasNotifications());
    }
    // Its subscription is due at its next cycle; a write that queued nothing new (filtered
    // out, or beside notifications already waiting) leaves the driver's timer as it is.
    if (becameDue) wake();
}

void ServerSubscriptionEngine::sample(MonitoredItem& item, const Node* node) {
    if (item.mode() == MonitoringMode::Disabled) return;
    DataValue dv = node == nullptr
                       ? DataValue::withStatus(status::BadNodeIdUnknown)
                       : readAttribute(as_, item.itemToMonitor(), TimestampsToReturn::Both);
    dv.serverTimestamp.reset();  // ours is set when queued; it must not count as a change
    item.offerValue(dv, DateTime::now());
}

void ServerSubscriptionEngine::unindex(const MonitoredItem& item) {
    auto& index = item.kind() == MonitoredItem::Kind::Event ? eventItems_ : valueItems_;
    auto [begin, end] = index.equal_range(item.itemToMonitor().nodeId);
    for (auto it = begin; it != end; ++it) {
        if (it->second == &item) {
            index.erase(it);
            break;
        }
    }
    std::erase(polledItems_, &item);
}

double ServerSubscriptionEngine::reviseSampling(const ServerSubscription& sub, const Node& node,
                                                double requested) const {
    double v = requested < 0 ? sub.settings().publishingIntervalMs : requested;
    // 0 (and NaN) mean "as fast as possible": the server's fastest rate.
    if (!(v >= limits_.minSamplingIntervalMs)) v = limits_.minSamplingIntervalMs;
    v = std::min(v, limits_.maxSamplingIntervalMs);
    return std::max(v, node.minimumSamplingInterval);
}

MonitoredItemCreateResult ServerSubscriptionEngine::createMonitoredItem(
    ServerSubscription& sub, TimestampsToReturn timestamps, const MonitoredItemCreateRequest& req,
    TimePoint now) {
    catchUp(now);  // the initial value is queued for the next cycle
    MonitoredItemCreateResult result;
    auto fail = [&result](StatusCode s) {
        result.statusCode = s;
        return result;
    };
    if (sub.itemCount() >= limits_.maxMonitoredItemsPerSubscription) {
        return fail(status::BadTooManyMonitoredItems);
    }
    if (!validMode(req.monitoringMode)) return fail(status::BadMonitoringModeInvalid);
    const ReadValueId& rv = req.itemToMonitor;
    const Node* node = as_.find(rv.nodeId);
    if (node == nullptr) return fail(status::BadNodeIdUnknown);
    if (rv.attributeId == 0 || rv.attributeId > kMaxAttributeId ||
        !hasAttribute(node->nodeClass, rv.attributeId)) {
        return fail(status::BadAttributeIdInvalid);
    }
    const bool isEvent = static_cast<AttributeId>(rv.attributeId) == AttributeId::EventNotifier;
    if (isEvent && (node->eventNotifier & kSubscribeToEvents) == 0) {
        return fail(status::BadNotSupported);  // the node does not produce events
    }
    if (!isEvent) {
        if (!parseIndexRange(rv.indexRange)) return fail(status::BadIndexRangeInvalid);
        if (static_cast<AttributeId>(rv.attributeId) == AttributeId::Value &&
            (node->accessLevel & node->userAccessLevel & access_level::kCurrentRead) == 0) {
            return fail(status::BadNotReadable);
        }
    }
    const auto& params = req.requestedParameters;
    auto filter = setupFilter(as_, *node, rv.attributeId, params.filter, result.filterResult);
    if (!filter) return fail(filter.status());

    const std::uint32_t id = nextItemId_++;
    auto item = std::make_unique<MonitoredItem>(
        id, isEvent ? MonitoredItem::Kind::Event : MonitoredItem::Kind::DataChange, rv, timestamps);
    // Events are not sampled: they are queued when fired.
    const double interval = isEvent ? 0 : reviseSampling(sub, *node, params.samplingInterval);
    const std::uint32_t queueSize =
        std::clamp<std::uint32_t>(params.queueSize, 1, limits_.maxMonitoredItemQueueSize);
    item->configure(params.clientHandle, interval, queueSize, params.discardOldest, timestamps);
    if (filter->data) item->setDataChangeFilter(*filter->data);
    if (filter->event) item->setEventFilter(std::move(*filter->event));
    item->setMode(req.monitoringMode);

    MonitoredItem& added = sub.addItem(std::move(item));
    if (isEvent) {
        eventItems_.emplace(rv.nodeId, &added);
    } else {
        valueItems_.emplace(rv.nodeId, &added);
        // Values the application computes change without telling anyone: poll them.
        if (node->valueSource && static_cast<AttributeId>(rv.attributeId) == AttributeId::Value) {
            polledItems_.push_back(&added);
            added.nextSample = now + toDuration(interval);
            wake();
        }
        sample(added, node);  // the initial value (OPC 10000-4, 5.12.1.4)
        wake();
    }
    result.statusCode = status::Good;
    result.monitoredItemId = id;
    result.revisedSamplingInterval = interval;
    result.revisedQueueSize = queueSize;
    return result;
}

MonitoredItemModifyResult ServerSubscriptionEngine::modifyMonitoredItem(
    ServerSubscription& sub, TimestampsToReturn timestamps, const MonitoredItemModifyRequest& req,
    TimePoint now) {
    catchUp(now);
    MonitoredItemModifyResult result;
    MonitoredItem* item = sub.item(req.monitoredItemId);
    if (item == nullptr) {
        result.statusCode = status::BadMonitoredItemIdInvalid;
        return result;
    }
    const Node* node = as_.find(item->itemToMonitor().nodeId);
    if (node == nullptr) {
        result.statusCode = status::BadNodeIdUnknown;
        return result;
    }
    const auto& params = req.requestedParameters;
    auto filter = setupFilter(as_, *node, item->itemToMonitor().attributeId, params.filter,
                              result.filterResult);
    if (!filter) {
        result.statusCode = filter.status();
        return result;
    }
    const bool isEvent = item->kind() == MonitoredItem::Kind::Event;
    const double interval = isEvent ? 0 : reviseSampling(sub, *node, params.samplingInterval);
    const std::uint32_t queueSize =
        std::clamp<std::uint32_t>(params.queueSize, 1, limits_.maxMonitoredItemQueueSize);
    item->configure(params.clientHandle, interval, queueSize, params.discardOldest, timestamps);
    if (filter->data) item->setDataChangeFilter(*filter->data);
    if (filter->event) item->setEventFilter(std::move(*filter->event));
    if (std::find(polledItems_.begin(), polledItems_.end(), item) != polledItems_.end()) {
        item->nextSample = std::min(item->nextSample, now + toDuration(interval));
        wake();
    }
    result.statusCode = status::Good;
    result.revisedSamplingInterval = interval;
    result.revisedQueueSize = queueSize;
    return result;
}

StatusCode ServerSubscriptionEngine::setMonitoringMode(ServerSubscription& sub,
                                                       std::uint32_t itemId, MonitoringMode mode,
                                                       TimePoint now) {
    MonitoredItem* item = sub.item(itemId);
    if (item == nullptr) return status::BadMonitoredItemIdInvalid;
    if (!validMode(mode)) return status::BadMonitoringModeInvalid;
    catchUp(now);
    const bool wasDisabled = item->mode() == MonitoringMode::Disabled;
    item->setMode(mode);
    wake();  // Reporting again: what the queue holds is due at the next cycle
    if (wasDisabled && mode != MonitoringMode::Disabled &&
        item->kind() == MonitoredItem::Kind::DataChange) {
        sample(*item, as_.find(item->itemToMonitor().nodeId));
        item->nextSample = now + toDuration(item->samplingIntervalMs());
        wake();
    }
    return status::Good;
}

StatusCode ServerSubscriptionEngine::deleteMonitoredItem(ServerSubscription& sub,
                                                         std::uint32_t itemId) {
    MonitoredItem* item = sub.item(itemId);
    if (item == nullptr) return status::BadMonitoredItemIdInvalid;
    unindex(*item);
    sub.removeItem(itemId);
    return status::Good;
}

ByteString ServerSubscriptionEngine::fireEvent(Event event) {
    EventRecord record;
    // Unique per server run: a counter; unpredictable across runs: random bits.
    record.eventId.bytes.resize(16);
    const std::uint64_t rnd = random_();
    const std::uint64_t seq = ++eventCounter_;
    for (int i = 0; i < 8; ++i) {
        record.eventId.bytes[static_cast<std::size_t>(i)] =
            static_cast<std::uint8_t>(rnd >> (8 * i));
        record.eventId.bytes[8 + static_cast<std::size_t>(i)] =
            static_cast<std::uint8_t>(seq >> (8 * i));
    }
    record.receiveTime = DateTime::now();
    record.time = event.time.value_or(record.receiveTime);
    if (event.sourceName.empty()) {
        if (const Node* source = as_.find(event.sourceNode))
            event.sourceName = source->browseName.name;
    }
    record.event = std::move(event);

    // The source and every notifier above it (inverse HasEventSource and its subtype
    // HasNotifier), then the Server object, which sees every event.
    std::vector<NodeId> notifiers{record.event.sourceNode};
    std::unordered_set<NodeId> seen{record.event.sourceNode};
    for (std::size_t i = 0; i < notifiers.size() && i < 1000; ++i) {
        const Node* n = as_.find(notifiers[i]);
        if (n == nullptr) continue;
        for (const auto& r : n->references) {
            if (r.isForward || !as_.isSubtypeOf(r.referenceTypeId, NodeId(ns0::HasEventSource))) {
                continue;
            }
            if (seen.insert(r.target).second) notifiers.push_back(r.target);
        }
    }
    if (seen.insert(NodeId(ns0::Server)).second) notifiers.emplace_back(ns0::Server);

    bool caughtUp = false;
    for (const auto& notifier : notifiers) {
        auto [begin, end] = eventItems_.equal_range(notifier);
        for (auto it = begin; it != end; ++it) {
            MonitoredItem& item = *it->second;
            if (item.mode() == MonitoringMode::Disabled || item.eventFilter() == nullptr) continue;
            if (auto fields = evaluateEventFilter(as_, *item.eventFilter(), record)) {
                if (!caughtUp) {  // before the first notification is queued
                    catchUp(clock_());
                    caughtUp = true;
                }
                item.offerEvent(std::move(*fields));
            }
        }
    }
    if (caughtUp) wake();  // their subscriptions are due at their next cycles
    return record.eventId;
}

}  // namespace skillcell::ua
