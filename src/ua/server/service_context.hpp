#pragma once
// ServiceContext: what a service operation may know about the request it serves.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ua/messages/common.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/types/builtin.hpp"

namespace skillcell::ua {

class Session;
namespace crypto {
class AsymmetricKey;
}

/// Sends an encoded service body (type id + structure) as the response to the request being
/// served, whenever that is. Set by the connection; harmless once the connection is gone.
using ResponseSender = std::function<void(std::vector<std::uint8_t> body)>;

struct ServiceContext {
    Session* session = nullptr;  // set for services that need an activated session
    std::uint32_t channelId = 0;
    std::uint32_t requestHandle = 0;
    const RequestHeader* requestHeader = nullptr;
    const ServerLimits* limits = nullptr;
    std::chrono::steady_clock::time_point now{};
    /// The endpoint URL the client gave in its Hello (what it used to reach us).
    const std::string* endpointUrl = nullptr;
    /// The channel's security: policy URI, mode, and the client's certificate (empty for
    /// None).
    std::string_view securityPolicyUri;
    MessageSecurityMode securityMode = MessageSecurityMode::None;
    const ByteString* clientCertificate = nullptr;
    /// The public key of clientCertificate's leaf, decoded when the channel opened.
    const crypto::AsymmetricKey* clientKey = nullptr;
    /// For deferred services (ServiceTable::addDeferred): answers this request later.
    ResponseSender reply;
};

}  // namespace skillcell::ua
