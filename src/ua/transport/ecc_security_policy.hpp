#pragma once
// EccSecurityPolicy: ECC_nistP256 (OPC 10000-7; the handshake of OPC 10000-6, 6.8.1). ECC
// signs but cannot encrypt, so the OpenSecureChannel chunks are signed only, in either mode:
//
//     [clear headers][sequence header, body, ECDSA signature r || s]
//
// and each side's nonce is the public half of an EphemeralKey made for that one exchange:
// both derive the same secret from their own private half and the other's public one (ECDH),
// and the keys from it by HKDF. An eavesdropper sees both public halves and learns nothing;
// the signatures tie them to the two certificates. The symmetric chunks are
// CertificateSecurityPolicy's (AES128-CBC, HMAC-SHA256).
//
// Why: an ECDSA P-256 signature costs about a tenth of an RSA-2048 one, and a cell's
// components handshake with every component that starts (docs/security.md has the numbers).
#include <memory>
#include <optional>

#include "ua/transport/certificate_security_policy.hpp"

namespace skillcell::ua {

class EccSecurityPolicy final : public CertificateSecurityPolicy {
public:
    EccSecurityPolicy(const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
                      crypto::AsymmetricKey localKey, ByteString remoteCertificate,
                      crypto::AsymmetricKey remoteKey, MessageSecurityMode mode)
        : CertificateSecurityPolicy(profile, std::move(localCertificate), std::move(localKey),
                                    std::move(remoteCertificate), std::move(remoteKey), mode) {}

    /// Builds the policy for a peer certificate, checking that both keys are on the policy's
    /// curve (BadCertificateInvalid for the peer's, BadConfigurationError for ours).
    [[nodiscard]] static Result<std::unique_ptr<EccSecurityPolicy>> create(
        const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
        crypto::AsymmetricKey localKey, ByteString remoteCertificate, MessageSecurityMode mode);

    /// A new EphemeralKey's public half; the pair is kept for the deriveKeys() that follows.
    [[nodiscard]] ByteString newNonce() override;
    /// ECDH of our EphemeralKey with the peer's nonce, then HKDF with the salts of 6.8.1:
    /// L | "opcua-client" | ClientNonce | ServerNonce for the client's keys, and
    /// L | "opcua-server" | ServerNonce | ClientNonce for the server's, each also the info.
    [[nodiscard]] Result<ChannelKeys> deriveKeys(std::span<const std::uint8_t> clientNonce,
                                                 std::span<const std::uint8_t> serverNonce,
                                                 bool client) const override;

private:
    [[nodiscard]] std::size_t maxAsymmetricBodySize(std::size_t chunkSize,
                                                    std::size_t headerSize) const override;
    [[nodiscard]] StatusCode protectAsymmetric(std::vector<std::uint8_t>& chunk,
                                               std::size_t headerSize) const override;
    [[nodiscard]] StatusCode unprotectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                 std::size_t headerSize) const override;

    std::optional<crypto::EphemeralKey> ephemeral_;
};

}  // namespace skillcell::ua
