#include "ua/address_space/role.hpp"

#include <array>
#include <cctype>

namespace skillcell::ua {
namespace {

constexpr std::array<std::pair<Role, std::string_view>, 6> kNames{{
    {Role::Anonymous, "Anonymous"},
    {Role::AuthenticatedUser, "AuthenticatedUser"},
    {Role::Observer, "Observer"},
    {Role::Operator, "Operator"},
    {Role::Engineer, "Engineer"},
    {Role::Admin, "Admin"},
}};

int rank(Role r) {
    switch (r) {
        case Role::Observer:
            return 1;
        case Role::Operator:
            return 2;
        case Role::Engineer:
            return 3;
        case Role::Admin:
            return 4;
        default:
            return 0;
    }
}

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i]))) {
            return false;
        }
    }
    return true;
}

}  // namespace

std::string_view roleName(Role role) {
    for (const auto& [r, n] : kNames) {
        if (r == role) return n;
    }
    return "?";
}

std::optional<Role> parseRole(std::string_view name) {
    for (const auto& [r, n] : kNames) {
        if (equalsIgnoringCase(n, name)) return r;
    }
    return std::nullopt;
}

bool RoleSet::atLeast(Role role) const {
    const int needed = rank(role);
    for (const auto& [r, n] : kNames) {
        if (has(r) && rank(r) >= needed && rank(r) > 0) return true;
    }
    return needed == 0;
}

std::vector<Role> RoleSet::roles() const {
    std::vector<Role> out;
    for (const auto& [r, n] : kNames) {
        if (has(r)) out.push_back(r);
    }
    return out;
}

std::string RoleSet::toString() const {
    std::string out;
    for (Role r : roles()) {
        if (!out.empty()) out += ',';
        out += roleName(r);
    }
    return out;
}

}  // namespace skillcell::ua
