#pragma once
// Client side of the Subscription and MonitoredItem service sets: Subscription objects made
// by Client::createSubscription, monitored items with callbacks, and the publish loop that
// feeds them (subscription.cpp; README.md describes the behaviour on timeouts and losses).
//
// Threading: like the Client, a Subscription is used from the Client's executor only, and
// every callback runs there, from the publish loop. A callback must not block; it may start
// new work (co_spawn) on the executor, including calls on this Subscription.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <asio/awaitable.hpp>

#include "ua/messages/subscription.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

class Client;

namespace client_detail {
struct SubscriptionEngine;  // subscription.cpp: the publish loop of one Client
}  // namespace client_detail

/// What CreateSubscription asks for; the server may revise every value.
struct SubscriptionSettings {
    // Not an aggregate on purpose (see ClientConfig): settings are often written in place,
    // inside a co_await expression.
    SubscriptionSettings() = default;
    SubscriptionSettings(double publishingIntervalMs, std::uint32_t lifetime,
                         std::uint32_t maxKeepAlive, std::uint32_t maxNotifications = 0,
                         std::uint8_t priorityLevel = 0)
        : publishingInterval(publishingIntervalMs),
          lifetimeCount(lifetime),
          maxKeepAliveCount(maxKeepAlive),
          maxNotificationsPerPublish(maxNotifications),
          priority(priorityLevel) {}

    double publishingInterval = 500;  // ms
    /// Publishing intervals without a Publish request before the server drops the
    /// subscription; the standard wants at least 3 x maxKeepAliveCount.
    std::uint32_t lifetimeCount = 60;
    /// Publishing intervals without notifications before the server sends a keep-alive.
    std::uint32_t maxKeepAliveCount = 10;
    std::uint32_t maxNotificationsPerPublish = 0;  // 0: no limit
    std::uint8_t priority = 0;
    bool publishingEnabled = true;
};

/// Select clauses for the named fields of BaseEventType ("EventId", "Message", ...), in the
/// order given; the event callback receives the fields in that order.
[[nodiscard]] EventFilter makeEventFilter(const std::vector<std::string>& baseEventFields);

/// One subscription on the server. Made by Client::createSubscription; shared by the
/// caller and the Client's publish loop, which keeps it alive while it runs on the server.
class Subscription {
public:
    using DataChangeCallback = std::function<void(const DataValue&)>;
    using EventCallback = std::function<void(const std::vector<Variant>& fields)>;
    using StatusCallback = std::function<void(StatusCode)>;

    /// The server's answer to one monitored item: its id is what modify/delete take.
    struct MonitoredItem {
        std::uint32_t monitoredItemId = 0;
        std::uint32_t clientHandle = 0;
        double revisedSamplingInterval = 0;
        std::uint32_t revisedQueueSize = 0;
        ExtensionObject filterResult;  // EventFilterResult for event items
    };

    // Made by Client::createSubscription only (it needs the engine); public for make_shared.
    Subscription(std::shared_ptr<client_detail::SubscriptionEngine> engine,
                 std::uint32_t subscriptionId, StatusCallback onStatusChange);
    Subscription(const Subscription&) = delete;
    Subscription& operator=(const Subscription&) = delete;
    ~Subscription();

    [[nodiscard]] std::uint32_t id() const { return id_; }
    [[nodiscard]] double revisedPublishingInterval() const { return publishingInterval_; }
    [[nodiscard]] std::uint32_t revisedLifetimeCount() const { return lifetimeCount_; }
    [[nodiscard]] std::uint32_t revisedMaxKeepAliveCount() const { return maxKeepAliveCount_; }
    /// Good while the subscription runs; otherwise why it stopped (deleted: BadNoSubscription,
    /// lost: the session's or connection's status, or the server's StatusChangeNotification).
    [[nodiscard]] StatusCode status() const { return status_; }
    /// revisedPublishingInterval x revisedMaxKeepAliveCount: the server answers a Publish
    /// for this subscription at least this often.
    [[nodiscard]] std::chrono::milliseconds keepAlivePeriod() const;

    /// Monitors one attribute (default: Value) for changes. `callback` receives every
    /// DataValue the server reports for it. The item, or why it was refused (the per-item
    /// status when the service succeeded).
    asio::awaitable<Result<MonitoredItem>> monitorDataChange(NodeId nodeId, AttributeId attribute,
                                                             double samplingInterval,
                                                             std::uint32_t queueSize,
                                                             std::optional<DataChangeFilter> filter,
                                                             DataChangeCallback callback);
    /// Monitors the events of `notifier` (e.g. the Server object, i=2253). `callback`
    /// receives each event's fields in the order of filter.selectClauses.
    asio::awaitable<Result<MonitoredItem>> monitorEvents(NodeId notifier, EventFilter filter,
                                                         EventCallback callback,
                                                         std::uint32_t queueSize = 100);
    /// New sampling interval and queue size for one item (its filter stays unless given).
    asio::awaitable<Result<MonitoredItem>> modifyMonitoredItem(
        std::uint32_t monitoredItemId, double samplingInterval, std::uint32_t queueSize,
        std::optional<ExtensionObject> filter = std::nullopt);
    /// One status per item, in order.
    asio::awaitable<Result<std::vector<StatusCode>>> setMonitoringMode(
        std::vector<std::uint32_t> monitoredItemIds, MonitoringMode mode);
    /// One status per item, in order; the items' callbacks are forgotten either way.
    asio::awaitable<Result<std::vector<StatusCode>>> deleteMonitoredItems(
        std::vector<std::uint32_t> monitoredItemIds);

    asio::awaitable<StatusCode> modify(SubscriptionSettings settings);
    asio::awaitable<StatusCode> setPublishingMode(bool enabled);
    /// DeleteSubscriptions. The subscription stops here whatever the server answers (its
    /// status() becomes BadNoSubscription, no callback is called any more).
    asio::awaitable<StatusCode> remove();

private:
    friend struct client_detail::SubscriptionEngine;
    friend class Client;

    struct Item {
        std::uint32_t monitoredItemId = 0;
        DataChangeCallback onDataChange;
        EventCallback onEvent;
        ExtensionObject filter;  // sent again by modifyMonitoredItem
    };

    asio::awaitable<Result<MonitoredItem>> createItem(ReadValueId what,
                                                      MonitoringParameters parameters,
                                                      DataChangeCallback onDataChange,
                                                      EventCallback onEvent);
    /// The Client to send requests through, or nullptr (with the reason in `why`) when this
    /// subscription or its Client is gone.
    Client* client(StatusCode& why) const;
    void applyRevised(double publishingInterval, std::uint32_t lifetimeCount,
                      std::uint32_t maxKeepAliveCount);

    std::shared_ptr<client_detail::SubscriptionEngine> engine_;
    std::uint32_t id_ = 0;
    StatusCallback onStatusChange_;
    StatusCode status_ = status::Good;
    double publishingInterval_ = 0;
    std::uint32_t lifetimeCount_ = 0;
    std::uint32_t maxKeepAliveCount_ = 0;
    std::map<std::uint32_t, std::shared_ptr<Item>> items_;  // by clientHandle

    // Publish bookkeeping, owned by the engine.
    std::uint32_t lastSequenceNumber_ = 0;  // 0: none received yet
    std::vector<std::uint32_t> missing_;    // detected gaps, awaiting Republish
    std::chrono::steady_clock::time_point lastHeard_{};
    bool watchdogReported_ = false;
};

}  // namespace skillcell::ua
