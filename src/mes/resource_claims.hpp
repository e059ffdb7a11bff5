#pragma once
// ResourceClaims: which order holds which component of the cell, and which orders wait for
// which components. An order takes a component when one of its steps first runs on it (or
// needs it, as a pick needs its gripper) and holds it until the order ends: two orders never
// interleave their steps on one piece of hardware, whose state (a tool mounted, a box held)
// one order's later steps rely on.
//
// Who goes first: among orders waiting for a component, the higher priority, then the older
// order (the smaller id). A free component is taken only by an order that no better-ranked
// waiting order is waiting for.
//
// An order about to wait is told whether waiting would deadlock: whether a holder of what it
// wants waits, directly or through other orders, for something it holds itself. The MES then
// stops it instead, with that reason, rather than let both wait forever.
//
// Plain data, no threads: the MES's executor owns it.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace skillcell::mes {

struct OrderRank {
    std::int64_t order = 0;
    int priority = 0;
    /// Whether this order goes before `other` (higher priority, then older).
    [[nodiscard]] bool before(const OrderRank& other) const {
        return priority != other.priority ? priority > other.priority : order < other.order;
    }
};

class ResourceClaims {
public:
    /// The order holding `component`, if any.
    [[nodiscard]] std::optional<std::int64_t> holder(const std::string& component) const;
    /// Whether `who` may take `component` now: it is free or `who`'s already, and no order
    /// ranked before `who` waits for it, unless that order also waits for something `who`
    /// holds (it cannot go before `who` ends).
    [[nodiscard]] bool mayTake(const OrderRank& who, const std::string& component) const;
    /// `who` holds `component` from now until release(). Taking a held one is a caller's
    /// error: it is not taken (false).
    bool take(std::int64_t order, const std::string& component);
    /// The components `order` holds.
    [[nodiscard]] std::set<std::string> heldBy(std::int64_t order) const;

    /// `who` waits for any one of `components`. Returns the chain of a deadlock this wait
    /// would close ("order 3 waits for urn:b, held by order 4; order 4 waits for urn:a, held by
    /// order 3"): then `who` is not registered as waiting.
    [[nodiscard]] std::optional<std::string> wait(const OrderRank& who,
                                                  std::set<std::string> components);
    void stopWaiting(std::int64_t order);
    /// Everything `order` holds is free again; it waits for nothing.
    void release(std::int64_t order);

private:
    /// The orders holding what `order` waits for.
    [[nodiscard]] std::set<std::int64_t> blockers(std::int64_t order) const;

    std::map<std::string, std::int64_t> held_;  // component -> order
    struct Waiting {
        OrderRank rank;
        std::set<std::string> components;
    };
    std::map<std::int64_t, Waiting> waiting_;  // by order
};

}  // namespace skillcell::mes
