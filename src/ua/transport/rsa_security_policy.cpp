#include "ua/transport/rsa_security_policy.hpp"

#include <openssl/x509.h>

#include <algorithm>

#include "ua/transport/tcp_framing.hpp"

namespace skillcell::ua {
namespace {

constexpr std::size_t kAesBlock = 16;
constexpr std::size_t kIvLength = 16;
/// RSA keys above 2048 bits need a second padding-size byte (OPC 10000-6, 6.7.2.5).
constexpr std::size_t kExtraPaddingThreshold = 256;

void patchMessageSize(std::vector<std::uint8_t>& chunk, std::size_t size) {
    const auto v = static_cast<std::uint32_t>(size);
    chunk[4] = static_cast<std::uint8_t>(v);
    chunk[5] = static_cast<std::uint8_t>(v >> 8);
    chunk[6] = static_cast<std::uint8_t>(v >> 16);
    chunk[7] = static_cast<std::uint8_t>(v >> 24);
}

/// Appends PaddingSize, the padding and (when `extra`) ExtraPaddingSize, so that
/// `chunk.size() - from + signatureSize` becomes a multiple of `block`.
void appendPadding(std::vector<std::uint8_t>& chunk, std::size_t from, std::size_t block,
                   std::size_t signatureSize, bool extra) {
    const std::size_t fixed = chunk.size() - from + 1 + (extra ? 1 : 0) + signatureSize;
    const std::size_t padding = (block - fixed % block) % block;
    const auto low = static_cast<std::uint8_t>(padding & 0xFF);
    chunk.insert(chunk.end(), padding + 1, low);
    if (extra) chunk.push_back(static_cast<std::uint8_t>(padding >> 8));
}

/// Checks and strips the padding that ends at `end` (signature already removed); returns
/// the new end, or 0 when the padding is malformed. The payload must keep at least the
/// sequence header after `from`.
std::size_t stripPadding(const std::vector<std::uint8_t>& chunk, std::size_t from, std::size_t end,
                         bool extra) {
    const std::size_t extraLen = extra ? 1 : 0;
    if (end < from + kSequenceHeaderSize + 1 + extraLen) return 0;
    std::size_t padding = chunk[end - 1 - extraLen];
    if (extra) padding |= std::size_t{chunk[end - 1]} << 8;
    const std::size_t paddingRegion = padding + 1 + extraLen;  // PaddingSize byte included
    if (end - from < kSequenceHeaderSize + paddingRegion) return 0;
    const std::size_t start = end - paddingRegion;
    const auto low = static_cast<std::uint8_t>(padding & 0xFF);
    // Every padding byte and the PaddingSize byte carry the low byte of the size.
    const bool wellFormed = std::all_of(chunk.begin() + static_cast<std::ptrdiff_t>(start),
                                        chunk.begin() + static_cast<std::ptrdiff_t>(end - extraLen),
                                        [low](std::uint8_t b) { return b == low; });
    return wellFormed ? start : 0;
}

}  // namespace

std::vector<std::uint8_t> leafCertificate(std::span<const std::uint8_t> der) {
    // From the DER header alone: a certificate is a SEQUENCE (tag 0x30) of definite length.
    // Decoding it whole (d2i_X509, which also decodes the public key) took 130 us, and a
    // secured handshake asked about ten times, as often as for all its RSA operations.
    if (der.size() < 2 || der[0] != 0x30) return {};
    std::size_t header = 2;
    std::size_t length = der[1];
    if ((length & 0x80U) != 0) {
        const std::size_t octets = length & 0x7FU;
        // 1 to 4 length octets (a certificate is far below 4 GB); no leading zero (DER).
        if (octets == 0 || octets > 4 || der.size() < 2 + octets || der[2] == 0) return {};
        length = 0;
        for (std::size_t i = 0; i < octets; ++i) length = (length << 8U) | der[2 + i];
        if (length < 0x80) return {};  // DER uses the short form below 128
        header += octets;
    }
    if (length > der.size() - header) return {};
    return {der.begin(), der.begin() + static_cast<std::ptrdiff_t>(header + length)};
}

Result<crypto::RsaKey> publicKeyOf(const ByteString& certificate,
                                   const ByteString* channelCertificate,
                                   const crypto::RsaKey* channelKey) {
    if (channelKey != nullptr && channelCertificate != nullptr &&
        leafCertificate(certificate.bytes) == leafCertificate(channelCertificate->bytes)) {
        return *channelKey;
    }
    return crypto::RsaKey::fromCertificate(certificate.bytes);
}

std::vector<std::uint8_t> certificateAndNonce(const ByteString& certificate,
                                              const ByteString& nonce) {
    std::vector<std::uint8_t> out(certificate.bytes);
    out.insert(out.end(), nonce.bytes.begin(), nonce.bytes.end());
    return out;
}

RsaSecurityPolicy::RsaSecurityPolicy(const crypto::SecurityPolicyProfile& profile,
                                     ByteString localCertificate, crypto::RsaKey localKey,
                                     ByteString remoteCertificate, crypto::RsaKey remoteKey,
                                     MessageSecurityMode mode)
    : profile_(profile),
      localCertificate_(std::move(localCertificate)),
      localKey_(std::move(localKey)),
      remoteCertificate_(std::move(remoteCertificate)),
      remoteKey_(std::move(remoteKey)),
      localThumbprint_(crypto::sha1(leafCertificate(localCertificate_.bytes))),
      remoteThumbprint_(crypto::sha1(leafCertificate(remoteCertificate_.bytes))),
      mode_(mode) {}

Result<std::unique_ptr<RsaSecurityPolicy>> RsaSecurityPolicy::create(
    const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
    crypto::RsaKey localKey, ByteString remoteCertificate, MessageSecurityMode mode) {
    const auto allowed = [&profile](int bits) {
        return bits >= profile.minAsymmetricKeyBits && bits <= profile.maxAsymmetricKeyBits;
    };
    if (!localKey.valid() || !allowed(localKey.bits())) return status::BadConfigurationError;
    auto remoteKey = crypto::RsaKey::fromCertificate(remoteCertificate.bytes);
    if (!remoteKey) return remoteKey.status();
    if (!allowed(remoteKey->bits())) return status::BadCertificateInvalid;
    return std::make_unique<RsaSecurityPolicy>(profile, std::move(localCertificate),
                                               std::move(localKey), std::move(remoteCertificate),
                                               std::move(*remoteKey), mode);
}

std::size_t RsaSecurityPolicy::maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                           bool asymmetric) const {
    if (headerSize < kSequenceHeaderSize || chunkSize <= headerSize) return 0;
    const std::size_t clear = headerSize - kSequenceHeaderSize;
    std::size_t capacity = 0;  // plain-text bytes after the clear headers
    std::size_t overhead = kSequenceHeaderSize;
    if (asymmetric) {
        const std::size_t cipherBlock = remoteKey_.sizeBytes();
        const std::size_t plainBlock =
            cipherBlock - crypto::oaepOverhead(profile_.asymmetricEncryption);
        capacity = (chunkSize - clear) / cipherBlock * plainBlock;
        overhead += 1 + (cipherBlock > kExtraPaddingThreshold ? 1 : 0) + localKey_.sizeBytes();
    } else if (mode_ == MessageSecurityMode::SignAndEncrypt) {
        capacity = (chunkSize - clear) / kAesBlock * kAesBlock;
        overhead += 1 + profile_.symmetricSignatureSize;
    } else {
        capacity = chunkSize - clear;
        overhead += profile_.symmetricSignatureSize;
    }
    return capacity > overhead ? capacity - overhead : 0;
}

StatusCode RsaSecurityPolicy::protect(std::vector<std::uint8_t>& chunk, std::size_t headerSize,
                                      const SymmetricKeys* keys) {
    if (chunk.size() < headerSize + kSequenceHeaderSize) return status::BadInternalError;
    return keys == nullptr ? protectAsymmetric(chunk, headerSize)
                           : protectSymmetric(chunk, headerSize, *keys);
}

StatusCode RsaSecurityPolicy::unprotect(std::vector<std::uint8_t>& chunk, std::size_t headerSize,
                                        const SymmetricKeys* keys) {
    if (chunk.size() < headerSize) return status::BadSecurityChecksFailed;
    return keys == nullptr ? unprotectAsymmetric(chunk, headerSize)
                           : unprotectSymmetric(chunk, headerSize, *keys);
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
    auto signature = crypto::rsaSign(localKey_, profile_.asymmetricSignature, chunk);
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
    if (const auto s = crypto::rsaVerify(remoteKey_, profile_.asymmetricSignature,
                                         std::span(chunk).first(signedEnd),
                                         std::span(chunk).subspan(signedEnd));
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

StatusCode RsaSecurityPolicy::protectSymmetric(std::vector<std::uint8_t>& chunk,
                                               std::size_t headerSize,
                                               const SymmetricKeys& keys) const {
    const bool encrypt = mode_ == MessageSecurityMode::SignAndEncrypt;
    const std::size_t signatureSize = profile_.symmetricSignatureSize;
    if (encrypt) appendPadding(chunk, headerSize, kAesBlock, signatureSize, false);
    patchMessageSize(chunk, chunk.size() + signatureSize);
    const auto mac = crypto::hmacSha256(keys.signingKey, chunk);
    chunk.insert(chunk.end(), mac.begin(), mac.end());
    if (!encrypt) return status::Good;
    return crypto::aesCbcEncrypt(keys.encryptingKey, keys.initializationVector,
                                 std::span(chunk).subspan(headerSize));
}

StatusCode RsaSecurityPolicy::unprotectSymmetric(std::vector<std::uint8_t>& chunk,
                                                 std::size_t headerSize,
                                                 const SymmetricKeys& keys) const {
    const bool encrypted = mode_ == MessageSecurityMode::SignAndEncrypt;
    const std::size_t signatureSize = profile_.symmetricSignatureSize;
    if (chunk.size() < headerSize + kSequenceHeaderSize + signatureSize) {
        return status::BadSecurityChecksFailed;
    }
    if (encrypted) {
        if ((chunk.size() - headerSize) % kAesBlock != 0) return status::BadSecurityChecksFailed;
        if (crypto::aesCbcDecrypt(keys.encryptingKey, keys.initializationVector,
                                  std::span(chunk).subspan(headerSize))
                .isBad()) {
            return status::BadSecurityChecksFailed;
        }
    }
    const std::size_t signedEnd = chunk.size() - signatureSize;
    const auto mac = crypto::hmacSha256(keys.signingKey, std::span(chunk).first(signedEnd));
    if (!crypto::equalConstantTime(mac, std::span(chunk).subspan(signedEnd))) {
        return status::BadSecurityChecksFailed;
    }
    std::size_t end = signedEnd;
    if (encrypted) {
        end = stripPadding(chunk, headerSize, signedEnd, false);
        if (end == 0) return status::BadSecurityChecksFailed;
    }
    chunk.resize(end);
    return status::Good;
}

StatusCode RsaSecurityPolicy::checkAsymmetricHeader(const AsymmetricSecurityHeader& header) const {
    // The chunk must be meant for our certificate and come from the one the channel was
    // opened with (a renewal cannot switch certificates).
    if (header.receiverCertificateThumbprint.bytes != localThumbprint_) {
        return status::BadCertificateInvalid;
    }
    if (leafCertificate(header.senderCertificate.bytes) !=
        leafCertificate(remoteCertificate_.bytes)) {
        return status::BadCertificateInvalid;
    }
    return status::Good;
}

ChannelKeys RsaSecurityPolicy::deriveKeys(std::span<const std::uint8_t> clientNonce,
                                          std::span<const std::uint8_t> serverNonce,
                                          bool client) const {
    const std::size_t sig = profile_.signingKeyLength;
    const std::size_t enc = profile_.symmetricKeyLength;
    auto split = [&](const std::vector<std::uint8_t>& material) {
        SymmetricKeys k;
        k.signingKey.assign(material.begin(), material.begin() + static_cast<std::ptrdiff_t>(sig));
        k.encryptingKey.assign(material.begin() + static_cast<std::ptrdiff_t>(sig),
                               material.begin() + static_cast<std::ptrdiff_t>(sig + enc));
        k.initializationVector.assign(material.begin() + static_cast<std::ptrdiff_t>(sig + enc),
                                      material.end());
        return k;
    };
    // OPC 10000-6, 6.7.5: the client's keys come from the server's nonce as secret and the
    // client's as seed, the server's the other way round.
    const std::size_t length = sig + enc + kIvLength;
    SymmetricKeys clientKeys = split(crypto::pSha256(serverNonce, clientNonce, length));
    SymmetricKeys serverKeys = split(crypto::pSha256(clientNonce, serverNonce, length));
    if (client) return {std::move(clientKeys), std::move(serverKeys)};
    return {std::move(serverKeys), std::move(clientKeys)};
}

}  // namespace skillcell::ua
