#pragma once
// The cryptographic primitives the OPC UA security policies are made of (OPC 10000-7,
// security policy profiles; OPC 10000-6, 6.7.5 key derivation), on OpenSSL 3. Each takes
// and returns bytes; none keeps state. Failures are StatusCodes, never exceptions: a bad
// signature is BadSecurityChecksFailed, a key or input the algorithm cannot use is
// BadSecurityChecksFailed too (the peer sent it), an OpenSSL failure on our own key is
// BadInternalError.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "ua/crypto/openssl_handles.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::crypto {

using Bytes = std::vector<std::uint8_t>;
using ByteView = std::span<const std::uint8_t>;

enum class RsaEncryption : std::uint8_t { OaepSha1, OaepSha256 };
/// ECDSA signatures travel as r || s, each the size of the curve's order (OPC 10000-6, 6.8),
/// not in the DER form OpenSSL makes: sign() and verify() convert.
enum class SignatureAlgorithm : std::uint8_t {
    Pkcs1v15Sha256,
    PssSha256,
    EcdsaSha256,
    EcdsaSha384
};
/// The hash of a policy's symmetric signature (HMAC) and ECC key derivation (HKDF).
enum class HashAlgorithm : std::uint8_t { Sha256, Sha384 };

/// Bytes of padding OAEP needs per block: 2 * hash length + 2.
[[nodiscard]] std::size_t oaepOverhead(RsaEncryption algorithm);

/// An RSA key, or an ECC key on the NIST P-256 or P-384 curve: public or private. Copyable
/// handle (shared, immutable after loading).
class AsymmetricKey {
public:
    enum class Kind : std::uint8_t { Rsa, EccNistP256, EccNistP384 };

    AsymmetricKey() = default;
    /// The public key of a DER certificate (the first one, if `der` is a chain);
    /// BadCertificateInvalid for a key of another kind or curve.
    [[nodiscard]] static Result<AsymmetricKey> fromCertificate(ByteView der);
    /// A private key from a PEM file (PKCS#8, traditional RSA or EC).
    [[nodiscard]] static Result<AsymmetricKey> fromPrivateKeyFile(const std::filesystem::path& pem);
    /// The same when the kind is known: OpenSSL then tries only that kind's decoders (a third
    /// of the time: a component reads two keys at every start). BadConfigurationError for a
    /// file that holds no key of that kind.
    [[nodiscard]] static Result<AsymmetricKey> fromPrivateKeyFile(const std::filesystem::path& pem,
                                                                  Kind expected);
    /// A fresh RSA key, for tests and certificates.
    [[nodiscard]] static Result<AsymmetricKey> generate(int bits);
    /// A fresh key on the curve `kind` names (not Rsa), for tests and certificates.
    [[nodiscard]] static Result<AsymmetricKey> generateEcc(Kind kind);
    [[nodiscard]] static Result<AsymmetricKey> generateEccNistP256() {
        return generateEcc(Kind::EccNistP256);
    }

    [[nodiscard]] bool valid() const { return key_ != nullptr; }
    [[nodiscard]] Kind kind() const { return kind_; }
    /// RSA: the modulus' bytes (a signature's and a cipher block's size); ECC: a signature's
    /// (r || s).
    [[nodiscard]] std::size_t sizeBytes() const;
    [[nodiscard]] int bits() const;
    [[nodiscard]] EVP_PKEY* get() const { return key_.get(); }

private:
    AsymmetricKey(std::shared_ptr<EVP_PKEY> key, Kind kind) : key_(std::move(key)), kind_(kind) {}
    /// The key's kind, or nothing for a kind no policy uses.
    static Result<AsymmetricKey> adopt(EVP_PKEY* key, StatusCode otherwise);

    std::shared_ptr<EVP_PKEY> key_;
    Kind kind_ = Kind::Rsa;
};

/// A key pair made for one key agreement and dropped after it: an ECC SecureChannel's nonce
/// is the public half (OPC 10000-6, 6.8.1).
class EphemeralKey {
public:
    /// A fresh pair on the curve `kind` names (EccNistP256 or EccNistP384).
    [[nodiscard]] static Result<EphemeralKey> generate(AsymmetricKey::Kind kind);
    [[nodiscard]] static Result<EphemeralKey> generateNistP256() {
        return generate(AsymmetricKey::Kind::EccNistP256);
    }
    /// The public key as OPC UA carries it: X || Y, 64 bytes for P-256, 96 for P-384 (no 0x04
    /// prefix).
    [[nodiscard]] const Bytes& publicKey() const { return public_; }
    /// ECDH with the peer's public key (X || Y): the shared secret (the x-coordinate).
    /// BadNonceInvalid when the peer's key is not a point of the curve.
    [[nodiscard]] Result<Bytes> agree(ByteView peerPublicKey) const;

private:
    std::shared_ptr<EVP_PKEY> key_;
    AsymmetricKey::Kind curve_ = AsymmetricKey::Kind::EccNistP256;
    Bytes public_;
};

/// The ECDSA algorithm keys on the curve `kind` names sign with (ECDSA-SHA256 on P-256,
/// ECDSA-SHA384 on P-384); nothing for RSA.
[[nodiscard]] std::optional<SignatureAlgorithm> ecdsaAlgorithmFor(AsymmetricKey::Kind kind);

/// Encrypts `plain` block by block (each block takes keySize - oaepOverhead bytes and
/// becomes keySize bytes), as OPC 10000-6, 6.7.2.5 lays out asymmetric encryption.
[[nodiscard]] Result<Bytes> rsaEncrypt(const AsymmetricKey& publicKey, RsaEncryption algorithm,
                                       ByteView plain);
/// The inverse; `cipher` must be a whole number of keySize blocks.
[[nodiscard]] Result<Bytes> rsaDecrypt(const AsymmetricKey& privateKey, RsaEncryption algorithm,
                                       ByteView cipher);
[[nodiscard]] Result<Bytes> sign(const AsymmetricKey& privateKey, SignatureAlgorithm algorithm,
                                 ByteView data);
/// Good, or BadSecurityChecksFailed.
[[nodiscard]] StatusCode verify(const AsymmetricKey& publicKey, SignatureAlgorithm algorithm,
                                ByteView data, ByteView signature);

[[nodiscard]] Bytes hmac(HashAlgorithm hash, ByteView key, ByteView data);
[[nodiscard]] inline Bytes hmacSha256(ByteView key, ByteView data) {
    return hmac(HashAlgorithm::Sha256, key, data);
}
/// AES-CBC without padding (the policy pads): `data` must be a multiple of 16 bytes, the
/// key 16 or 32 bytes, the IV 16 bytes. Works in place on `data`.
[[nodiscard]] StatusCode aesCbcEncrypt(ByteView key, ByteView iv, std::span<std::uint8_t> data);
[[nodiscard]] StatusCode aesCbcDecrypt(ByteView key, ByteView iv, std::span<std::uint8_t> data);
/// HKDF (RFC 5869) with SHA-256 or SHA-384: extract with `salt` from `secret`, expand with
/// `info` to `length` bytes: the ECC policies' key derivation (OPC 10000-6, 6.8.1).
/// BadInternalError when OpenSSL offers no HKDF (a provider without it) or `length` exceeds
/// 255 hash lengths.
[[nodiscard]] Result<Bytes> hkdf(HashAlgorithm hash, ByteView salt, ByteView secret, ByteView info,
                                 std::size_t length);
[[nodiscard]] inline Result<Bytes> hkdfSha256(ByteView salt, ByteView secret, ByteView info,
                                              std::size_t length) {
    return hkdf(HashAlgorithm::Sha256, salt, secret, info, length);
}
/// P_SHA256(secret, seed) of RFC 5246 5, `length` bytes: the UA key derivation.
[[nodiscard]] Bytes pSha256(ByteView secret, ByteView seed, std::size_t length);
[[nodiscard]] Bytes sha1(ByteView data);
/// Cryptographically secure random bytes.
[[nodiscard]] Bytes randomBytes(std::size_t n);
/// Constant-time comparison, for MACs.
[[nodiscard]] bool equalConstantTime(ByteView a, ByteView b);

}  // namespace skillcell::ua::crypto
