#pragma once
// OrderNodes: the MES's orders on OPC UA, under Objects/Orders.
//
//   SubmitOrder(ProcessIri, Priority) -> OrderId, Resumed        (Operator)
//   CancelOrder(OrderId)                                          (Operator)
//   ListOrders(Count) -> OrderIds, Processes, States, Priorities, Progress   (Observer)
//   GetOrder(OrderId) -> Process, State, Reason, Steps            (Observer)
//   Orders/<id>/State, Orders/<id>/Progress: one object per order this MES ran, for a
//   client to follow by subscription (`skillcell run`). The newest kMaxEnded ended orders
//   keep theirs; the journal keeps everything.
//
// Refusals are status codes: BadInvalidArgument (an empty IRI, a priority out of range),
// BadNotFound (no such order), BadInvalidState (an order that has ended already),
// BadUserAccessDenied (the role), BadInternalError (the journal failed; the MES logs why).
//
// Build, use and destroy on the server's thread.
#include <cstdint>
#include <deque>
#include <memory>

#include "mes/process_executor.hpp"
#include "ua/address_space/address_space.hpp"

namespace skillcell::mes {

class OrderNodes {
public:
    /// How many ended orders keep their objects.
    static constexpr std::size_t kMaxEnded = 200;

    [[nodiscard]] static ua::Result<std::unique_ptr<OrderNodes>> create(
        ua::AddressSpace& as, std::shared_ptr<ProcessExecutor> executor, Journal& journal);
    /// Shows `p` in its order's object (creating it).
    void show(const Progress& p);

    struct Token {
    private:
        friend class OrderNodes;
        Token() = default;
    };
    OrderNodes(Token, ua::AddressSpace& as) : as_(as) {}

private:
    void removeOldest();

    ua::AddressSpace& as_;
    std::deque<std::int64_t> ended_;  // orders whose objects show their end, oldest first
};

/// Orders/<id>/<name> (name: "State" or "Progress").
[[nodiscard]] ua::NodeId orderVariable(std::int64_t order, const char* name);
/// Objects/Orders/<method> ("SubmitOrder", ...).
[[nodiscard]] ua::NodeId orderMethod(const char* name);
[[nodiscard]] ua::NodeId ordersObject();
/// Whether an order in `state` ("completed", "stopped", "cancelled", ...) has ended.
[[nodiscard]] bool hasEnded(const std::string& state);

}  // namespace skillcell::mes
