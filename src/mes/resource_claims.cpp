#include "mes/resource_claims.hpp"

#include <algorithm>
#include <functional>

namespace skillcell::mes {

std::optional<std::int64_t> ResourceClaims::holder(const std::string& component) const {
    const auto it = held_.find(component);
    if (it == held_.end()) return std::nullopt;
    return it->second;
}

bool ResourceClaims::mayTake(const OrderRank& who, const std::string& component) const {
    const auto h = holder(component);
    if (h) return *h == who.order;
    for (const auto& [order, w] : waiting_) {
        if (order == who.order || !w.rank.before(who) || !w.components.contains(component)) {
            continue;
        }
        // An order that waits for something `who` holds cannot go first: `who` must run to its
        // end and free it. Letting it wait for `who` and `who` for it is a deadlock that no
        // holder closes (a resumed order that lost a claim the MES's former life had).
        const bool blockedByWho = std::any_of(
            w.components.begin(), w.components.end(),
            [&](const std::string& c) { return holder(c) == std::optional(who.order); });
        if (!blockedByWho) return false;
    }
    return true;
}

bool ResourceClaims::take(std::int64_t order, const std::string& component) {
    const auto [it, inserted] = held_.emplace(component, order);
    return inserted || it->second == order;
}

std::set<std::string> ResourceClaims::heldBy(std::int64_t order) const {
    std::set<std::string> out;
    for (const auto& [component, h] : held_) {
        if (h == order) out.insert(component);
    }
    return out;
}

std::set<std::int64_t> ResourceClaims::blockers(std::int64_t order) const {
    std::set<std::int64_t> out;
    const auto w = waiting_.find(order);
    if (w == waiting_.end()) return out;
    for (const auto& c : w->second.components) {
        if (const auto h = holder(c); h && *h != order) out.insert(*h);
    }
    return out;
}

std::optional<std::string> ResourceClaims::wait(const OrderRank& who,
                                                std::set<std::string> components) {
    waiting_[who.order] = Waiting{who, std::move(components)};
    // A deadlock is a path of "waits for what X holds" from `who` back to `who`: a depth-first
    // search over the orders, each visited once, that keeps the path for the reason.
    std::vector<std::int64_t> path{who.order};
    std::set<std::int64_t> visited{who.order};
    const std::function<bool(std::int64_t)> reaches = [&](std::int64_t from) -> bool {
        for (const std::int64_t next : blockers(from)) {
            if (next == who.order) return true;
            if (!visited.insert(next).second) continue;
            path.push_back(next);
            if (reaches(next)) return true;
            path.pop_back();
        }
        return false;
    };
    if (!reaches(who.order)) return std::nullopt;
    path.push_back(who.order);
    std::string chain;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const auto& wanted = waiting_.at(path[i]).components;
        std::string what;
        for (const auto& c : wanted) {
            if (holder(c) == path[i + 1]) what += (what.empty() ? "" : " or ") + c;
        }
        chain += (chain.empty() ? "" : "; ") + std::string("order ") + std::to_string(path[i]) +
                 " waits for " + what + ", held by order " + std::to_string(path[i + 1]);
    }
    waiting_.erase(who.order);
    return chain;
}

void ResourceClaims::stopWaiting(std::int64_t order) {
    waiting_.erase(order);
}

void ResourceClaims::release(std::int64_t order) {
    std::erase_if(held_, [order](const auto& entry) { return entry.second == order; });
    waiting_.erase(order);
}

}  // namespace skillcell::mes
