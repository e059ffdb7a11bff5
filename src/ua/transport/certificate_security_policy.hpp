#pragma once
// CertificateSecurityPolicy: what the RSA and the ECC security policies share (OPC 10000-6,
// 6.7.2): both ends' application certificates and keys, the asymmetric header's checks, and
// the symmetric chunks after OpenSecureChannel, which both secure alike:
//
//   Sign:            [headers][sequence header, body, HMAC-SHA256]
//   SignAndEncrypt:  [headers][ AES-CBC: sequence header, body, padding, HMAC-SHA256 ]
//
// The signature always covers the chunk from its first byte, with the final message size
// already in the header. What differs, the OpenSecureChannel chunks, the nonces and the key
// derivation, is the subclass's: RsaSecurityPolicy, EccSecurityPolicy.
#include <memory>
#include <span>
#include <vector>

#include "ua/crypto/primitives.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/transport/security_policy.hpp"

namespace skillcell::ua {

class CertificateSecurityPolicy : public SecurityPolicy {
public:
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
    void setSecurityMode(MessageSecurityMode mode) override { mode_ = mode; }

    [[nodiscard]] MessageSecurityMode securityMode() const { return mode_; }
    [[nodiscard]] const ByteString& remoteCertificate() const override {
        return remoteCertificate_;
    }
    [[nodiscard]] const crypto::AsymmetricKey* remoteKey() const override { return &remoteKey_; }

protected:
    CertificateSecurityPolicy(const crypto::SecurityPolicyProfile& profile,
                              ByteString localCertificate, crypto::AsymmetricKey localKey,
                              ByteString remoteCertificate, crypto::AsymmetricKey remoteKey,
                              MessageSecurityMode mode);

    /// Checks that our key and the peer certificate's fit the profile (kind, and size in
    /// bits): the peer's key, or BadCertificateInvalid for the peer's, BadConfigurationError
    /// for ours.
    [[nodiscard]] static Result<crypto::AsymmetricKey> checkKeys(
        const crypto::SecurityPolicyProfile& profile, const crypto::AsymmetricKey& localKey,
        const ByteString& remoteCertificate);

    /// The OpenSecureChannel chunks, as the subclass's policy lays them out.
    [[nodiscard]] virtual std::size_t maxAsymmetricBodySize(std::size_t chunkSize,
                                                            std::size_t headerSize) const = 0;
    [[nodiscard]] virtual StatusCode protectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                       std::size_t headerSize) const = 0;
    [[nodiscard]] virtual StatusCode unprotectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                         std::size_t headerSize) const = 0;

    /// Splits derived key material into signing key, encrypting key and IV (6.7.5).
    [[nodiscard]] SymmetricKeys splitKeys(std::span<const std::uint8_t> material) const;
    /// The length of that material: signing key, encrypting key and a 16-byte IV.
    [[nodiscard]] std::size_t keyMaterialLength() const;

    const crypto::SecurityPolicyProfile& profile_;
    ByteString localCertificate_;
    crypto::AsymmetricKey localKey_;
    ByteString remoteCertificate_;
    crypto::AsymmetricKey remoteKey_;

private:
    [[nodiscard]] StatusCode protectSymmetric(std::vector<std::uint8_t>& chunk,
                                              std::size_t headerSize,
                                              const SymmetricKeys& keys) const;
    [[nodiscard]] StatusCode unprotectSymmetric(std::vector<std::uint8_t>& chunk,
                                                std::size_t headerSize,
                                                const SymmetricKeys& keys) const;

    std::vector<std::uint8_t> localThumbprint_;
    std::vector<std::uint8_t> remoteThumbprint_;
    MessageSecurityMode mode_;
};

/// The policy of `profile` (RSA or ECC) between our certificate and key and the peer's
/// certificate, its keys checked as the policy's create() checks them.
[[nodiscard]] Result<std::unique_ptr<CertificateSecurityPolicy>> createCertificateSecurityPolicy(
    const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
    crypto::AsymmetricKey localKey, ByteString remoteCertificate, MessageSecurityMode mode);

/// Writes a chunk's final size into its MessageSize field (bytes 4 to 7).
void patchMessageSize(std::vector<std::uint8_t>& chunk, std::size_t size);
/// Appends PaddingSize, the padding and (when `extra`) ExtraPaddingSize, so that
/// `chunk.size() - from + signatureSize` becomes a multiple of `block`.
void appendPadding(std::vector<std::uint8_t>& chunk, std::size_t from, std::size_t block,
                   std::size_t signatureSize, bool extra);
/// Checks and strips the padding that ends at `end` (signature already removed); returns
/// the new end, or 0 when the padding is malformed. The payload must keep at least the
/// sequence header after `from`.
[[nodiscard]] std::size_t stripPadding(const std::vector<std::uint8_t>& chunk, std::size_t from,
                                       std::size_t end, bool extra);

/// The first certificate of a DER chain (OPC UA sends a leaf followed by its issuers in
/// one ByteString): the first DER element, found from its header; empty when `der` does
/// not start with a DER SEQUENCE that fits. It does not decode the certificate: what
/// must be one is checked where it is validated or its key is read.
[[nodiscard]] std::vector<std::uint8_t> leafCertificate(std::span<const std::uint8_t> der);

/// The public key of `certificate` (DER, chain allowed): `channelKey`, the one a channel
/// decoded when it opened from `channelCertificate`, when the two leaves are the same (the
/// session handshake's certificates, and an X.509 user token that is the application's);
/// decoded now otherwise. Decoding costs about 130 us in OpenSSL 3.
[[nodiscard]] Result<crypto::AsymmetricKey> publicKeyOf(const ByteString& certificate,
                                                        const ByteString* channelCertificate,
                                                        const crypto::AsymmetricKey* channelKey);

/// What the session handshake signs: a certificate followed by a nonce (OPC 10000-4,
/// 5.6.2 and 5.6.3: the server's and the client's signatures, and an X.509 user token's).
[[nodiscard]] std::vector<std::uint8_t> certificateAndNonce(const ByteString& certificate,
                                                            const ByteString& nonce);

}  // namespace skillcell::ua
