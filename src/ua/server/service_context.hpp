#pragma once
// ServiceContext: what a service operation may know about the request it serves.
#include <chrono>
#include <cstdint>
#include <string>

#include "ua/messages/common.hpp"
#include "ua/server/server_limits.hpp"

namespace skillcell::ua {

class Session;

struct ServiceContext {
    Session* session = nullptr;  // set for services that need an activated session
    std::uint32_t channelId = 0;
    std::uint32_t requestHandle = 0;
    const RequestHeader* requestHeader = nullptr;
    const ServerLimits* limits = nullptr;
    std::chrono::steady_clock::time_point now{};
    /// The endpoint URL the client gave in its Hello (what it used to reach us).
    const std::string* endpointUrl = nullptr;
};

}  // namespace skillcell::ua
