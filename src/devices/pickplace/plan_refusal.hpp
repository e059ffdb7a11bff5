#pragma once
// How a planner says no: the reason into the caller's `why` (if it asked), and no plan.
#include <optional>
#include <string>

namespace skillcell::devices::pickplace {

inline std::nullopt_t refuse(std::string* why, std::string reason) {
    if (why != nullptr) *why = std::move(reason);
    return std::nullopt;
}

}  // namespace skillcell::devices::pickplace
