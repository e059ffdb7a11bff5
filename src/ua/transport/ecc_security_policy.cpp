#include "ua/transport/ecc_security_policy.hpp"

#include <string_view>

#include "ua/transport/tcp_framing.hpp"

namespace skillcell::ua {
namespace {

/// L | label | first nonce | second nonce, L the key material's length as a UInt16.
std::vector<std::uint8_t> salt(std::size_t length, std::string_view label,
                               std::span<const std::uint8_t> first,
                               std::span<const std::uint8_t> second) {
    std::vector<std::uint8_t> out;
    out.reserve(2 + label.size() + first.size() + second.size());
    out.push_back(static_cast<std::uint8_t>(length & 0xFFU));
    out.push_back(static_cast<std::uint8_t>((length >> 8) & 0xFFU));
    for (const char c : label) out.push_back(static_cast<std::uint8_t>(c));
    out.insert(out.end(), first.begin(), first.end());
    out.insert(out.end(), second.begin(), second.end());
    return out;
}

}  // namespace

Result<std::unique_ptr<EccSecurityPolicy>> EccSecurityPolicy::create(
    const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
    crypto::AsymmetricKey localKey, ByteString remoteCertificate, MessageSecurityMode mode) {
    if (!profile.isEcc()) return status::BadInternalError;
    auto remoteKey = checkKeys(profile, localKey, remoteCertificate);
    if (!remoteKey) return remoteKey.status();
    return std::make_unique<EccSecurityPolicy>(profile, std::move(localCertificate),
                                               std::move(localKey), std::move(remoteCertificate),
                                               std::move(*remoteKey), mode);
}

ByteString EccSecurityPolicy::newNonce() {
    auto key = crypto::EphemeralKey::generate(profile_.keyKind);
    if (!key) {
        // Only a broken OpenSSL gets here: the empty nonce fails the exchange (the server
        // answers BadInternalError, a client's derivation BadNonceInvalid).
        ephemeral_.reset();
        return {};
    }
    ByteString nonce(key->publicKey());
    ephemeral_ = std::move(*key);
    return nonce;
}

Result<ChannelKeys> EccSecurityPolicy::deriveKeys(std::span<const std::uint8_t> clientNonce,
                                                  std::span<const std::uint8_t> serverNonce,
                                                  bool client) const {
    if (!ephemeral_) return status::BadNonceInvalid;
    auto secret = ephemeral_->agree(client ? serverNonce : clientNonce);
    if (!secret) return secret.status();
    const std::size_t length = keyMaterialLength();
    const auto clientSalt = salt(length, "opcua-client", clientNonce, serverNonce);
    const auto serverSalt = salt(length, "opcua-server", serverNonce, clientNonce);
    auto clientMaterial = crypto::hkdf(profile_.hash, clientSalt, *secret, clientSalt, length);
    auto serverMaterial = crypto::hkdf(profile_.hash, serverSalt, *secret, serverSalt, length);
    if (!clientMaterial) return clientMaterial.status();
    if (!serverMaterial) return serverMaterial.status();
    SymmetricKeys clientKeys = splitKeys(*clientMaterial);
    SymmetricKeys serverKeys = splitKeys(*serverMaterial);
    if (client) return ChannelKeys{std::move(clientKeys), std::move(serverKeys)};
    return ChannelKeys{std::move(serverKeys), std::move(clientKeys)};
}

std::size_t EccSecurityPolicy::maxAsymmetricBodySize(std::size_t chunkSize,
                                                     std::size_t headerSize) const {
    const std::size_t overhead = headerSize + localKey_.sizeBytes();
    return chunkSize > overhead ? chunkSize - overhead : 0;
}

StatusCode EccSecurityPolicy::protectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                std::size_t /*headerSize*/) const {
    // Nothing is encrypted: the whole chunk is signed as it stands.
    patchMessageSize(chunk, chunk.size() + localKey_.sizeBytes());
    auto signature = crypto::sign(localKey_, profile_.asymmetricSignature, chunk);
    if (!signature) return signature.status();
    chunk.insert(chunk.end(), signature->begin(), signature->end());
    return status::Good;
}

StatusCode EccSecurityPolicy::unprotectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                  std::size_t headerSize) const {
    const std::size_t signatureSize = remoteKey_.sizeBytes();
    if (chunk.size() < headerSize + kSequenceHeaderSize + signatureSize) {
        return status::BadSecurityChecksFailed;
    }
    const std::size_t signedEnd = chunk.size() - signatureSize;
    if (crypto::verify(remoteKey_, profile_.asymmetricSignature, std::span(chunk).first(signedEnd),
                       std::span(chunk).subspan(signedEnd))
            .isBad()) {
        return status::BadSecurityChecksFailed;
    }
    chunk.resize(signedEnd);
    return status::Good;
}

}  // namespace skillcell::ua
