#pragma once
// Method service set (OPC 10000-4, 5.11): Call.
#include "ua/address_space/address_space.hpp"
#include "ua/messages/method.hpp"
#include "ua/server/server_limits.hpp"

namespace skillcell::ua {

[[nodiscard]] CallMethodResult callMethod(AddressSpace& as, const CallMethodRequest& request);
StatusCode call(AddressSpace& as, const ServerLimits& limits, const CallRequest& request,
                CallResponse& response);

}  // namespace skillcell::ua
