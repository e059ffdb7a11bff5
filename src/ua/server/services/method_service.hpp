#pragma once
// Method service set (OPC 10000-4, 5.11): Call.
#include "ua/address_space/address_space.hpp"
#include "ua/messages/method.hpp"
#include "ua/server/server_limits.hpp"

namespace skillcell::ua {

/// `caller` is handed to the method's callback (tests and application code may omit it).
[[nodiscard]] CallMethodResult callMethod(AddressSpace& as, const CallMethodRequest& request,
                                          const Caller& caller = {});
StatusCode call(AddressSpace& as, const ServerLimits& limits, const CallRequest& request,
                CallResponse& response, const Caller& caller = {});

}  // namespace skillcell::ua
