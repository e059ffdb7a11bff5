#pragma once
// Limits a server enforces; every one is a typed field with a sane default.
#include <cstdint>

#include "ua/transport/tcp_framing.hpp"

namespace skillcell::ua {

struct ServerLimits {
    TransportLimits transport;
    std::uint32_t maxChannels = 100;
    std::uint32_t maxSessions = 100;
    double minSessionTimeoutMs = 1'000;
    double maxSessionTimeoutMs = 3'600'000;
    /// Operations per request (nodes to read, browse, write, methods to call, ...).
    std::uint32_t maxOperationsPerRequest = 10'000;
    std::uint32_t maxReferencesPerBrowse = 1'000;
    std::uint32_t maxBrowseContinuationPoints = 10;  // per session
    /// A connection that has not sent Hello / opened a channel by then is closed.
    std::uint32_t helloTimeoutMs = 5'000;

    // Subscriptions (OPC 10000-4, 5.13): requested values are revised into these ranges.
    std::uint32_t maxSubscriptionsPerSession = 20;            // else BadTooManySubscriptions
    std::uint32_t maxMonitoredItemsPerSubscription = 10'000;  // else BadTooManyMonitoredItems
    std::uint32_t maxPublishRequestsPerSession = 10;          // else BadTooManyPublishRequests
    double minPublishingIntervalMs = 20;
    double maxPublishingIntervalMs = 3'600'000;
    /// The fastest sampling (a requested 0) and the slowest.
    double minSamplingIntervalMs = 10;
    double maxSamplingIntervalMs = 3'600'000;
    std::uint32_t maxKeepAliveCount = 10'000;
    /// Lifetime counts are revised to at least 3 keep-alive counts (OPC 10000-4, 5.13.2.2).
    std::uint32_t maxLifetimeCount = 100'000;
    std::uint32_t maxNotificationsPerPublish = 10'000;  // also the limit for a requested 0
    std::uint32_t maxMonitoredItemQueueSize = 1'000;
    /// Sent NotificationMessages kept per subscription for Republish until acknowledged;
    /// the oldest is dropped beyond this.
    std::uint32_t maxRetransmissionQueueSize = 20;
};

}  // namespace skillcell::ua
