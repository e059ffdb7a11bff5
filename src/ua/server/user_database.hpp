#pragma once
// UserDatabase: the users a server knows, in a text file an operator can read and back up,
// one user per line:
//
//   # comment
//   alice:Operator:scrypt$16384$8$1$<salt hex>$<hash hex>
//   cell-mes:Operator,Engineer:x509$<SHA-1 thumbprint of the user certificate, hex>
//
// Passwords are stored only as scrypt hashes (N=16384, r=8, p=1, 16-byte salt, 32-byte
// hash); there is no built-in user and no default password. The file is written
// atomically with mode 0600. A line that cannot be parsed makes load() fail with its line
// number: a half-read user list would lock people out or let the wrong ones in.
#include <filesystem>
#include <string>
#include <vector>

#include "ua/server/user_identity.hpp"

namespace skillcell::ua {

struct UserRecord {
    std::string name;
    RoleSet roles;
    std::string credential;  // "scrypt$..." or "x509$<thumbprint>"
};

class UserDatabase final : public UserAuthenticator {
public:
    UserDatabase() = default;
    explicit UserDatabase(std::vector<UserRecord> users) : users_(std::move(users)) {}

    /// Reads the file; an absent file is an empty database. BadConfigurationError with
    /// `error` naming the line for a malformed one.
    [[nodiscard]] static Result<UserDatabase> load(const std::filesystem::path& file,
                                                   std::string* error = nullptr);
    [[nodiscard]] StatusCode save(const std::filesystem::path& file,
                                  std::string* error = nullptr) const;

    /// Adds or replaces a user with a password (hashed here). BadInvalidArgument for a name
    /// with ':' or whitespace, an empty password, or no role.
    [[nodiscard]] StatusCode setPassword(const std::string& name, RoleSet roles,
                                         const std::string& password);
    /// Adds or replaces a user identified by an X.509 certificate (DER).
    [[nodiscard]] StatusCode setCertificate(const std::string& name, RoleSet roles,
                                            const ByteString& certificate);
    /// The same with several certificates, each a line of its own: an application with an
    /// RSA and an ECC certificate is one user by either.
    [[nodiscard]] StatusCode setCertificates(const std::string& name, RoleSet roles,
                                             const std::vector<ByteString>& certificates);
    /// False when there was no such user.
    bool remove(const std::string& name);
    [[nodiscard]] const std::vector<UserRecord>& users() const { return users_; }

    [[nodiscard]] Result<UserIdentity> authenticatePassword(
        std::string_view userName, std::string_view password) const override;
    [[nodiscard]] Result<UserIdentity> authenticateCertificate(
        const ByteString& certificate) const override;

private:
    std::vector<UserRecord> users_;
};

}  // namespace skillcell::ua
