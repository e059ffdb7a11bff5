#pragma once
// RsaSecurityPolicy: the RSA-based security policies (Basic256Sha256, Aes128_Sha256_RsaOaep,
// Aes256_Sha256_RsaPss) applied to chunks as OPC 10000-6, 6.7.2 lays them out:
//
//   OpenSecureChannel (always signed and encrypted, whatever the mode):
//     [clear headers][ RSA-encrypted: sequence header, body, padding, RSA signature ]
//     signed with our private key, encrypted with the peer's public key.
//   Other chunks, Sign:            [headers][sequence header, body, HMAC-SHA256]
//   Other chunks, SignAndEncrypt:  [headers][ AES-CBC: sequence header, body, padding, HMAC ]
//
// The signature always covers the chunk from its first byte, with the final message size
// already in the header. Padding is PaddingSize, that many bytes of PaddingSize, and for
// RSA keys above 2048 bits an ExtraPaddingSize byte.
#include <vector>

#include "ua/crypto/primitives.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/transport/security_policy.hpp"

namespace skillcell::ua {

class RsaSecurityPolicy final : public SecurityPolicy {
public:
    /// `localCertificate` is our DER certificate (a chain is allowed), `localKey` its
    /// private key; `remoteCertificate` the peer's DER certificate (chain allowed).
    RsaSecurityPolicy(const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
                      crypto::RsaKey localKey, ByteString remoteCertificate,
                      crypto::RsaKey remoteKey, MessageSecurityMode mode);

    /// Builds the policy for a peer certificate, checking that both keys have a size the
    /// policy allows (BadCertificateInvalid for the peer's, BadConfigurationError for ours).
    [[nodiscard]] static Result<std::unique_ptr<RsaSecurityPolicy>> create(
        const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
        crypto::RsaKey localKey, ByteString remoteCertificate, MessageSecurityMode mode);

    [[nodiscard]] std::string_view uri() const override { return profile_.uri; }
    [[nodiscard]] std::size_t maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                          bool asymmetric) const override;
    [[nodiscard]] StatusCode protect(std::vector<std::uint8_t>& chunk, std::size_t headerSize,
                                     const SymmetricKeys* keys) override;
    [[nodiscard]] StatusCode unprotect(std::vector<std::uint8_t>& chunk, std::size_t headerSize,
                                       const SymmetricKeys* keys) override;
    [[nodiscard]] std::vector<std::uint8_t> localCertificate() const override {
        return localCertificate_.bytes;
    }
    [[nodiscard]] std::vector<std::uint8_t> remoteThumbprint() const override {
        return remoteThumbprint_;
    }
    [[nodiscard]] StatusCode checkAsymmetricHeader(
        const AsymmetricSecurityHeader& header) const override;
    [[nodiscard]] std::size_t nonceLength() const override { return profile_.nonceLength; }
    [[nodiscard]] ChannelKeys deriveKeys(std::span<const std::uint8_t> clientNonce,
                                         std::span<const std::uint8_t> serverNonce,
                                         bool client) const override;
    void setSecurityMode(MessageSecurityMode mode) override { mode_ = mode; }

    [[nodiscard]] MessageSecurityMode securityMode() const { return mode_; }
    [[nodiscard]] const ByteString& remoteCertificate() const override {
        return remoteCertificate_;
    }
    [[nodiscard]] const crypto::RsaKey* remoteKey() const override { return &remoteKey_; }

private:
    [[nodiscard]] StatusCode protectAsymmetric(std::vector<std::uint8_t>& chunk,
                                               std::size_t headerSize) const;
    [[nodiscard]] StatusCode unprotectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                 std::size_t headerSize) const;
    [[nodiscard]] StatusCode protectSymmetric(std::vector<std::uint8_t>& chunk,
                                              std::size_t headerSize,
                                              const SymmetricKeys& keys) const;
    [[nodiscard]] StatusCode unprotectSymmetric(std::vector<std::uint8_t>& chunk,
                                                std::size_t headerSize,
                                                const SymmetricKeys& keys) const;

    const crypto::SecurityPolicyProfile& profile_;
    ByteString localCertificate_;
    crypto::RsaKey localKey_;
    ByteString remoteCertificate_;
    crypto::RsaKey remoteKey_;
    std::vector<std::uint8_t> localThumbprint_;
    std::vector<std::uint8_t> remoteThumbprint_;
    MessageSecurityMode mode_;
};

/// The first certificate of a DER chain (OPC UA sends a leaf followed by its issuers in
/// one ByteString): the first DER element, found from its header; empty when `der` does
/// not start with a DER SEQUENCE that fits. It does not decode the certificate: what
/// must be one is checked where it is validated or its key is read.
[[nodiscard]] std::vector<std::uint8_t> leafCertificate(std::span<const std::uint8_t> der);

/// The public key of `certificate` (DER, chain allowed): `channelKey`, the one a channel
/// decoded when it opened from `channelCertificate`, when the two leaves are the same (the
/// session handshake's certificates, and an X.509 user token that is the application's);
/// decoded now otherwise. Decoding costs about 130 us in OpenSSL 3.
[[nodiscard]] Result<crypto::RsaKey> publicKeyOf(const ByteString& certificate,
                                                 const ByteString* channelCertificate,
                                                 const crypto::RsaKey* channelKey);

/// What the session handshake signs: a certificate followed by a nonce (OPC 10000-4,
/// 5.6.2 and 5.6.3: the server's and the client's signatures, and an X.509 user token's).
[[nodiscard]] std::vector<std::uint8_t> certificateAndNonce(const ByteString& certificate,
                                                            const ByteString& nonce);

}  // namespace skillcell::ua
