#include "http/user_gate.hpp"

#include <openssl/evp.h>
#include <openssl/rand.h>

#include <array>

#include <cctype>
#include <optional>
#include <vector>

namespace skillcell::http {
namespace {

constexpr std::size_t kMaxRemembered = 256;  // beyond: forget all (a flood of users)

// The bytes of standard base64 `text` (RFC 4648, 4), by OpenSSL; nothing when malformed.
std::optional<std::string> fromBase64(std::string_view text) {
    if (text.empty() || text.size() % 4 != 0 || text.size() > 4096) return std::nullopt;
    std::vector<unsigned char> out(text.size() / 4 * 3);
    const int n = EVP_DecodeBlock(out.data(), reinterpret_cast<const unsigned char*>(text.data()),
                                  static_cast<int>(text.size()));
    if (n < 0) return std::nullopt;
    std::size_t size = static_cast<std::size_t>(n);
    // EVP_DecodeBlock counts the padding as zero bytes.
    for (std::size_t i = text.size(); i > 0 && text[i - 1] == '='; --i) --size;
    return std::string(reinterpret_cast<const char*>(out.data()), size);
}

std::string sha256(std::string_view a, std::string_view b) {
    std::string input(a);
    input.push_back('\0');
    input.append(b);
    std::string digest(EVP_MAX_MD_SIZE, '\0');
    unsigned int size = 0;
    if (EVP_Digest(input.data(), input.size(), reinterpret_cast<unsigned char*>(digest.data()),
                   &size, EVP_sha256(), nullptr) != 1) {
        return {};
    }
    digest.resize(size);
    return digest;
}

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or empty.
std::string_view cookieValue(std::string_view header, std::string_view name) {
    while (!header.empty()) {
        const auto semicolon = header.find(';');
        auto pair = header.substr(0, semicolon);
        header =
            semicolon == std::string_view::npos ? std::string_view() : header.substr(semicolon + 1);
        while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
        if (pair.size() > name.size() && pair.substr(0, name.size()) == name &&
            pair[name.size()] == '=') {
            return pair.substr(name.size() + 1);
        }
    }
    return {};
}

std::string newToken() {
    std::array<unsigned char, 32> bytes{};
    if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1) return {};
    static constexpr std::string_view kHex = "0123456789abcdef";
    std::string token;
    for (const unsigned char b : bytes) {
        token += kHex[b >> 4U];
        token += kHex[b & 0x0fU];
    }
    return token;
}

}  // namespace

UserGate::UserGate(std::shared_ptr<const ua::UserAuthenticator> users, ua::RoleSet anonymousRoles,
                   std::chrono::seconds remember)
    : users_(std::move(users)), anonymousRoles_(anonymousRoles), remember_(remember) {}

ua::Result<ua::UserIdentity> UserGate::checkPassword(std::string_view name,
                                                     std::string_view password,
                                                     std::chrono::seconds* retryAfter) {
    if (auto wait = throttle_.refusedFor(name)) {
        if (retryAfter != nullptr) *retryAfter = *wait;
        return ua::status::BadTooManyOperations;
    }
    auto user = users_->authenticatePassword(name, password);
    if (user) {
        throttle_.succeeded(name);
    } else {
        throttle_.failed(name);
    }
    return user;
}

ua::Result<ua::UserIdentity> UserGate::identify(std::string_view authorization,
                                                const ua::ByteString& peerCertificate,
                                                std::string_view cookie,
                                                std::chrono::seconds* retryAfter) {
    if (users_ == nullptr) return ua::UserIdentity{"anonymous", anonymousRoles_};
    if (!peerCertificate.empty()) {
        if (auto user = users_->authenticateCertificate(peerCertificate)) return user;
    }
    {
        const std::lock_guard lock(mutex_);
        if (const Remembered* s = session(cookie)) return s->user;
    }
    // "Basic" 1*SP token68 (RFC 7617, 2); the scheme name is case-insensitive.
    constexpr std::string_view kBasic = "basic ";
    if (authorization.size() <= kBasic.size()) return ua::status::BadUserAccessDenied;
    for (std::size_t i = 0; i < kBasic.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(authorization[i])) != kBasic[i]) {
            return ua::status::BadUserAccessDenied;
        }
    }
    auto text = authorization.substr(kBasic.size());
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    const auto decoded = fromBase64(text);
    if (!decoded) return ua::status::BadUserAccessDenied;
    const auto colon = decoded->find(':');
    if (colon == std::string::npos || colon == 0) return ua::status::BadUserAccessDenied;
    const std::string_view name = std::string_view(*decoded).substr(0, colon);
    const std::string_view password = std::string_view(*decoded).substr(colon + 1);

    const std::string key = sha256(name, password);
    const auto now = std::chrono::steady_clock::now();
    {
        const std::lock_guard lock(mutex_);
        if (auto it = remembered_.find(key); it != remembered_.end()) {
            if (it->second.until > now) return it->second.user;
            remembered_.erase(it);
        }
    }
    auto user = checkPassword(name, password, retryAfter);
    if (!user) return user.status();
    if (!key.empty()) {
        const std::lock_guard lock(mutex_);
        if (remembered_.size() >= kMaxRemembered) remembered_.clear();
        remembered_[key] = Remembered{*user, now + remember_, {}};
    }
    return user;
}

ua::Result<std::pair<ua::UserIdentity, std::string>> UserGate::login(
    std::string_view name, std::string_view password, std::chrono::seconds* retryAfter) {
    if (users_ == nullptr) return ua::status::BadUserAccessDenied;
    auto user = checkPassword(name, password, retryAfter);
    if (!user) return user.status();
    std::string token = newToken();
    if (token.empty()) return ua::status::BadInternalError;
    const std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (sessions_.size() >= kMaxRemembered * 4) {  // forget the expired ones first
        std::erase_if(sessions_, [now](const auto& s) { return s.second.until <= now; });
    }
    sessions_[token] = Remembered{*user, now + idle_, {std::string(name), std::string(password)}};
    return std::pair{*user, std::move(token)};
}

UserGate::Remembered* UserGate::session(std::string_view cookie) {
    const auto token = cookieValue(cookie, kSessionCookie);
    if (token.empty()) return nullptr;
    const auto it = sessions_.find(std::string(token));
    if (it == sessions_.end()) return nullptr;
    const auto now = std::chrono::steady_clock::now();
    if (it->second.until <= now) {
        sessions_.erase(it);
        return nullptr;
    }
    it->second.until = now + idle_;
    return &it->second;
}

std::optional<std::pair<std::string, std::string>> UserGate::sessionCredentials(
    std::string_view cookie) {
    const std::lock_guard lock(mutex_);
    const Remembered* s = session(cookie);
    if (s == nullptr) return std::nullopt;
    return s->credentials;
}

void UserGate::logout(std::string_view cookie) {
    const auto token = cookieValue(cookie, kSessionCookie);
    const std::lock_guard lock(mutex_);
    sessions_.erase(std::string(token));
}

}  // namespace skillcell::http
