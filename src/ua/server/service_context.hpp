#pragma once
// ServiceContext: what a service operation may know about the request it serves.
#include <cstdint>

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
};

}  // namespace skillcell::ua
