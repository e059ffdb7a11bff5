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
};

}  // namespace skillcell::ua
