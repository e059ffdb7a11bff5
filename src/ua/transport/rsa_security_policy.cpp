#include "ua/transport/rsa_security_policy.hpp"

#include "ua/transport/tcp_framing.hpp"

namespace skillcell::ua {
namespace {

/// RSA keys above 2048 bits need a second padding-size byte (OPC 10000-6, 6.7.2.5).
constexpr std::size_t kExtraPaddingThreshold = 256;

}  // namespace

Result<std::unique_ptr<RsaSecurityPolicy>> RsaSecurityPolicy::create(
    const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
    crypto::AsymmetricKey localKey, ByteString remoteCertificate, MessageSecurityMode mode) {
    if (profile.isEcc()) return status::BadInternalError;
    auto remoteKey = checkKeys(profile, localKey, remoteCertificate);
    if (!remoteKey) return remoteKey.status();
    return std::make_unique<RsaSecurityPolicy>(profile, std::move(localCertificate),
                                               std::move(localKey), std::move(remoteCertificate),
                                               std::move(*remoteKey), mode);
}

std::size_t RsaSecurityPolicy::maxAsymmetricBodySize(std::size_t chunkSize,
                                                     std::size_t headerSize) const {
    const std::size_t clear = headerSize - kSequenceHeaderSize;
    const std::size_t cipherBlock = remoteKey_.sizeBytes();
    const std::size_t plainBlock =
        cipherBlock - crypto::oaepOverhead(profile_.asymmetricEncryption);
    const std::size_t capacity = (chunkSize - clear) / cipherBlock * plainBlock;
    const std::size_t overhead = kSequenceHeaderSize + 1 +
                                 (cipherBlock > kExtraPaddingThreshold ? 1 : 0) +
                                 localKey_.sizeBytes();
    return capacity > overhead ? capacity - overhead : 0;
}

StatusCode RsaSecurityPolicy::protectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                std::size_t headerSize) const {
    const std::size_t cipherBlock = remoteKey_.sizeBytes();
    const std::size_t plainBlock =
        cipherBlock - crypto::oaepOverhead(profile_.asymmetricEncryption);
    const std::size_t signatureSize = localKey_.sizeBytes();
    appendPadding(chunk, headerSize, plainBlock, signatureSize,
                  cipherBlock > kExtraPaddingThreshold);
    const std::size_t plainSize = chunk.size() - headerSize + signatureSize;
    patchMessageSize(chunk, headerSize + plainSize / plainBlock * cipherBlock);
    auto signature = crypto::sign(localKey_, profile_.asymmetricSignature, chunk);
    if (!signature) return signature.status();
    chunk.insert(chunk.end(), signature->begin(), signature->end());
    auto cipher = crypto::rsaEncrypt(remoteKey_, profile_.asymmetricEncryption,
                                     std::span(chunk).subspan(headerSize));
    if (!cipher) return cipher.status();
    chunk.resize(headerSize);
    chunk.insert(chunk.end(), cipher->begin(), cipher->end());
    return status::Good;
}

StatusCode RsaSecurityPolicy::unprotectAsymmetric(std::vector<std::uint8_t>& chunk,
                                                  std::size_t headerSize) const {
    auto plain = crypto::rsaDecrypt(localKey_, profile_.asymmetricEncryption,
                                    std::span(chunk).subspan(headerSize));
    if (!plain) return status::BadSecurityChecksFailed;
    const std::size_t signatureSize = remoteKey_.sizeBytes();
    if (plain->size() < signatureSize + kSequenceHeaderSize + 1) {
        return status::BadSecurityChecksFailed;
    }
    chunk.resize(headerSize);
    chunk.insert(chunk.end(), plain->begin(), plain->end());
    const std::size_t signedEnd = chunk.size() - signatureSize;
    if (const auto s =
            crypto::verify(remoteKey_, profile_.asymmetricSignature,
                           std::span(chunk).first(signedEnd), std::span(chunk).subspan(signedEnd));
        s.isBad()) {
        return status::BadSecurityChecksFailed;
    }
    // The padding follows the receiver's (our) key size.
    const std::size_t end =
        stripPadding(chunk, headerSize, signedEnd, localKey_.sizeBytes() > kExtraPaddingThreshold);
    if (end == 0) return status::BadSecurityChecksFailed;
    chunk.resize(end);
    return status::Good;
}

Result<ChannelKeys> RsaSecurityPolicy::deriveKeys(std::span<const std::uint8_t> clientNonce,
                                                  std::span<const std::uint8_t> serverNonce,
                                                  bool client) const {
    // OPC 10000-6, 6.7.5: the client's keys come from the server's nonce as secret and the
    // client's as seed, the server's the other way round.
    const std::size_t length = keyMaterialLength();
    SymmetricKeys clientKeys = splitKeys(crypto::pSha256(serverNonce, clientNonce, length));
    SymmetricKeys serverKeys = splitKeys(crypto::pSha256(clientNonce, serverNonce, length));
    if (client) return ChannelKeys{std::move(clientKeys), std::move(serverKeys)};
    return ChannelKeys{std::move(serverKeys), std::move(clientKeys)};
}

}  // namespace skillcell::ua
