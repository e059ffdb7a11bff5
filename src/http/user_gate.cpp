#include "http/user_gate.hpp"

#include <openssl/evp.h>

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

}  // namespace

UserGate::UserGate(std::shared_ptr<const ua::UserAuthenticator> users, ua::RoleSet anonymousRoles,
                   std::chrono::seconds remember)
    : users_(std::move(users)), anonymousRoles_(anonymousRoles), remember_(remember) {}

ua::Result<ua::UserIdentity> UserGate::identify(std::string_view authorization,
                                                const ua::ByteString& peerCertificate) {
    if (users_ == nullptr) return ua::UserIdentity{"anonymous", anonymousRoles_};
    if (!peerCertificate.empty()) {
        if (auto user = users_->authenticateCertificate(peerCertificate)) return user;
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
    auto user = users_->authenticatePassword(name, password);
    if (!user) return user.status();
    if (!key.empty()) {
        const std::lock_guard lock(mutex_);
        if (remembered_.size() >= kMaxRemembered) remembered_.clear();
        remembered_[key] = Remembered{*user, now + remember_};
    }
    return user;
}

}  // namespace skillcell::http
