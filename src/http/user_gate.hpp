#pragma once
// UserGate: who an HTTP request comes from, by the cell's user database: the same users,
// passwords and roles as OPC UA sessions (ua/server/user_database.hpp).
//
// A request proves its user with a TLS client certificate that the database lists, or with
// HTTP Basic credentials (RFC 7617), which only travel inside TLS. Passwords are
// scrypt-hashed on purpose, which makes one check cost tens of milliseconds: a password
// that was right is remembered for a few minutes, by a SHA-256 of name and password, so
// that a client sending a query every few milliseconds is not slowed (nor the host loaded)
// by the hash. Wrong passwords are throttled per user name (PasswordThrottle): a name guessed
// at too often is refused for a while with BadTooManyOperations, without hashing.
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "http/password_throttle.hpp"
#include "ua/server/user_identity.hpp"

namespace skillcell::http {

class UserGate {
public:
    /// `users` null: a server without users (--insecure), where everyone is "anonymous"
    /// with `anonymousRoles`.
    explicit UserGate(std::shared_ptr<const ua::UserAuthenticator> users,
                      ua::RoleSet anonymousRoles = {},
                      std::chrono::seconds remember = std::chrono::seconds(300));

    /// The user of a request, from its client certificate (DER, empty: none), its session
    /// cookie (the Cookie header) or else its Authorization header. BadUserAccessDenied
    /// when none names a known user, or when the header is malformed; BadTooManyOperations
    /// while the name is throttled, with the seconds to wait in `retryAfter`.
    [[nodiscard]] ua::Result<ua::UserIdentity> identify(std::string_view authorization,
                                                        const ua::ByteString& peerCertificate,
                                                        std::string_view cookie = {},
                                                        std::chrono::seconds* retryAfter = nullptr);

    /// A browser's login: the user of `name` and `password`, and a new session token for
    /// the cookie kSessionCookie (random, 256 bits), valid while used within `idle`. The
    /// session keeps the name and password, in memory only, for a server that acts as its
    /// users (the dashboard opens OPC UA sessions as them); they go with the session.
    /// Throttled as identify() is.
    [[nodiscard]] ua::Result<std::pair<ua::UserIdentity, std::string>> login(
        std::string_view name, std::string_view password,
        std::chrono::seconds* retryAfter = nullptr);
    void logout(std::string_view cookie);
    /// The name and password that the live session of a Cookie header logged in with;
    /// nothing without one (a user known by Basic or a certificate, an ended session).
    [[nodiscard]] std::optional<std::pair<std::string, std::string>> sessionCredentials(
        std::string_view cookie);
    static constexpr std::string_view kSessionCookie = "skillcell_session";

    [[nodiscard]] bool hasUsers() const { return users_ != nullptr; }

private:
    struct Remembered {
        ua::UserIdentity user;
        std::chrono::steady_clock::time_point until;
        std::pair<std::string, std::string> credentials;  // sessions only: name, password
    };
    /// The live session of a Cookie header, its idle time renewed; under mutex_.
    Remembered* session(std::string_view cookie);
    /// The user of a name and password, by the database, throttled.
    ua::Result<ua::UserIdentity> checkPassword(std::string_view name, std::string_view password,
                                               std::chrono::seconds* retryAfter);
    std::shared_ptr<const ua::UserAuthenticator> users_;
    ua::RoleSet anonymousRoles_;
    std::chrono::seconds remember_;
    std::mutex mutex_;
    std::unordered_map<std::string, Remembered> remembered_;  // by SHA-256(name \0 password)
    std::unordered_map<std::string, Remembered> sessions_;    // by token; `until` slides
    std::chrono::seconds idle_{8 * 3600};
    PasswordThrottle throttle_;
};

}  // namespace skillcell::http
