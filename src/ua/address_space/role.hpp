#pragma once
// Roles: what a session's user may do. They follow the well-known roles of OPC 10000-18
// (4.4.1); skillcell uses four of them to decide access:
// Observer browses, reads and subscribes; Operator also calls skill methods and writes
// skill parameters; Engineer also calls the methods and writes the variables marked as
// configuration (Node::requiredRole, e.g. the world model's scene); Admin (ConfigureAdmin +
// SecurityAdmin) may do everything.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skillcell::ua {

enum class Role : std::uint8_t {
    Anonymous,
    AuthenticatedUser,
    Observer,
    Operator,
    Engineer,
    Admin
};

[[nodiscard]] std::string_view roleName(Role role);
/// "Observer", "operator", ... (case-insensitive); nothing for an unknown name.
[[nodiscard]] std::optional<Role> parseRole(std::string_view name);

class RoleSet {
public:
    RoleSet() = default;
    RoleSet(std::initializer_list<Role> roles) {
        for (Role r : roles) add(r);
    }
    void add(Role role) { bits_ |= bit(role); }
    [[nodiscard]] bool has(Role role) const { return (bits_ & bit(role)) != 0; }
    /// True when any role of the set grants at least `role`'s rights (Admin > Engineer >
    /// Operator > Observer).
    [[nodiscard]] bool atLeast(Role role) const;
    [[nodiscard]] std::vector<Role> roles() const;
    [[nodiscard]] std::string toString() const;  // "Observer,Operator"
    friend bool operator==(const RoleSet&, const RoleSet&) = default;

private:
    static std::uint32_t bit(Role r) { return 1U << static_cast<unsigned>(r); }
    std::uint32_t bits_ = 0;
};

}  // namespace skillcell::ua
