#pragma once
// The cryptographic primitives the OPC UA security policies are made of (OPC 10000-7,
// security policy profiles; OPC 10000-6, 6.7.5 key derivation), on OpenSSL 3. Each takes
// and returns bytes; none keeps state. Failures are StatusCodes, never exceptions: a bad
// signature is BadSecurityChecksFailed, a key or input the algorithm cannot use is
// BadSecurityChecksFailed too (the peer sent it), an OpenSSL failure on our own key is
// BadInternalError.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "ua/crypto/openssl_handles.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::crypto {

using Bytes = std::vector<std::uint8_t>;
using ByteView = std::span<const std::uint8_t>;

enum class RsaEncryption : std::uint8_t { OaepSha1, OaepSha256 };
enum class RsaSignature : std::uint8_t { Pkcs1v15Sha256, PssSha256 };

/// Bytes of padding OAEP needs per block: 2 * hash length + 2.
[[nodiscard]] std::size_t oaepOverhead(RsaEncryption algorithm);

/// An RSA public or private key. Copyable handle (shared, immutable after loading).
class RsaKey {
public:
    RsaKey() = default;
    /// The public key of a DER certificate (the first one, if `der` is a chain).
    [[nodiscard]] static Result<RsaKey> fromCertificate(ByteView der);
    /// A private key from a PEM file (PKCS#8 or traditional RSA).
    [[nodiscard]] static Result<RsaKey> fromPrivateKeyFile(const std::filesystem::path& pem);
    /// A fresh key, for tests and certificates.
    [[nodiscard]] static Result<RsaKey> generate(int bits);

    [[nodiscard]] bool valid() const { return key_ != nullptr; }
    [[nodiscard]] std::size_t sizeBytes() const;
    [[nodiscard]] int bits() const;
    [[nodiscard]] EVP_PKEY* get() const { return key_.get(); }

private:
    explicit RsaKey(std::shared_ptr<EVP_PKEY> key) : key_(std::move(key)) {}
    std::shared_ptr<EVP_PKEY> key_;
};

/// Encrypts `plain` block by block (each block takes keySize - oaepOverhead bytes and
/// becomes keySize bytes), as OPC 10000-6, 6.7.2.5 lays out asymmetric encryption.
[[nodiscard]] Result<Bytes> rsaEncrypt(const RsaKey& publicKey, RsaEncryption algorithm,
                                       ByteView plain);
/// The inverse; `cipher` must be a whole number of keySize blocks.
[[nodiscard]] Result<Bytes> rsaDecrypt(const RsaKey& privateKey, RsaEncryption algorithm,
                                       ByteView cipher);
[[nodiscard]] Result<Bytes> rsaSign(const RsaKey& privateKey, RsaSignature algorithm,
                                    ByteView data);
/// Good, or BadSecurityChecksFailed.
[[nodiscard]] StatusCode rsaVerify(const RsaKey& publicKey, RsaSignature algorithm, ByteView data,
                                   ByteView signature);

[[nodiscard]] Bytes hmacSha256(ByteView key, ByteView data);
/// AES-CBC without padding (the policy pads): `data` must be a multiple of 16 bytes, the
/// key 16 or 32 bytes, the IV 16 bytes. Works in place on `data`.
[[nodiscard]] StatusCode aesCbcEncrypt(ByteView key, ByteView iv, std::span<std::uint8_t> data);
[[nodiscard]] StatusCode aesCbcDecrypt(ByteView key, ByteView iv, std::span<std::uint8_t> data);
/// P_SHA256(secret, seed) of RFC 5246 5, `length` bytes: the UA key derivation.
[[nodiscard]] Bytes pSha256(ByteView secret, ByteView seed, std::size_t length);
[[nodiscard]] Bytes sha1(ByteView data);
/// Cryptographically secure random bytes.
[[nodiscard]] Bytes randomBytes(std::size_t n);
/// Constant-time comparison, for MACs.
[[nodiscard]] bool equalConstantTime(ByteView a, ByteView b);

}  // namespace skillcell::ua::crypto
