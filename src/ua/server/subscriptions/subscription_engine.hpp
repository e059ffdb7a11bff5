#pragma once
// ServerSubscriptionEngine: every subscription of a server, the Publish requests each session has
// queued, the value observer that turns writes into notifications, and event delivery.
// The server's driver calls tick(now) at nextDeadline() on its io_context; tests call it with
// fake times (and a fake clock, setClock(), for writes and events, which come without one).
// A subscription with nothing to send does not make a deadline every publishing interval:
// only its keep-alive (with a Publish request waiting) or its lifetime's end does, and a write,
// an event or a request first lets it count the cycles it slept through (catchUp).
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <unordered_map>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/messages/subscription.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/server/service_table.hpp"
#include "ua/server/subscriptions/event.hpp"
#include "ua/server/subscriptions/subscription.hpp"

namespace skillcell::ua {

class ServerSubscriptionEngine {
public:
    using Clock = std::chrono::steady_clock;
    using TimePoint = Clock::time_point;

    /// Installs the address space's value observer; both must outlive nothing of each
    /// other beyond this object's lifetime (the destructor removes the observer).
    ServerSubscriptionEngine(AddressSpace& as, const ServerLimits& limits);
    ServerSubscriptionEngine(const ServerSubscriptionEngine&) = delete;
    ServerSubscriptionEngine& operator=(const ServerSubscriptionEngine&) = delete;
    ~ServerSubscriptionEngine();

    /// Called when nextDeadline() may have moved earlier (the driver re-arms its timer).
    void setWakeup(std::function<void()> wakeup) { wakeup_ = std::move(wakeup); }
    /// Where the time comes from when no caller passes it (a value written, an event fired):
    /// the steady clock, or a test's fake one.
    void setClock(std::function<TimePoint()> clock) { clock_ = std::move(clock); }

    // --- Subscription service set ----------------------------------------------------------
    [[nodiscard]] Result<ServerSubscription*> createSubscription(
        const NodeId& session, const CreateSubscriptionRequest& req, TimePoint now);
    /// The session's subscription, or nullptr (unknown, or another session's).
    [[nodiscard]] ServerSubscription* find(const NodeId& session, std::uint32_t subscriptionId);
    StatusCode deleteSubscription(const NodeId& session, std::uint32_t subscriptionId);
    /// ModifySubscription with revised settings (reviseSettings()).
    void modifySubscription(ServerSubscription& sub, const ServerSubscriptionSettings& settings,
                            TimePoint now);
    /// SetPublishingMode for one subscription.
    void setPublishingEnabled(ServerSubscription& sub, bool enabled, TimePoint now);
    /// Queues a Publish request (acknowledgements processed first) and answers it as soon
    /// as a subscription of the session has something to send. Faults: BadNoSubscription,
    /// BadTooManyPublishRequests.
    void publish(const NodeId& session, const PublishRequest& req,
                 Deferred<PublishResponse> response, TimePoint now);
    /// All subscriptions of a closed session go, and its queued Publish requests are
    /// answered with BadSessionClosed.
    void closeSession(const NodeId& session);

    // --- MonitoredItem service set ---------------------------------------------------------
    MonitoredItemCreateResult createMonitoredItem(ServerSubscription& sub,
                                                  TimestampsToReturn timestamps,
                                                  const MonitoredItemCreateRequest& req,
                                                  TimePoint now);
    MonitoredItemModifyResult modifyMonitoredItem(ServerSubscription& sub,
                                                  TimestampsToReturn timestamps,
                                                  const MonitoredItemModifyRequest& req,
                                                  TimePoint now);
    StatusCode setMonitoringMode(ServerSubscription& sub, std::uint32_t itemId, MonitoringMode mode,
                                 TimePoint now);
    StatusCode deleteMonitoredItem(ServerSubscription& sub, std::uint32_t itemId);

    // --- Events ------------------------------------------------------------------------------
    /// Delivers an event to the event items on its source node, on the notifiers above it
    /// (inverse HasEventSource / HasNotifier) and on the Server object. Returns the EventId.
    ByteString fireEvent(Event event);

    // --- Driver ------------------------------------------------------------------------------
    /// Samples polled items, runs due publishing cycles, times out Publish requests.
    void tick(TimePoint now);
    /// The first due publishing cycle, sample or Publish timeout. A subscription with nothing
    /// to send is not due every cycle, only when its keep-alive or its lifetime's end comes.
    [[nodiscard]] TimePoint nextDeadline() const;
    [[nodiscard]] std::size_t subscriptionCount() const { return subscriptions_.size(); }
    [[nodiscard]] std::size_t queuedPublishRequests(const NodeId& session) const;

private:
    struct PendingPublish {
        Deferred<PublishResponse> response;
        std::vector<StatusCode> ackResults;
        TimePoint deadline;  // max(): no timeout hint
    };
    struct SessionState {
        std::deque<PendingPublish> requests;
        std::vector<std::uint32_t> subscriptions;  // in creation order
    };

    void onValueChanged(const Node& node);
    void sample(MonitoredItem& item, const Node* node);
    /// Answers the session's oldest Publish request for `sub`.
    void send(SessionState& state, ServerSubscription& sub, ServerSubscription::Action action);
    /// Serves late subscriptions (highest priority first) while requests are queued.
    void serveLate(SessionState& state);
    void expire(ServerSubscription& sub);
    void removeSubscription(std::uint32_t id);
    void unindex(const MonitoredItem& item);
    /// -1: the publishing interval; 0 or below the minimum: the fastest; never faster
    /// than the node's MinimumSamplingInterval.
    [[nodiscard]] double reviseSampling(const ServerSubscription& sub, const Node& node,
                                        double requested) const;
    void wake() {
        if (wakeup_) wakeup_();
    }
    /// Every subscription counts the cycles it slept through, before something changes.
    void catchUp(TimePoint now);
    [[nodiscard]] bool requestQueued(const ServerSubscription& sub) const;

    AddressSpace& as_;
    const ServerLimits& limits_;
    std::function<void()> wakeup_;
    std::function<TimePoint()> clock_ = [] { return Clock::now(); };
    std::map<std::uint32_t, std::unique_ptr<ServerSubscription>> subscriptions_;
    std::unordered_map<NodeId, SessionState> sessions_;
    // Items by monitored node: value items for the observer, event items for fireEvent.
    std::unordered_multimap<NodeId, MonitoredItem*> valueItems_;
    std::unordered_multimap<NodeId, MonitoredItem*> eventItems_;
    std::vector<MonitoredItem*> polledItems_;  // value items of ValueSource variables
    std::uint32_t nextSubscriptionId_ = 1;
    std::uint32_t nextItemId_ = 1;
    std::mt19937_64 random_;
    std::uint64_t eventCounter_ = 0;
};

}  // namespace skillcell::ua
