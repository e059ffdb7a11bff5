#pragma once
// The generic loop every service with an operation array runs (OPC 10000-4, 7.34 / 5.x):
// an empty array is BadNothingToDo, more operations than the server allows are
// BadTooManyOperations, otherwise one result per operation in request order.
#include <vector>

#include "ua/address_space/node.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/server/service_context.hpp"
#include "ua/server/session.hpp"
#include "ua/types/status_code.hpp"

namespace skillcell::ua {

template <class In, class Out, class Operation>
StatusCode forEachOperation(const ServerLimits& limits, const std::vector<In>& operations,
                            std::vector<Out>& results, Operation&& operation) {
    if (operations.empty()) return status::BadNothingToDo;
    if (operations.size() > limits.maxOperationsPerRequest) return status::BadTooManyOperations;
    results.clear();
    results.reserve(operations.size());
    for (const auto& op : operations) results.push_back(operation(op));
    return status::Good;
}

/// The session a request came on, for callbacks that apply per-session rules.
inline Caller callerOf(const ServiceContext& ctx) {
    if (ctx.session == nullptr) return Caller{};
    return Caller{ctx.session->sessionId(), ctx.session->identity().roles};
}

/// The server's limits, or the defaults when a caller (a test) has none.
inline const ServerLimits& limitsOf(const ServiceContext& ctx) {
    static const ServerLimits kDefaults{};
    return ctx.limits != nullptr ? *ctx.limits : kDefaults;
}

}  // namespace skillcell::ua
