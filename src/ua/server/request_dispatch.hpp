#pragma once
// Request dispatch: one service request, as the body of a secure channel message (its type
// id, then the request), served through the ServiceTable: the session looked up by the
// request header's authentication token on this channel, the service invoked, the response
// or a ServiceFault encoded. It knows nothing of sockets or chunks: Connection feeds it what
// the secure channel decoded, and the stateful fuzzer (fuzz/session_services_fuzzer.cpp)
// feeds it requests directly.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ua/server/service_context.hpp"
#include "ua/server/service_table.hpp"
#include "ua/server/session_manager.hpp"
#include "ua/transport/secure_channel.hpp"

namespace skillcell::ua {

/// The secure channel a request came on, as the services see it.
struct RequestChannel {
    std::uint32_t channelId = 0;
    const std::string* endpointUrl = nullptr;  // from the client's Hello
    std::string_view securityPolicyUri;        // empty: none negotiated
    const ByteString* clientCertificate = nullptr;
    const crypto::AsymmetricKey* clientKey = nullptr;  // clientCertificate's, decoded
    MessageSecurityMode securityMode = MessageSecurityMode::None;
    /// A None channel on a server that does not offer None: discovery services only.
    bool discoveryOnly = false;
};

struct DispatchedRequest {
    /// Bad only when the body has no type id: the stream is corrupt, the channel must close.
    StatusCode status = status::Good;
    std::uint32_t requestHandle = 0;
    /// The response or ServiceFault body; empty when the service answers later, through the
    /// sender that `replyFor` made.
    std::vector<std::uint8_t> response;
};

/// Makes the sender through which a deferred service (Publish) answers the request whose
/// handle is given.
using ReplyFactory = std::function<ResponseSender(std::uint32_t requestHandle)>;

/// Serves one request.
[[nodiscard]] DispatchedRequest dispatchRequest(const ServiceTable& services,
                                                SessionManager& sessions,
                                                const ServerLimits& limits,
                                                const RequestChannel& channel,
                                                std::span<const std::uint8_t> body, SteadyTime now,
                                                const ReplyFactory& replyFor);

/// Whether a request of this type is a discovery service (GetEndpoints, FindServers...).
[[nodiscard]] bool isDiscoveryService(std::uint32_t requestTypeId);

}  // namespace skillcell::ua
