#pragma once
// SecurityPolicy: the cryptography a secure channel applies to its chunks (OPC 10000-7
// security policies, OPC 10000-6, 6.7). The channel asks the policy how many bytes a chunk
// loses to padding and signature, and hands it whole chunks to sign/encrypt or to verify/
// decrypt: with the asymmetric keys (certificates) for OpenSecureChannel, with the
// symmetric keys of a security token for everything else. The channel owns the tokens and
// their keys (a renewal has two at once); the policy owns the algorithms and certificates.
// None implements it as identity; RsaSecurityPolicy (rsa_security_policy.hpp) implements
// Basic256Sha256, Aes128_Sha256_RsaOaep and Aes256_Sha256_RsaPss, EccSecurityPolicy
// (ecc_security_policy.hpp) ECC_nistP256.
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "ua/crypto/primitives.hpp"
#include "ua/messages/common.hpp"
#include "ua/types/result.hpp"
#include "ua/types/status_code.hpp"

namespace skillcell::ua {

inline constexpr std::string_view kSecurityPolicyNoneUri =
    "http://opcfoundation.org/UA/SecurityPolicy#None";

/// The keys that secure the messages of one direction under one token (OPC 10000-6, 6.7.5).
struct SymmetricKeys {
    std::vector<std::uint8_t> signingKey;
    std::vector<std::uint8_t> encryptingKey;
    std::vector<std::uint8_t> initializationVector;
};

/// A token's keys as one side sees them: what it sends with and what it receives with.
struct ChannelKeys {
    SymmetricKeys sending;
    SymmetricKeys receiving;
};

/// The security header of an OpenSecureChannel chunk (OPC 10000-6, 6.7.2.3).
struct AsymmetricSecurityHeader {
    String securityPolicyUri;
    ByteString senderCertificate;
    ByteString receiverCertificateThumbprint;
};

class SecurityPolicy {
public:
    virtual ~SecurityPolicy() = default;
    [[nodiscard]] virtual std::string_view uri() const = 0;

    /// Bytes a chunk's body may carry when the chunk is at most `chunkSize` bytes, after
    /// headers of `headerSize` bytes, padding and signature are accounted for.
    [[nodiscard]] virtual std::size_t maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                                  bool asymmetric) const = 0;
    /// Applies padding, signature and encryption to a complete chunk in place; `headerSize`
    /// bytes at the start stay in clear text. `keys` are the sending keys of the token in
    /// use, or nullptr for an OpenSecureChannel chunk (asymmetric). The message size field
    /// is patched by the caller afterwards.
    [[nodiscard]] virtual StatusCode protect(std::vector<std::uint8_t>& chunk,
                                             std::size_t headerSize, const SymmetricKeys* keys) = 0;
    /// Decrypts and verifies a received chunk in place and removes padding and signature
    /// (`keys`: the receiving keys of the chunk's token, nullptr for OpenSecureChannel).
    /// BadSecurityChecksFailed on a bad signature or padding.
    [[nodiscard]] virtual StatusCode unprotect(std::vector<std::uint8_t>& chunk,
                                               std::size_t headerSize,
                                               const SymmetricKeys* keys) = 0;
    /// The sender certificate and receiver thumbprint carried in the asymmetric header.
    [[nodiscard]] virtual std::vector<std::uint8_t> localCertificate() const { return {}; }
    [[nodiscard]] virtual std::vector<std::uint8_t> remoteThumbprint() const { return {}; }
    /// The peer's certificate (DER, chain allowed); empty for None.
    [[nodiscard]] virtual const ByteString& remoteCertificate() const {
        static const ByteString kNone;
        return kNone;
    }
    /// The public key of remoteCertificate()'s leaf, decoded once for the channel (the
    /// session services verify signatures with it); nullptr for None.
    [[nodiscard]] virtual const crypto::AsymmetricKey* remoteKey() const { return nullptr; }
    /// Checks a received asymmetric header beyond its policy URI: that it names our
    /// certificate and comes from the certificate this channel was opened with.
    [[nodiscard]] virtual StatusCode checkAsymmetricHeader(
        const AsymmetricSecurityHeader& /*header*/) const {
        return status::Good;
    }

    /// The length of the nonces exchanged in OpenSecureChannel; 0 for None.
    [[nodiscard]] virtual std::size_t nonceLength() const { return 0; }
    /// Our nonce for the next OpenSecureChannel: random bytes, or (ECC) the public half of
    /// a new EphemeralKey whose private half deriveKeys() then uses.
    [[nodiscard]] virtual ByteString newNonce() {
        return ByteString(crypto::randomBytes(nonceLength()));
    }
    /// The keys of a new token from the two nonces; `client` says which side we are.
    /// BadNonceInvalid when the peer's nonce cannot be used (ECC: not a point of the curve).
    [[nodiscard]] virtual Result<ChannelKeys> deriveKeys(
        std::span<const std::uint8_t> /*clientNonce*/,
        std::span<const std::uint8_t> /*serverNonce*/, bool /*client*/) const {
        return ChannelKeys{};
    }
    /// Sign or SignAndEncrypt for the symmetric chunks; set once the mode is agreed.
    virtual void setSecurityMode(MessageSecurityMode /*mode*/) {}
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
                                     std::size_t /*headerSize*/,
                                     const SymmetricKeys* /*keys*/) override {
        return status::Good;
    }
    [[nodiscard]] StatusCode unprotect(std::vector<std::uint8_t>& /*chunk*/,
                                       std::size_t /*headerSize*/,
                                       const SymmetricKeys* /*keys*/) override {
        return status::Good;
    }
};

}  // namespace skillcell::ua
