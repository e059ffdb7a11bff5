#include "ua/transport/certificate_security_policy.hpp"

#include <algorithm>

#include "ua/transport/ecc_security_policy.hpp"
#include "ua/transport/rsa_security_policy.hpp"
#include "ua/transport/tcp_framing.hpp"

namespace skillcell::ua {
namespace {

constexpr std::size_t kAesBlock = 16;
constexpr std::size_t kIvLength = 16;

}  // namespace

void patchMessageSize(std::vector<std::uint8_t>& chunk, std::size_t size) {
    const auto v = static_cast<std::uint32_t>(size);
    chunk[4] = static_cast<std::uint8_t>(v);
    chunk[5] = static_cast<std::uint8_t>(v >> 8);
    chunk[6] = static_cast<std::uint8_t>(v >> 16);
    chunk[7] = static_cast<std::uint8_t>(v >> 24);
}

void appendPadding(std::vector<std::uint8_t>& chunk, std::size_t from, std::size_t block,
                   std::size_t signatureSize, bool extra) {
    const std::size_t fixed = chunk.size() - from + 1 + (extra ? 1 : 0) + signatureSize;
    const std::size_t padding = (block - fixed % block) % block;
    const auto low = static_cast<std::uint8_t>(padding & 0xFF);
    chunk.insert(chunk.end(), padding + 1, low);
    if (extra) chunk.push_back(static_cast<std::uint8_t>(padding >> 8));
}

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

Result<crypto::AsymmetricKey> publicKeyOf(const ByteString& certificate,
                                          const ByteString* channelCertificate,
                                          const crypto::AsymmetricKey* channelKey) {
    if (channelKey != nullptr && channelCertificate != nullptr &&
        leafCertificate(certificate.bytes) == leafCertificate(channelCertificate->bytes)) {
        return *channelKey;
    }
    return crypto::AsymmetricKey::fromCertificate(certificate.bytes);
}

std::vector<std::uint8_t> certificateAndNonce(const ByteString& certificate,
                                              const ByteString& nonce) {
    std::vector<std::uint8_t> out(certificate.bytes);
    out.insert(out.end(), nonce.bytes.begin(), nonce.bytes.end());
    return out;
}

Result<std::unique_ptr<CertificateSecurityPolicy>> createCertificateSecurityPolicy(
    const crypto::SecurityPolicyProfile& profile, ByteString localCertificate,
    crypto::AsymmetricKey localKey, ByteString remoteCertificate, MessageSecurityMode mode) {
    if (profile.isEcc()) {
        auto ecc =
            EccSecurityPolicy::create(profile, std::move(localCertificate), std::move(localKey),
                                      std::move(remoteCertificate), mode);
        if (!ecc) return ecc.status();
        return std::unique_ptr<CertificateSecurityPolicy>(std::move(*ecc));
    }
    auto rsa = RsaSecurityPolicy::create(profile, std::move(localCertificate), std::move(localKey),
                                         std::move(remoteCertificate), mode);
    if (!rsa) return rsa.status();
    return std::unique_ptr<CertificateSecurityPolicy>(std::move(*rsa));
}

CertificateSecurityPolicy::CertificateSecurityPolicy(const crypto::SecurityPolicyProfile& profile,
                                                     ByteString localCertificate,
                                                     crypto::AsymmetricKey localKey,
                                                     ByteString remoteCertificate,
                                                     crypto::AsymmetricKey remoteKey,
                                                     MessageSecurityMode mode)
    : profile_(profile),
      localCertificate_(std::move(localCertificate)),
      localKey_(std::move(localKey)),
      remoteCertificate_(std::move(remoteCertificate)),
      remoteKey_(std::move(remoteKey)),
      localThumbprint_(crypto::sha1(leafCertificate(localCertificate_.bytes))),
      remoteThumbprint_(crypto::sha1(leafCertificate(remoteCertificate_.bytes))),
      mode_(mode) {}

Result<crypto::AsymmetricKey> CertificateSecurityPolicy::checkKeys(
    const crypto::SecurityPolicyProfile& profile, const crypto::AsymmetricKey& localKey,
    const ByteString& remoteCertificate) {
    const auto fits = [&profile](const crypto::AsymmetricKey& key) {
        return key.kind() == profile.keyKind && key.bits() >= profile.minAsymmetricKeyBits &&
               key.bits() <= profile.maxAsymmetricKeyBits;
    };
    if (!localKey.valid() || !fits(localKey)) return status::BadConfigurationError;
    auto remoteKey = crypto::AsymmetricKey::fromCertificate(remoteCertificate.bytes);
    if (!remoteKey) return remoteKey.status();
    if (!fits(*remoteKey)) return status::BadCertificateInvalid;
    return remoteKey;
}

std::size_t CertificateSecurityPolicy::maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                                   bool asymmetric) const {
    if (headerSize < kSequenceHeaderSize || chunkSize <= headerSize) return 0;
    if (asymmetric) return maxAsymmetricBodySize(chunkSize, headerSize);
    const std::size_t clear = headerSize - kSequenceHeaderSize;
    std::size_t capacity = 0;  // plain-text bytes after the clear headers
    std::size_t overhead = kSequenceHeaderSize;
    if (mode_ == MessageSecurityMode::SignAndEncrypt) {
        capacity = (chunkSize - clear) / kAesBlock * kAesBlock;
        overhead += 1 + profile_.symmetricSignatureSize;
    } else {
        capacity = chunkSize - clear;
        overhead += profile_.symmetricSignatureSize;
    }
    return capacity > overhead ? capacity - overhead : 0;
}

StatusCode CertificateSecurityPolicy::protect(std::vector<std::uint8_t>& chunk,
                                              std::size_t headerSize, const SymmetricKeys* keys) {
    if (chunk.size() < headerSize + kSequenceHeaderSize) return status::BadInternalError;
    return keys == nullptr ? protectAsymmetric(chunk, headerSize)
                           : protectSymmetric(chunk, headerSize, *keys);
}

StatusCode CertificateSecurityPolicy::unprotect(std::vector<std::uint8_t>& chunk,
                                                std::size_t headerSize, const SymmetricKeys* keys) {
    if (chunk.size() < headerSize) return status::BadSecurityChecksFailed;
    return keys == nullptr ? unprotectAsymmetric(chunk, headerSize)
                           : unprotectSymmetric(chunk, headerSize, *keys);
}

StatusCode CertificateSecurityPolicy::protectSymmetric(std::vector<std::uint8_t>& chunk,
                                                       std::size_t headerSize,
                                                       const SymmetricKeys& keys) const {
    const bool encrypt = mode_ == MessageSecurityMode::SignAndEncrypt;
    const std::size_t signatureSize = profile_.symmetricSignatureSize;
    if (encrypt) appendPadding(chunk, headerSize, kAesBlock, signatureSize, false);
    patchMessageSize(chunk, chunk.size() + signatureSize);
    const auto mac = crypto::hmac(profile_.hash, keys.signingKey, chunk);
    chunk.insert(chunk.end(), mac.begin(), mac.end());
    if (!encrypt) return status::Good;
    return crypto::aesCbcEncrypt(keys.encryptingKey, keys.initializationVector,
                                 std::span(chunk).subspan(headerSize));
}

StatusCode CertificateSecurityPolicy::unprotectSymmetric(std::vector<std::uint8_t>& chunk,
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
    const auto mac =
        crypto::hmac(profile_.hash, keys.signingKey, std::span(chunk).first(signedEnd));
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

StatusCode CertificateSecurityPolicy::checkAsymmetricHeader(
    const AsymmetricSecurityHeader& header) const {
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

std::size_t CertificateSecurityPolicy::keyMaterialLength() const {
    return profile_.signingKeyLength + profile_.symmetricKeyLength + kIvLength;
}

SymmetricKeys CertificateSecurityPolicy::splitKeys(std::span<const std::uint8_t> material) const {
    const auto sig = static_cast<std::ptrdiff_t>(profile_.signingKeyLength);
    const auto enc = static_cast<std::ptrdiff_t>(profile_.symmetricKeyLength);
    SymmetricKeys k;
    k.signingKey.assign(material.begin(), material.begin() + sig);
    k.encryptingKey.assign(material.begin() + sig, material.begin() + sig + enc);
    k.initializationVector.assign(material.begin() + sig + enc, material.end());
    return k;
}

}  // namespace skillcell::ua
