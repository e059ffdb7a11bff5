#include "ua/server/subscriptions/subscription.hpp"

#include <algorithm>
#include <cmath>

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {

ServerSubscriptionSettings reviseSettings(const ServerLimits& limits, double publishingIntervalMs,
                                          std::uint32_t lifetimeCount,
                                          std::uint32_t maxKeepAliveCount,
                                          std::uint32_t maxNotificationsPerPublish,
                                          std::uint8_t priority) {
    ServerSubscriptionSettings s;
    // NaN and negative values fail the comparison and take the minimum.
    s.publishingIntervalMs = publishingIntervalMs >= limits.minPublishingIntervalMs
                                 ? std::min(publishingIntervalMs, limits.maxPublishingIntervalMs)
                                 : limits.minPublishingIntervalMs;
    s.maxKeepAliveCount = std::clamp<std::uint32_t>(maxKeepAliveCount, 1, limits.maxKeepAliveCount);
    const std::uint64_t minLifetime = std::uint64_t{s.maxKeepAliveCount} * 3;
    s.lifetimeCount = static_cast<std::uint32_t>(std::clamp<std::uint64_t>(
        lifetimeCount, std::min<std::uint64_t>(minLifetime, limits.maxLifetimeCount),
        limits.maxLifetimeCount));
    s.lifetimeCount = std::max<std::uint32_t>(s.lifetimeCount, 3);
    s.maxNotificationsPerPublish =
        maxNotificationsPerPublish == 0
            ? limits.maxNotificationsPerPublish
            : std::min(maxNotificationsPerPublish, limits.maxNotificationsPerPublish);
    s.priority = priority;
    return s;
}

ServerSubscription::ServerSubscription(std::uint32_t id, NodeId sessionId,
                                       const ServerSubscriptionSettings& settings,
                                       bool publishingEnabled, std::uint32_t maxRetransmissionQueue,
                                       TimePoint now)
    : id_(id),
      sessionId_(std::move(sessionId)),
      settings_(settings),
      publishingEnabled_(publishingEnabled),
      maxRetransmission_(std::max<std::uint32_t>(maxRetransmissionQueue, 1)),
      nextCycle_(now + interval()),
      // The first cycle without notifications sends a keep-alive, so the client learns at
      // once that the subscription works (OPC 10000-4, 5.13.1.2, state table row 3).
      keepAliveCounter_(settings.maxKeepAliveCount) {}

std::chrono::nanoseconds ServerSubscription::interval() const {
    return std::chrono::nanoseconds(
        static_cast<std::int64_t>(std::llround(settings_.publishingIntervalMs * 1e6)));
}

bool ServerSubscription::hasNotifications() const {
    return std::any_of(items_.begin(), items_.end(),
                       [](const auto& kv) { return kv.second->hasNotifications(); });
}

void ServerSubscription::modify(const ServerSubscriptionSettings& settings, TimePoint now) {
    settings_ = settings;
    nextCycle_ = std::min(nextCycle_, now + interval());
    lifetimeCounter_ = 0;
}

ServerSubscription::Action ServerSubscription::onPublishingTimer(TimePoint now,
                                                                 bool requestQueued) {
    // The next cycle follows the schedule; after a long stall it restarts from now rather
    // than firing a burst of catch-up cycles.
    nextCycle_ += interval();
    if (nextCycle_ <= now) nextCycle_ = now + interval();

    if (requestQueued) lifetimeCounter_ = 0;
    const bool notifications = publishingEnabled_ && hasNotifications();
    if (notifications) {
        if (requestQueued) return Action::Notifications;
        late_ = true;
    } else {
        if (keepAliveCounter_ < settings_.maxKeepAliveCount) ++keepAliveCounter_;
        if (keepAliveCounter_ >= settings_.maxKeepAliveCount) {
            if (requestQueued) return Action::KeepAlive;
            late_ = true;
        }
    }
    if (!requestQueued && ++lifetimeCounter_ >= settings_.lifetimeCount) return Action::Expired;
    return Action::None;
}

std::uint64_t ServerSubscription::cyclesUntilDue(bool requestQueued) const {
    if (publishingEnabled_ && hasNotifications()) return 1;
    if (requestQueued) {  // the keep-alive is what comes; the lifetime is reset every cycle
        const std::uint32_t max = settings_.maxKeepAliveCount;
        return keepAliveCounter_ >= max ? 1 : max - keepAliveCounter_;
    }
    // Without a request a keep-alive only marks the subscription late, which the next
    // request finds (catchUp() marks it); the lifetime's end is what comes.
    const std::uint32_t life = settings_.lifetimeCount;
    return lifetimeCounter_ >= life ? 1 : life - lifetimeCounter_;
}

ServerSubscription::TimePoint ServerSubscription::nextDue(bool requestQueued) const {
    const std::uint64_t k = cyclesUntilDue(requestQueued);
    const auto step = interval();
    if (step.count() <= 0) return nextCycle_;
    // Guarded against overflow: a lifetime may count many cycles of up to an hour each.
    const auto room = TimePoint::max() - nextCycle_;
    const auto ahead = static_cast<std::uint64_t>(room / step);
    if (k - 1 > ahead) return TimePoint::max();
    return nextCycle_ + step * static_cast<std::int64_t>(k - 1);
}

void ServerSubscription::catchUp(TimePoint now, bool requestQueued) {
    const auto step = interval();
    if (nextCycle_ >= now || step.count() <= 0) return;
    // The cycles strictly before `now`: one at `now` itself is left to the timer, which
    // runs it after whatever happens at `now`.
    const auto passed =
        static_cast<std::uint64_t>((now - nextCycle_ + step - std::chrono::nanoseconds(1)) / step);
    const std::uint64_t k = cyclesUntilDue(requestQueued);
    const std::uint64_t n = std::min(passed, k - 1);
    if (n == 0) return;
    const std::uint32_t max = settings_.maxKeepAliveCount;
    keepAliveCounter_ = static_cast<std::uint32_t>(
        std::min<std::uint64_t>(max, std::uint64_t{keepAliveCounter_} + n));
    if (keepAliveCounter_ >= max && !requestQueued) late_ = true;
    lifetimeCounter_ = requestQueued ? 0
                                     : static_cast<std::uint32_t>(std::min<std::uint64_t>(
                                           settings_.lifetimeCount, lifetimeCounter_ + n));
    nextCycle_ += step * static_cast<std::int64_t>(n);
}

std::uint32_t ServerSubscription::takeSequenceNumber() {
    const std::uint32_t n = nextSequenceNumber_;
    // Sequence numbers wrap to 1, never 0 (OPC 10000-4, 7.21).
    nextSequenceNumber_ = nextSequenceNumber_ == 0xFFFFFFFFu ? 1 : nextSequenceNumber_ + 1;
    return n;
}

void ServerSubscription::remember(const NotificationMessage& message) {
    retransmission_.push_back(message);
    while (retransmission_.size() > maxRetransmission_) retransmission_.pop_front();
}

NotificationMessage ServerSubscription::nextMessage(DateTime publishTime, bool& more) {
    std::size_t budget = settings_.maxNotificationsPerPublish;
    DataChangeNotification changes;
    EventNotificationList events;
    for (auto& [id, item] : items_) {
        if (budget == 0) break;
        if (!item->hasNotifications()) continue;
        budget -= item->takeDataChanges(changes.monitoredItems, budget);
        budget -= item->takeEvents(events.events, budget);
    }
    NotificationMessage m;
    m.sequenceNumber = takeSequenceNumber();
    m.publishTime = publishTime;
    if (!changes.monitoredItems.empty()) m.notificationData.push_back(toExtensionObject(changes));
    if (!events.events.empty()) m.notificationData.push_back(toExtensionObject(events));
    remember(m);
    more = publishingEnabled_ && hasNotifications();
    late_ = more;
    keepAliveCounter_ = 0;
    return m;
}

NotificationMessage ServerSubscription::keepAlive(DateTime publishTime) {
    keepAliveCounter_ = 0;
    late_ = false;
    NotificationMessage m;
    m.sequenceNumber = nextSequenceNumber_;
    m.publishTime = publishTime;
    return m;
}

NotificationMessage ServerSubscription::statusChange(StatusCode status, DateTime publishTime) {
    NotificationMessage m;
    m.sequenceNumber = takeSequenceNumber();
    m.publishTime = publishTime;
    StatusChangeNotification change;
    change.status = status;
    m.notificationData.push_back(toExtensionObject(change));
    return m;
}

StatusCode ServerSubscription::acknowledge(std::uint32_t sequenceNumber) {
    auto it = std::find_if(retransmission_.begin(), retransmission_.end(),
                           [&](const auto& m) { return m.sequenceNumber == sequenceNumber; });
    if (it == retransmission_.end()) return status::BadSequenceNumberUnknown;
    retransmission_.erase(it);
    return status::Good;
}

Result<NotificationMessage> ServerSubscription::republish(std::uint32_t sequenceNumber) const {
    auto it = std::find_if(retransmission_.begin(), retransmission_.end(),
                           [&](const auto& m) { return m.sequenceNumber == sequenceNumber; });
    if (it == retransmission_.end()) return status::BadMessageNotAvailable;
    return *it;
}

std::vector<std::uint32_t> ServerSubscription::availableSequenceNumbers() const {
    std::vector<std::uint32_t> out;
    out.reserve(retransmission_.size());
    for (const auto& m : retransmission_) out.push_back(m.sequenceNumber);
    return out;
}

MonitoredItem& ServerSubscription::addItem(std::unique_ptr<MonitoredItem> item) {
    const std::uint32_t id = item->id();
    return *items_.insert_or_assign(id, std::move(item)).first->second;
}

MonitoredItem* ServerSubscription::item(std::uint32_t id) {
    auto it = items_.find(id);
    return it == items_.end() ? nullptr : it->second.get();
}

std::unique_ptr<MonitoredItem> ServerSubscription::removeItem(std::uint32_t id) {
    auto it = items_.find(id);
    if (it == items_.end()) return nullptr;
    auto item = std::move(it->second);
    items_.erase(it);
    return item;
}

}  // namespace skillcell::ua
