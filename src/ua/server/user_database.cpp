#include "ua/server/user_database.hpp"

#include <openssl/evp.h>
#include <openssl/kdf.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "common/atomic_file.hpp"
#include "ua/crypto/primitives.hpp"
#include "ua/transport/certificate_security_policy.hpp"
#include "ua/types/hex.hpp"

namespace skillcell::ua {
namespace {

constexpr std::uint64_t kScryptN = 16384;
constexpr std::uint64_t kScryptR = 8;
constexpr std::uint64_t kScryptP = 1;
constexpr std::size_t kSaltLength = 16;
constexpr std::size_t kHashLength = 32;
/// Parameters read from a file are bounded, so that a tampered file cannot make every
/// login take minutes or gigabytes.
constexpr std::uint64_t kMaxScryptN = 1U << 20;

std::vector<std::string_view> split(std::string_view s, char sep) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (;;) {
        const auto at = s.find(sep, start);
        out.push_back(s.substr(start, at == std::string_view::npos ? at : at - start));
        if (at == std::string_view::npos) return out;
        start = at + 1;
    }
}

std::optional<std::vector<std::uint8_t>> scrypt(std::string_view password,
                                                std::span<const std::uint8_t> salt, std::uint64_t n,
                                                std::uint64_t r, std::uint64_t p,
                                                std::size_t length) {
    std::vector<std::uint8_t> out(length);
    if (EVP_PBE_scrypt(password.data(), password.size(), salt.data(), salt.size(), n, r, p,
                       std::uint64_t{256} * 1024 * 1024, out.data(), out.size()) != 1) {
        return std::nullopt;
    }
    return out;
}

bool validName(const std::string& name) {
    return !name.empty() && name.size() <= 256 &&
           std::none_of(name.begin(), name.end(), [](char c) {
               return c == ':' || c == '#' || std::isspace(static_cast<unsigned char>(c)) != 0 ||
                      std::iscntrl(static_cast<unsigned char>(c)) != 0;
           });
}

std::string thumbprintHex(const ByteString& certificate) {
    return toHex(crypto::sha1(leafCertificate(certificate.bytes)));
}

bool parseRoles(std::string_view text, RoleSet& roles) {
    for (auto name : split(text, ',')) {
        const auto role = parseRole(name);
        if (!role) return false;
        roles.add(*role);
    }
    return true;
}

}  // namespace

Result<UserDatabase> UserDatabase::load(const std::filesystem::path& file, std::string* error) {
    std::ifstream in(file);
    if (!in) {
        if (!std::filesystem::exists(file)) return UserDatabase{};
        if (error != nullptr) *error = "cannot read " + file.string();
        return status::BadConfigurationError;
    }
    std::vector<UserRecord> users;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.empty() || line.front() == '#') continue;
        const auto fields = split(line, ':');
        UserRecord record;
        bool ok = fields.size() == 3;
        if (ok) {
            record.name = std::string(fields[0]);
            record.credential = std::string(fields[2]);
            ok = validName(record.name) && parseRoles(fields[1], record.roles) &&
                 (record.credential.starts_with("scrypt$") ||
                  record.credential.starts_with("x509$"));
        }
        if (!ok) {
            if (error != nullptr) {
                *error = file.string() + ":" + std::to_string(number) +
                         ": expected NAME:ROLE[,ROLE...]:scrypt$... or x509$...";
            }
            return status::BadConfigurationError;
        }
        users.push_back(std::move(record));
    }
    return UserDatabase(std::move(users));
}

StatusCode UserDatabase::save(const std::filesystem::path& file, std::string* error) const {
    std::ostringstream text;
    text << "# skillcell users: NAME:ROLES:CREDENTIAL (written by `skillcell user`)\n";
    for (const auto& u : users_)
        text << u.name << ':' << u.roles.toString() << ':' << u.credential << '\n';
    // 0600 before the hashes are in it.
    if (!writeFileAtomically(file, text.str(), 0600)) {
        if (error != nullptr) *error = "cannot replace " + file.string();
        return status::BadConfigurationError;
    }
    return status::Good;
}

StatusCode UserDatabase::setPassword(const std::string& name, RoleSet roles,
                                     const std::string& password) {
    if (!validName(name) || password.empty() || roles.roles().empty()) {
        return status::BadInvalidArgument;
    }
    const auto salt = crypto::randomBytes(kSaltLength);
    const auto hash = scrypt(password, salt, kScryptN, kScryptR, kScryptP, kHashLength);
    if (!hash) return status::BadInternalError;
    std::string credential = "scrypt$" + std::to_string(kScryptN) + "$" + std::to_string(kScryptR) +
                             "$" + std::to_string(kScryptP) + "$" + toHex(salt) + "$" +
                             toHex(*hash);
    remove(name);
    users_.push_back({name, roles, std::move(credential)});
    return status::Good;
}

StatusCode UserDatabase::setCertificate(const std::string& name, RoleSet roles,
                                        const ByteString& certificate) {
    return setCertificates(name, roles, {certificate});
}

StatusCode UserDatabase::setCertificates(const std::string& name, RoleSet roles,
                                         const std::vector<ByteString>& certificates) {
    // Decoded once here, so that a file of bytes that is not a certificate is refused now
    // (and nothing changes).
    if (!validName(name) || roles.roles().empty() || certificates.empty()) {
        return status::BadInvalidArgument;
    }
    for (const auto& certificate : certificates) {
        if (!crypto::AsymmetricKey::fromCertificate(certificate.bytes)) {
            return status::BadInvalidArgument;
        }
    }
    remove(name);
    for (const auto& certificate : certificates) {
        users_.push_back({name, roles, "x509$" + thumbprintHex(certificate)});
    }
    return status::Good;
}

bool UserDatabase::remove(const std::string& name) {
    return std::erase_if(users_, [&](const UserRecord& u) { return u.name == name; }) > 0;
}

Result<UserIdentity> UserDatabase::authenticatePassword(std::string_view userName,
                                                        std::string_view password) const {
    for (const auto& u : users_) {
        if (u.name != userName || !u.credential.starts_with("scrypt$")) continue;
        const auto parts = split(u.credential, '$');
        if (parts.size() != 6) return status::BadUserAccessDenied;
        const auto salt = fromHex(parts[4]);
        const auto expected = fromHex(parts[5]);
        if (!salt || !expected || expected->empty()) return status::BadUserAccessDenied;
        std::uint64_t n = 0;
        std::uint64_t r = 0;
        std::uint64_t p = 0;
        try {
            n = std::stoull(std::string(parts[1]));
            r = std::stoull(std::string(parts[2]));
            p = std::stoull(std::string(parts[3]));
        } catch (...) {
            return status::BadUserAccessDenied;
        }
        if (n > kMaxScryptN || r > 32 || p > 16) return status::BadUserAccessDenied;
        const auto hash = scrypt(password, *salt, n, r, p, expected->size());
        if (!hash || !crypto::equalConstantTime(*hash, *expected)) {
            return status::BadUserAccessDenied;
        }
        RoleSet roles = u.roles;
        roles.add(Role::AuthenticatedUser);
        return UserIdentity{u.name, roles};
    }
    // An unknown user costs as much as a known one: timing tells no names.
    (void)scrypt(password, std::vector<std::uint8_t>(kSaltLength), kScryptN, kScryptR, kScryptP,
                 kHashLength);
    return status::BadUserAccessDenied;
}

Result<UserIdentity> UserDatabase::authenticateCertificate(const ByteString& certificate) const {
    const std::string credential = "x509$" + thumbprintHex(certificate);
    for (const auto& u : users_) {
        if (u.credential == credential) {
            RoleSet roles = u.roles;
            roles.add(Role::AuthenticatedUser);
            return UserIdentity{u.name, roles};
        }
    }
    return status::BadUserAccessDenied;
}

}  // namespace skillcell::ua
