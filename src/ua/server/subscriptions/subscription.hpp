#pragma once
// ServerSubscription: one subscription's publishing state machine of OPC 10000-4, 5.13.1 without
// I/O or clock. The engine calls onPublishingTimer() when a publishing interval elapsed, telling it
// whether a Publish request is queued; the subscription answers what to send (notifications,
// a keep-alive, nothing) or that its lifetime expired. Tests drive it with fake times.
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>

#include "ua/messages/subscription.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/server/subscriptions/monitored_item.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

struct ServerSubscriptionSettings {
    double publishingIntervalMs = 0;
    std::uint32_t lifetimeCount = 0;
    std::uint32_t maxKeepAliveCount = 0;
    std::uint32_t maxNotificationsPerPublish = 0;
    std::uint8_t priority = 0;
};

/// Revises requested values into the server's limits (OPC 10000-4, 5.13.2.2): the interval
/// clamped, keep-alive count at least 1, lifetime count at least three keep-alive counts,
/// 0 notifications per publish meaning the server's maximum.
[[nodiscard]] ServerSubscriptionSettings reviseSettings(const ServerLimits& limits,
                                                        double publishingIntervalMs,
                                                        std::uint32_t lifetimeCount,
                                                        std::uint32_t maxKeepAliveCount,
                                                        std::uint32_t maxNotificationsPerPublish,
                                                        std::uint8_t priority);

class ServerSubscription {
public:
    using TimePoint = std::chrono::steady_clock::time_point;
    enum class Action : std::uint8_t {
        None,           // nothing to send this cycle
        Notifications,  // call nextMessage()
        KeepAlive,      // call keepAlive()
        Expired,        // the lifetime count elapsed without Publish requests
    };

    ServerSubscription(std::uint32_t id, NodeId sessionId,
                       const ServerSubscriptionSettings& settings, bool publishingEnabled,
                       std::uint32_t maxRetransmissionQueue, TimePoint now);

    [[nodiscard]] std::uint32_t id() const { return id_; }
    [[nodiscard]] const NodeId& sessionId() const { return sessionId_; }
    [[nodiscard]] const ServerSubscriptionSettings& settings() const { return settings_; }
    [[nodiscard]] bool publishingEnabled() const { return publishingEnabled_; }
    [[nodiscard]] TimePoint nextCycle() const { return nextCycle_; }
    [[nodiscard]] std::chrono::nanoseconds interval() const;
    /// A publishing cycle passed without a Publish request while something was due: the
    /// next Publish request is answered at once.
    [[nodiscard]] bool isLate() const { return late_; }
    /// The sequence number the next NotificationMessage with data will carry.
    [[nodiscard]] std::uint32_t nextSequenceNumber() const { return nextSequenceNumber_; }
    [[nodiscard]] bool hasNotifications() const;

    void modify(const ServerSubscriptionSettings& settings, TimePoint now);
    void setPublishingEnabled(bool enabled) { publishingEnabled_ = enabled; }
    /// A Publish request arrived for the session (OPC 10000-4, 5.13.1.1: resets the
    /// lifetime counter).
    void resetLifetime() { lifetimeCounter_ = 0; }

    /// The publishing timer fired at `now` (>= nextCycle()).
    Action onPublishingTimer(TimePoint now, bool requestQueued);

    // An idle subscription is not woken every publishing interval: the cycles in which it
    // could only count (toward the keep-alive and the lifetime) are counted when it is next
    // looked at. The engine sleeps until nextDue() and calls catchUp() before anything changes
    // (a notification queued, a Publish request, a setting).

    /// The first cycle at which onPublishingTimer() may send or expire, `requestQueued`
    /// telling whether a Publish request waits: the next one with notifications queued, the
    /// keep-alive's with a request, else the lifetime's end.
    [[nodiscard]] TimePoint nextDue(bool requestQueued) const;
    /// Counts the cycles before `now` that passed with nothing to do, as onPublishingTimer()
    /// would have; what changes at `now` then takes effect from the next cycle. Never counts
    /// the due cycle itself.
    void catchUp(TimePoint now, bool requestQueued);

    /// The next NotificationMessage with up to maxNotificationsPerPublish notifications;
    /// it takes the next sequence number and is kept for Republish. `more` tells whether
    /// notifications remain.
    NotificationMessage nextMessage(DateTime publishTime, bool& more);
    /// A keep-alive: no notifications, the next sequence number without using it.
    NotificationMessage keepAlive(DateTime publishTime);
    /// A StatusChangeNotification (lifetime expiry: BadTimeout).
    NotificationMessage statusChange(StatusCode status, DateTime publishTime);

    /// Removes an acknowledged message: Good, or BadSequenceNumberUnknown.
    StatusCode acknowledge(std::uint32_t sequenceNumber);
    /// A message still in the retransmission queue, or BadMessageNotAvailable.
    [[nodiscard]] Result<NotificationMessage> republish(std::uint32_t sequenceNumber) const;
    [[nodiscard]] std::vector<std::uint32_t> availableSequenceNumbers() const;

    // Monitored items, owned here; pointers stay valid until the item is removed.
    MonitoredItem& addItem(std::unique_ptr<MonitoredItem> item);
    [[nodiscard]] MonitoredItem* item(std::uint32_t id);
    std::unique_ptr<MonitoredItem> removeItem(std::uint32_t id);
    [[nodiscard]] std::size_t itemCount() const { return items_.size(); }
    [[nodiscard]] const std::map<std::uint32_t, std::unique_ptr<MonitoredItem>>& items() const {
        return items_;
    }

private:
    /// How many cycles from nextCycle() on until the due one (1: the next one).
    [[nodiscard]] std::uint64_t cyclesUntilDue(bool requestQueued) const;
    std::uint32_t takeSequenceNumber();
    void remember(const NotificationMessage& message);

    std::uint32_t id_;
    NodeId sessionId_;
    ServerSubscriptionSettings settings_;
    bool publishingEnabled_;
    std::uint32_t maxRetransmission_;
    TimePoint nextCycle_;
    std::uint32_t keepAliveCounter_;
    std::uint32_t lifetimeCounter_ = 0;
    bool late_ = false;
    std::uint32_t nextSequenceNumber_ = 1;
    std::deque<NotificationMessage> retransmission_;
    std::map<std::uint32_t, std::unique_ptr<MonitoredItem>> items_;
};

}  // namespace skillcell::ua
