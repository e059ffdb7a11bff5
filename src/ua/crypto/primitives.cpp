#include "ua/crypto/primitives.hpp"

#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/hmac.h>
#include <openssl/pem.h>
#include <openssl/rand.h>
#include <openssl/rsa.h>
#include <openssl/sha.h>

#include <cstdio>
#include <limits>

namespace skillcell::ua::crypto {
namespace {

constexpr std::size_t kAesBlock = 16;

const EVP_MD* oaepDigest(RsaEncryption a) {
    return a == RsaEncryption::OaepSha1 ? EVP_sha1() : EVP_sha256();
}

std::shared_ptr<EVP_PKEY> share(EVP_PKEY* key) {
    return {key, EVP_PKEY_free};
}

/// An RSA key context for encryption or decryption with OAEP and the policy's digest (MGF1
/// uses the same digest, as the UA policies specify).
PKeyCtxHandle oaepContext(const RsaKey& key, RsaEncryption algorithm, bool encrypt) {
    PKeyCtxHandle ctx(EVP_PKEY_CTX_new_from_pkey(nullptr, key.get(), nullptr));
    if (!ctx) return nullptr;
    const int init = encrypt ? EVP_PKEY_encrypt_init(ctx.get()) : EVP_PKEY_decrypt_init(ctx.get());
    if (init != 1 || EVP_PKEY_CTX_set_rsa_padding(ctx.get(), RSA_PKCS1_OAEP_PADDING) != 1 ||
        EVP_PKEY_CTX_set_rsa_oaep_md(ctx.get(), oaepDigest(algorithm)) != 1 ||
        EVP_PKEY_CTX_set_rsa_mgf1_md(ctx.get(), oaepDigest(algorithm)) != 1) {
        return nullptr;
    }
    return ctx;
}

bool setSignaturePadding(EVP_PKEY_CTX* ctx, RsaSignature algorithm) {
    if (algorithm == RsaSignature::Pkcs1v15Sha256) {
        return EVP_PKEY_CTX_set_rsa_padding(ctx, RSA_PKCS1_PADDING) == 1;
    }
    // RSA-PSS-SHA2-256: MGF1 with SHA-256 and a salt as long as the hash (OPC 10000-7).
    return EVP_PKEY_CTX_set_rsa_padding(ctx, RSA_PKCS1_PSS_PADDING) == 1 &&
           EVP_PKEY_CTX_set_rsa_pss_saltlen(ctx, RSA_PSS_SALTLEN_DIGEST) == 1 &&
           EVP_PKEY_CTX_set_rsa_mgf1_md(ctx, EVP_sha256()) == 1;
}

bool isRsa(EVP_PKEY* key) {
    return key != nullptr && EVP_PKEY_is_a(key, "RSA") == 1;
}

}  // namespace

std::size_t oaepOverhead(RsaEncryption algorithm) {
    return algorithm == RsaEncryption::OaepSha1 ? 42 : 66;
}

Result<RsaKey> RsaKey::fromCertificate(ByteView der) {
    const unsigned char* p = der.data();
    // d2i_X509 reads the first certificate of a chain and stops there.
    const X509Handle cert(d2i_X509(nullptr, &p, static_cast<long>(der.size())));
    if (!cert) return status::BadCertificateInvalid;
    EVP_PKEY* key = X509_get_pubkey(cert.get());
    if (!isRsa(key)) {
        EVP_PKEY_free(key);
        return status::BadCertificateInvalid;
    }
    return RsaKey(share(key));
}

Result<RsaKey> RsaKey::fromPrivateKeyFile(const std::filesystem::path& pem) {
    std::FILE* f = std::fopen(pem.c_str(), "rb");
    if (f == nullptr) return status::BadConfigurationError;
    EVP_PKEY* key = PEM_read_PrivateKey(f, nullptr, nullptr, nullptr);
    std::fclose(f);
    if (!isRsa(key)) {
        EVP_PKEY_free(key);
        return status::BadConfigurationError;
    }
    return RsaKey(share(key));
}

Result<RsaKey> RsaKey::generate(int bits) {
    EVP_PKEY* key = EVP_RSA_gen(static_cast<unsigned>(bits));
    if (key == nullptr) return status::BadInternalError;
    return RsaKey(share(key));
}

std::size_t RsaKey::sizeBytes() const {
    return key_ ? static_cast<std::size_t>(EVP_PKEY_get_size(key_.get())) : 0;
}

int RsaKey::bits() const {
    return key_ ? EVP_PKEY_get_bits(key_.get()) : 0;
}

Result<Bytes> rsaEncrypt(const RsaKey& publicKey, RsaEncryption algorithm, ByteView plain) {
    const std::size_t keySize = publicKey.sizeBytes();
    if (keySize <= oaepOverhead(algorithm)) return status::BadSecurityChecksFailed;
    const std::size_t block = keySize - oaepOverhead(algorithm);
    auto ctx = oaepContext(publicKey, algorithm, true);
    if (!ctx) return status::BadInternalError;
    Bytes out;
    out.reserve((plain.size() + block - 1) / block * keySize);
    for (std::size_t offset = 0; offset < plain.size(); offset += block) {
        const auto piece = plain.subspan(offset, std::min(block, plain.size() - offset));
        std::size_t written = keySize;
        const auto at = out.size();
        out.resize(at + keySize);
        if (EVP_PKEY_encrypt(ctx.get(), out.data() + at, &written, piece.data(), piece.size()) !=
                1 ||
            written != keySize) {
            return status::BadSecurityChecksFailed;
        }
    }
    return out;
}

Result<Bytes> rsaDecrypt(const RsaKey& privateKey, RsaEncryption algorithm, ByteView cipher) {
    const std::size_t keySize = privateKey.sizeBytes();
    if (keySize == 0 || cipher.size() % keySize != 0) return status::BadSecurityChecksFailed;
    auto ctx = oaepContext(privateKey, algorithm, false);
    if (!ctx) return status::BadInternalError;
    Bytes out;
    out.reserve(cipher.size());
    for (std::size_t offset = 0; offset < cipher.size(); offset += keySize) {
        const auto at = out.size();
        out.resize(at + keySize);
        std::size_t written = keySize;
        if (EVP_PKEY_decrypt(ctx.get(), out.data() + at, &written, cipher.data() + offset,
                             keySize) != 1) {
            return status::BadSecurityChecksFailed;
        }
        out.resize(at + written);
    }
    return out;
}

Result<Bytes> rsaSign(const RsaKey& privateKey, RsaSignature algorithm, ByteView data) {
    MdCtxHandle md(EVP_MD_CTX_new());
    EVP_PKEY_CTX* pctx = nullptr;  // owned by md
    if (!md || EVP_DigestSignInit(md.get(), &pctx, EVP_sha256(), nullptr, privateKey.get()) != 1 ||
        !setSignaturePadding(pctx, algorithm)) {
        return status::BadInternalError;
    }
    std::size_t size = 0;
    if (EVP_DigestSign(md.get(), nullptr, &size, data.data(), data.size()) != 1) {
        return status::BadInternalError;
    }
    Bytes signature(size);
    if (EVP_DigestSign(md.get(), signature.data(), &size, data.data(), data.size()) != 1) {
        return status::BadInternalError;
    }
    signature.resize(size);
    return signature;
}

StatusCode rsaVerify(const RsaKey& publicKey, RsaSignature algorithm, ByteView data,
                     ByteView signature) {
    MdCtxHandle md(EVP_MD_CTX_new());
    EVP_PKEY_CTX* pctx = nullptr;
    if (!md || !publicKey.valid() ||
        EVP_DigestVerifyInit(md.get(), &pctx, EVP_sha256(), nullptr, publicKey.get()) != 1 ||
        !setSignaturePadding(pctx, algorithm)) {
        return status::BadSecurityChecksFailed;
    }
    return EVP_DigestVerify(md.get(), signature.data(), signature.size(), data.data(),
                            data.size()) == 1
               ? status::Good
               : status::BadSecurityChecksFailed;
}

Bytes hmacSha256(ByteView key, ByteView data) {
    Bytes mac(SHA256_DIGEST_LENGTH);
    unsigned int size = 0;
    HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), data.data(), data.size(),
         mac.data(), &size);
    mac.resize(size);
    return mac;
}

namespace {

StatusCode aesCbc(ByteView key, ByteView iv, std::span<std::uint8_t> data, bool encrypt) {
    if (data.size() % kAesBlock != 0 || iv.size() != kAesBlock ||
        data.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        return status::BadSecurityChecksFailed;
    }
    const EVP_CIPHER* cipher = key.size() == 16   ? EVP_aes_128_cbc()
                               : key.size() == 32 ? EVP_aes_256_cbc()
                                                  : nullptr;
    if (cipher == nullptr) return status::BadInternalError;
    CipherCtxHandle ctx(EVP_CIPHER_CTX_new());
    if (!ctx ||
        EVP_CipherInit_ex(ctx.get(), cipher, nullptr, key.data(), iv.data(), encrypt ? 1 : 0) !=
            1 ||
        EVP_CIPHER_CTX_set_padding(ctx.get(), 0) != 1) {
        return status::BadInternalError;
    }
    int written = 0;
    // In place: OpenSSL allows out == in for CBC.
    if (EVP_CipherUpdate(ctx.get(), data.data(), &written, data.data(),
                         static_cast<int>(data.size())) != 1 ||
        static_cast<std::size_t>(written) != data.size()) {
        return status::BadSecurityChecksFailed;
    }
    return status::Good;
}

}  // namespace

StatusCode aesCbcEncrypt(ByteView key, ByteView iv, std::span<std::uint8_t> data) {
    return aesCbc(key, iv, data, true);
}

StatusCode aesCbcDecrypt(ByteView key, ByteView iv, std::span<std::uint8_t> data) {
    return aesCbc(key, iv, data, false);
}

Bytes pSha256(ByteView secret, ByteView seed, std::size_t length) {
    // A(0) = seed; A(i) = HMAC(secret, A(i-1)); output = HMAC(secret, A(1) + seed) + ...
    Bytes out;
    out.reserve(length + SHA256_DIGEST_LENGTH);
    Bytes a(seed.begin(), seed.end());
    Bytes input;
    while (out.size() < length) {
        a = hmacSha256(secret, a);
        input.assign(a.begin(), a.end());
        input.insert(input.end(), seed.begin(), seed.end());
        const Bytes block = hmacSha256(secret, input);
        out.insert(out.end(), block.begin(), block.end());
    }
    out.resize(length);
    return out;
}

Bytes sha1(ByteView data) {
    Bytes digest(SHA_DIGEST_LENGTH);
    SHA1(data.data(), data.size(), digest.data());
    return digest;
}

Bytes randomBytes(std::size_t n) {
    Bytes out(n);
    // RAND_bytes fails only if the DRBG cannot be seeded; a nonce of zeros would be worse
    // than stopping, so fail loudly.
    if (n != 0 && RAND_bytes(out.data(), static_cast<int>(n)) != 1) std::abort();
    return out;
}

bool equalConstantTime(ByteView a, ByteView b) {
    return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

}  // namespace skillcell::ua::crypto
