#pragma once
// Who a session acts for (ActivateSession's user identity token) and the interface that
// checks credentials. What the roles allow is decided in the address space services
// (ua/address_space/role.hpp).
#include <string>
#include <string_view>

#include "ua/address_space/role.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

struct UserIdentity {
    std::string name;  // "anonymous", the user name, or the certificate's subject
    RoleSet roles;
};

/// Checks user credentials. BadUserAccessDenied for a wrong name or password or an unknown
/// certificate; no other detail goes back to the client (it would help guessing).
class UserAuthenticator {
public:
    virtual ~UserAuthenticator() = default;
    [[nodiscard]] virtual Result<UserIdentity> authenticatePassword(
        std::string_view userName, std::string_view password) const = 0;
    [[nodiscard]] virtual Result<UserIdentity> authenticateCertificate(
        const ByteString& certificate) const = 0;
};

}  // namespace skillcell::ua
