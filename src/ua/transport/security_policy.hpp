#pragma once
// SecurityPolicy: the cryptography a secure channel applies to its chunks (OPC 10000-7
// security policies, OPC 10000-6, 6.7). The channel asks the policy how many bytes a chunk
// loses to padding and signature, and hands it whole chunks to sign/encrypt or to verify/
// decrypt. None implements it as identity; Basic256Sha256 and the Aes policies (a later
// issue) implement it with OpenSSL without the channel changing.
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "ua/types/status_code.hpp"

namespace skillcell::ua {

inline constexpr std::string_view kSecurityPolicyNoneUri =
    "http://opcfoundation.org/UA/SecurityPolicy#None";

class SecurityPolicy {
public:
    virtual ~SecurityPolicy() = default;
    [[nodiscard]] virtual std::string_view uri() const = 0;

    /// Bytes a chunk's body may carry when the chunk is at most `chunkSize` bytes, after
    /// headers of `headerSize` bytes, padding and signature are accounted for.
    [[nodiscard]] virtual std::size_t maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                                  bool asymmetric) const = 0;
    /// Applies padding, signature and encryption to a complete chunk in place; `headerSize`
    /// bytes at the start stay in clear text. The message size field is patched by the
    /// caller afterwards.
    [[nodiscard]] virtual StatusCode protect(std::vector<std::uint8_t>& chunk,
                                             std::size_t headerSize, bool asymmetric) = 0;
    /// Decrypts and verifies a received chunk in place and removes padding and signature.
    /// BadSecurityChecksFailed on a bad signature or padding.
    [[nodiscard]] virtual StatusCode unprotect(std::vector<std::uint8_t>& chunk,
                                               std::size_t headerSize, bool asymmetric) = 0;
    /// The sender certificate and receiver thumbprint carried in the asymmetric header.
    [[nodiscard]] virtual std::vector<std::uint8_t> localCertificate() const { return {}; }
    [[nodiscard]] virtual std::vector<std::uint8_t> remoteThumbprint() const { return {}; }
};

/// SecurityPolicy None: no signature, no encryption.
class SecurityPolicyNone final : public SecurityPolicy {
public:
    [[nodiscard]] std::string_view uri() const override { return kSecurityPolicyNoneUri; }
    [[nodiscard]] std::size_t maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                          bool /*asymmetric*/) const override {
        return chunkSize > headerSize ? chunkSize - headerSize : 0;
    }
    [[nodiscard]] StatusCode protect(std::vector<std::uint8_t>& /*chunk*/,
                                     std::size_t /*headerSize*/, bool /*asymmetric*/) override {
        return status::Good;
    }
    [[nodiscard]] StatusCode unprotect(std::vector<std::uint8_t>& /*chunk*/,
                                       std::size_t /*headerSize*/, bool /*asymmetric*/) override {
        return status::Good;
    }
};

}  // namespace skillcell::ua
