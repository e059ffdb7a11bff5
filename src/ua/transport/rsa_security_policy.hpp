#pragma once
// RsaSecurityPolicy: the RSA-based security policies (Basic256Sha256, Aes128_Sha256_RsaOaep,
// Aes256_Sha256_RsaPss). Their OpenSecureChannel chunks (OPC 10000-6, 6.7.2) are always
// signed and encrypted, whatever the mode:
//
//     [clear headers][ RSA-encrypted: sequence header, body, padding, RSA signature ]
//
// signed with our private key, encrypted with the peer's public key. Padding is
// PaddingSize, that many bytes of PaddingSize, and for RSA keys above 2048 bits an
// ExtraPaddingSize byte. The nonces are random; the keys come from them by P_SHA256 (6.7.5).
// The symmetric chunks are CertificateSecurityPolicy's.
#include <memory>

#include "ua/transport/certificate_security_policy.hpp"

namespace skillcell::ua {

class RsaSecurityPolicy final : public CertificateSecurityPolicy {
public:
    /// `localCertificate` is our DER certificate (a chain is allowed), `localKey` its
    /// private key; `remoteCertificate` the peer's DER certificate (chain allowed).
    RsaSecurityPolicy(const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
                      crypto::AsymmetricKey localKey, ByteString remoteCertificate,
                      crypto::AsymmetricKey remoteKey, MessageSecurityMode mode)
        : CertificateSecurityPolicy(profile, std::move(localCertificate), std::move(localKey),
                                    std::move(remoteCertificate), std::move(remoteKey), mode) {}

    /// Builds the policy for a peer certificate, checking that both keys are RSA keys of a
    /// size the policy allows (BadCertificateInvalid for the peer's, BadConfigurationError
    /// for ours).
    [[nodiscard]] static Result<std::unique_ptr<RsaSecurityPolicy>> create(
        const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
        crypto::AsymmetricKey localKey, ByteString remoteCertificate, MessageSecurityMode mode);

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
};

}  // namespace skillcell::ua
