#include "ua/crypto/primitives.hpp"

#include <openssl/bio.h>
#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/decoder.h>
#include <openssl/ec.h>
#include <openssl/hmac.h>
#include <openssl/kdf.h>
#include <openssl/param_build.h>
#include <openssl/pem.h>
#include <openssl/rand.h>
#include <openssl/rsa.h>
#include <openssl/sha.h>

#include <array>
#include <cstdio>
#include <limits>
#include <optional>

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
PKeyCtxHandle oaepContext(const AsymmetricKey& key, RsaEncryption algorithm, bool encrypt) {
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

bool setSignaturePadding(EVP_PKEY_CTX* ctx, SignatureAlgorithm algorithm) {
    if (algorithm == SignatureAlgorithm::Pkcs1v15Sha256) {
        return EVP_PKEY_CTX_set_rsa_padding(ctx, RSA_PKCS1_PADDING) == 1;
    }
    // RSA-PSS-SHA2-256: MGF1 with SHA-256 and a salt as long as the hash (OPC 10000-7).
    return EVP_PKEY_CTX_set_rsa_padding(ctx, RSA_PKCS1_PSS_PADDING) == 1 &&
           EVP_PKEY_CTX_set_rsa_pss_saltlen(ctx, RSA_PSS_SALTLEN_DIGEST) == 1 &&
           EVP_PKEY_CTX_set_rsa_mgf1_md(ctx, EVP_sha256()) == 1;
}

/// A curve of the ECC policies: OpenSSL's name of it, its coordinates' size, and the ECDSA
/// its keys sign with (the hash of the same strength).
struct Curve {
    AsymmetricKey::Kind kind;
    const char* group;
    int nid;  // the named curve's OID, as OpenSSL numbers it
    std::size_t coordinate;
    SignatureAlgorithm ecdsa;
    HashAlgorithm hash;
};
constexpr std::array<Curve, 2> kCurves{{
    {AsymmetricKey::Kind::EccNistP256, "prime256v1", NID_X9_62_prime256v1, 32,
     SignatureAlgorithm::EcdsaSha256, HashAlgorithm::Sha256},
    {AsymmetricKey::Kind::EccNistP384, "secp384r1", NID_secp384r1, 48,
     SignatureAlgorithm::EcdsaSha384, HashAlgorithm::Sha384},
}};

const EVP_MD* mdOf(HashAlgorithm hash) {
    return hash == HashAlgorithm::Sha384 ? EVP_sha384() : EVP_sha256();
}

const Curve* curveOf(AsymmetricKey::Kind kind) {
    for (const auto& c : kCurves) {
        if (c.kind == kind) return &c;
    }
    return nullptr;
}

/// The public key at `point` (uncompressed: 0x04 || x || y) on `curve`; null when the point
/// is not one of the curve's (OpenSSL's import checks that it lies on it).
PKeyHandle eccPublicKey(const Curve& curve, ByteView point) {
    const std::unique_ptr<OSSL_PARAM_BLD, void (*)(OSSL_PARAM_BLD*)> build(OSSL_PARAM_BLD_new(),
                                                                           OSSL_PARAM_BLD_free);
    if (!build ||
        OSSL_PARAM_BLD_push_utf8_string(build.get(), OSSL_PKEY_PARAM_GROUP_NAME, curve.group, 0) !=
            1 ||
        OSSL_PARAM_BLD_push_octet_string(build.get(), OSSL_PKEY_PARAM_PUB_KEY, point.data(),
                                         point.size()) != 1) {
        return nullptr;
    }
    const std::unique_ptr<OSSL_PARAM, void (*)(OSSL_PARAM*)> params(
        OSSL_PARAM_BLD_to_param(build.get()), OSSL_PARAM_free);
    const PKeyCtxHandle fromData(EVP_PKEY_CTX_new_from_name(nullptr, "EC", nullptr));
    EVP_PKEY* key = nullptr;
    if (!params || !fromData || EVP_PKEY_fromdata_init(fromData.get()) != 1 ||
        EVP_PKEY_fromdata(fromData.get(), &key, EVP_PKEY_PUBLIC_KEY, params.get()) != 1) {
        return nullptr;
    }
    return PKeyHandle(key);
}

/// The next DER element at `p` (before `end`): its content's start and length, `p` moved
/// past it; false when there is none or it overruns.
bool nextElement(const unsigned char*& p, const unsigned char* end, const unsigned char** content,
                 long* length, int* tag, int* tagClass) {
    if (p >= end) return false;
    const int flags = ASN1_get_object(&p, length, tag, tagClass, end - p);
    // 0x80: an error; 0x21 (constructed, indefinite length) has no place in DER.
    if ((flags & 0x80) != 0 || flags == 0x21 || *length > end - p) return false;
    *content = p;
    p += *length;
    return true;
}

/// The public key of a certificate whose key is on one of our curves, read from its
/// SubjectPublicKeyInfo alone; null for any other certificate (RSA, another curve, DER
/// that does not have the shape), which then takes d2i_X509. Why: OpenSSL 3.0's d2i_X509
/// decodes the key through its decoder framework, which builds a chain of decoders for
/// every certificate it reads (240 us for a P-256 one on the 2-core machine, more than the
/// handshake's ECDSA signature and verification together, on both ends of every secured
/// connection). The certificate itself is validated elsewhere (the CertificateValidator,
/// which reads it whole); this only takes its key, as d2i_X509 would.
PKeyHandle eccKeyOfCertificate(ByteView der) {
    const unsigned char* p = der.data();
    const unsigned char* end = p + der.size();
    const unsigned char* content = nullptr;
    long length = 0;
    int tag = 0;
    int tagClass = 0;
    // Certificate ::= SEQUENCE { tbsCertificate, signatureAlgorithm, signature }: that shape,
    // with nothing after the signature, as d2i_X509 would insist on.
    if (!nextElement(p, end, &content, &length, &tag, &tagClass) || tag != V_ASN1_SEQUENCE) {
        return nullptr;
    }
    p = content;
    end = content + length;
    const unsigned char* tbs = nullptr;
    long tbsLength = 0;
    if (!nextElement(p, end, &tbs, &tbsLength, &tag, &tagClass) || tag != V_ASN1_SEQUENCE ||
        !nextElement(p, end, &content, &length, &tag, &tagClass) || tag != V_ASN1_SEQUENCE ||
        !nextElement(p, end, &content, &length, &tag, &tagClass) || tag != V_ASN1_BIT_STRING ||
        p != end) {
        return nullptr;
    }
    // TBSCertificate ::= SEQUENCE { [0] version OPTIONAL, serialNumber, signature, issuer,
    //                               validity, subject, subjectPublicKeyInfo, ... }
    p = tbs;
    end = tbs + tbsLength;
    const unsigned char* element = p;
    if (!nextElement(p, end, &content, &length, &tag, &tagClass)) return nullptr;
    if (tagClass == V_ASN1_CONTEXT_SPECIFIC && tag == 0) element = p;  // the version
    p = element;
    for (int skipped = 0; skipped < 5; ++skipped) {  // serial number ... subject
        if (!nextElement(p, end, &content, &length, &tag, &tagClass)) return nullptr;
    }
    // SubjectPublicKeyInfo ::= SEQUENCE { algorithm AlgorithmIdentifier, BIT STRING }
    if (!nextElement(p, end, &content, &length, &tag, &tagClass) || tag != V_ASN1_SEQUENCE) {
        return nullptr;
    }
    p = content;
    end = content + length;
    const std::unique_ptr<X509_ALGOR, void (*)(X509_ALGOR*)> algorithm(
        d2i_X509_ALGOR(nullptr, &p, end - p), X509_ALGOR_free);
    if (!algorithm || p >= end) return nullptr;
    const std::unique_ptr<ASN1_BIT_STRING, void (*)(ASN1_BIT_STRING*)> bits(
        d2i_ASN1_BIT_STRING(nullptr, &p, end - p), ASN1_BIT_STRING_free);
    if (!bits || p != end) return nullptr;
    const ASN1_OBJECT* keyType = nullptr;
    int parameterType = 0;
    const void* parameter = nullptr;
    X509_ALGOR_get0(&keyType, &parameterType, &parameter, algorithm.get());
    if (OBJ_obj2nid(keyType) != NID_X9_62_id_ecPublicKey || parameterType != V_ASN1_OBJECT) {
        return nullptr;
    }
    const int curveNid = OBJ_obj2nid(static_cast<const ASN1_OBJECT*>(parameter));
    const Curve* curve = nullptr;
    for (const auto& c : kCurves) {
        if (c.nid == curveNid) curve = &c;
    }
    // A key is a whole number of octets: no unused bits.
    const bool unusedBits =
        (bits->flags & ASN1_STRING_FLAG_BITS_LEFT) != 0 && (bits->flags & 0x07) != 0;
    if (curve == nullptr || unusedBits) {
        return nullptr;
    }
    return eccPublicKey(*curve, ByteView(bits->data, static_cast<std::size_t>(bits->length)));
}

/// The curve of an EC key, if it is one of ours.
const Curve* curveOfKey(EVP_PKEY* key) {
    if (EVP_PKEY_is_a(key, "EC") != 1) return nullptr;
    char group[64] = {};
    std::size_t length = 0;
    if (EVP_PKEY_get_utf8_string_param(key, OSSL_PKEY_PARAM_GROUP_NAME, group, sizeof(group),
                                       &length) != 1) {
        return nullptr;
    }
    for (const auto& c : kCurves) {
        if (std::string_view(group, length) == c.group) return &c;
    }
    return nullptr;
}

/// The curve an ECDSA algorithm signs on; nothing for the RSA algorithms.
const Curve* curveSigning(SignatureAlgorithm algorithm) {
    for (const auto& c : kCurves) {
        if (c.ecdsa == algorithm) return &c;
    }
    return nullptr;
}
/// The key kind an algorithm signs with, and its digest (SHA-256 for the RSA algorithms).
AsymmetricKey::Kind keyKindOf(SignatureAlgorithm algorithm) {
    const Curve* curve = curveSigning(algorithm);
    return curve != nullptr ? curve->kind : AsymmetricKey::Kind::Rsa;
}
const EVP_MD* digestOf(SignatureAlgorithm algorithm) {
    const Curve* curve = curveSigning(algorithm);
    return mdOf(curve != nullptr ? curve->hash : HashAlgorithm::Sha256);
}

/// OpenSSL's DER ECDSA-Sig-Value as r || s, each `half` bytes.
Result<Bytes> rawFromDer(ByteView der, std::size_t half) {
    const unsigned char* p = der.data();
    const std::unique_ptr<ECDSA_SIG, void (*)(ECDSA_SIG*)> sig(
        d2i_ECDSA_SIG(nullptr, &p, static_cast<long>(der.size())), ECDSA_SIG_free);
    if (!sig) return status::BadInternalError;
    Bytes raw(2 * half);
    if (BN_bn2binpad(ECDSA_SIG_get0_r(sig.get()), raw.data(), static_cast<int>(half)) < 0 ||
        BN_bn2binpad(ECDSA_SIG_get0_s(sig.get()), raw.data() + half, static_cast<int>(half)) < 0) {
        return status::BadInternalError;
    }
    return raw;
}

/// r || s as DER, for OpenSSL's verification; nothing when the halves do not fit.
Result<Bytes> derFromRaw(ByteView raw, std::size_t half) {
    if (raw.size() != 2 * half) return status::BadSecurityChecksFailed;
    const std::unique_ptr<ECDSA_SIG, void (*)(ECDSA_SIG*)> sig(ECDSA_SIG_new(), ECDSA_SIG_free);
    BIGNUM* r = BN_bin2bn(raw.data(), static_cast<int>(half), nullptr);
    BIGNUM* s = BN_bin2bn(raw.data() + half, static_cast<int>(half), nullptr);
    if (!sig || r == nullptr || s == nullptr || ECDSA_SIG_set0(sig.get(), r, s) != 1) {
        BN_free(r);
        BN_free(s);
        return status::BadInternalError;
    }
    unsigned char* out = nullptr;
    const int length = i2d_ECDSA_SIG(sig.get(), &out);
    if (length <= 0) return status::BadInternalError;
    Bytes der(out, out + length);
    OPENSSL_free(out);
    return der;
}

}  // namespace

Result<AsymmetricKey> AsymmetricKey::adopt(EVP_PKEY* key, StatusCode otherwise) {
    if (key != nullptr && EVP_PKEY_is_a(key, "RSA") == 1) {
        return AsymmetricKey(share(key), Kind::Rsa);
    }
    if (const Curve* curve = key != nullptr ? curveOfKey(key) : nullptr) {
        return AsymmetricKey(share(key), curve->kind);
    }
    EVP_PKEY_free(key);
    return otherwise;
}

std::size_t oaepOverhead(RsaEncryption algorithm) {
    return algorithm == RsaEncryption::OaepSha1 ? 42 : 66;
}

Result<AsymmetricKey> AsymmetricKey::fromCertificate(ByteView der) {
    if (auto ecc = eccKeyOfCertificate(der))
        return adopt(ecc.release(), status::BadCertificateInvalid);
    const unsigned char* p = der.data();
    // d2i_X509 reads the first certificate of a chain and stops there.
    const X509Handle cert(d2i_X509(nullptr, &p, static_cast<long>(der.size())));
    if (!cert) return status::BadCertificateInvalid;
    return adopt(X509_get_pubkey(cert.get()), status::BadCertificateInvalid);
}

Result<AsymmetricKey> AsymmetricKey::fromPrivateKeyFile(const std::filesystem::path& pem) {
    const std::unique_ptr<BIO, int (*)(BIO*)> in(BIO_new_file(pem.c_str(), "rb"), BIO_free);
    if (!in) return status::BadConfigurationError;
    return adopt(PEM_read_bio_PrivateKey(in.get(), nullptr, nullptr, nullptr),
                 status::BadConfigurationError);
}

Result<AsymmetricKey> AsymmetricKey::fromPrivateKeyFile(const std::filesystem::path& pem,
                                                        Kind expected) {
    const std::unique_ptr<BIO, int (*)(BIO*)> in(BIO_new_file(pem.c_str(), "rb"), BIO_free);
    if (!in) return status::BadConfigurationError;
    EVP_PKEY* key = nullptr;
    const std::unique_ptr<OSSL_DECODER_CTX, void (*)(OSSL_DECODER_CTX*)> decoder(
        OSSL_DECODER_CTX_new_for_pkey(&key, "PEM", nullptr, expected == Kind::Rsa ? "RSA" : "EC",
                                      OSSL_KEYMGMT_SELECT_KEYPAIR, nullptr, nullptr),
        OSSL_DECODER_CTX_free);
    if (!decoder || OSSL_DECODER_from_bio(decoder.get(), in.get()) != 1) {
        EVP_PKEY_free(key);
        return status::BadConfigurationError;
    }
    auto out = adopt(key, status::BadConfigurationError);
    if (out && out->kind() != expected) return status::BadConfigurationError;
    return out;
}

Result<AsymmetricKey> AsymmetricKey::generate(int bits) {
    EVP_PKEY* key = EVP_RSA_gen(static_cast<unsigned>(bits));
    if (key == nullptr) return status::BadInternalError;
    return AsymmetricKey(share(key), Kind::Rsa);
}

std::optional<SignatureAlgorithm> ecdsaAlgorithmFor(AsymmetricKey::Kind kind) {
    const Curve* curve = curveOf(kind);
    if (curve == nullptr) return std::nullopt;
    return curve->ecdsa;
}

Result<AsymmetricKey> AsymmetricKey::generateEcc(Kind kind) {
    const Curve* curve = curveOf(kind);
    if (curve == nullptr) return status::BadInternalError;
    EVP_PKEY* key = EVP_EC_gen(curve->group);
    if (key == nullptr) return status::BadInternalError;
    return AsymmetricKey(share(key), kind);
}

std::size_t AsymmetricKey::sizeBytes() const {
    if (!key_) return 0;
    // EVP_PKEY_get_size of an EC key is the longest DER signature, not r || s.
    if (const Curve* curve = curveOf(kind_)) return 2 * curve->coordinate;
    return static_cast<std::size_t>(EVP_PKEY_get_size(key_.get()));
}

Result<EphemeralKey> EphemeralKey::generate(AsymmetricKey::Kind kind) {
    const Curve* curve = curveOf(kind);
    if (curve == nullptr) return status::BadInternalError;
    EVP_PKEY* raw = EVP_EC_gen(curve->group);
    if (raw == nullptr) return status::BadInternalError;
    EphemeralKey out;
    out.key_ = share(raw);
    out.curve_ = kind;
    // The uncompressed point: 0x04 || X || Y.
    std::array<unsigned char, 1 + 2 * 48> point{};
    const std::size_t expected = 1 + 2 * curve->coordinate;
    std::size_t length = 0;
    if (EVP_PKEY_get_octet_string_param(raw, OSSL_PKEY_PARAM_PUB_KEY, point.data(), point.size(),
                                        &length) != 1 ||
        length != expected || point[0] != 0x04) {
        return status::BadInternalError;
    }
    out.public_.assign(point.begin() + 1, point.begin() + static_cast<std::ptrdiff_t>(length));
    return out;
}

Result<Bytes> EphemeralKey::agree(ByteView peerPublicKey) const {
    const Curve* curve = curveOf(curve_);
    if (!key_ || curve == nullptr || peerPublicKey.size() != 2 * curve->coordinate) {
        return status::BadNonceInvalid;
    }
    Bytes point{0x04};
    point.insert(point.end(), peerPublicKey.begin(), peerPublicKey.end());
    const PKeyHandle peer = eccPublicKey(*curve, point);
    if (!peer) return status::BadNonceInvalid;  // not a point of the curve
    // The peer's point: within the field, on the curve, not the point at infinity. The
    // curves here (P-256, P-384) have cofactor 1, so such a point has the group's prime order,
    // and the full check's order test (a scalar multiplication as costly as the agreement
    // itself) adds nothing: the partial validation of SP 800-56A (5.6.2.3.4) suffices for an
    // ephemeral key. OpenSSL's own check in derive_set_peer (the full one again) is skipped
    // too: each cost a scalar multiplication beside the agreement's own.
    const PKeyCtxHandle check(EVP_PKEY_CTX_new_from_pkey(nullptr, peer.get(), nullptr));
    if (!check || EVP_PKEY_public_check_quick(check.get()) != 1) return status::BadNonceInvalid;
    const PKeyCtxHandle derive(EVP_PKEY_CTX_new_from_pkey(nullptr, key_.get(), nullptr));
    std::size_t size = 0;
    if (!derive || EVP_PKEY_derive_init(derive.get()) != 1 ||
        EVP_PKEY_derive_set_peer_ex(derive.get(), peer.get(), /*validate_peer=*/0) != 1 ||
        EVP_PKEY_derive(derive.get(), nullptr, &size) != 1) {
        return status::BadNonceInvalid;
    }
    Bytes secret(size);
    if (EVP_PKEY_derive(derive.get(), secret.data(), &size) != 1) return status::BadInternalError;
    secret.resize(size);
    return secret;
}

int AsymmetricKey::bits() const {
    return key_ ? EVP_PKEY_get_bits(key_.get()) : 0;
}

Result<Bytes> rsaEncrypt(const AsymmetricKey& publicKey, RsaEncryption algorithm, ByteView plain) {
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

Result<Bytes> rsaDecrypt(const AsymmetricKey& privateKey, RsaEncryption algorithm,
                         ByteView cipher) {
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

Result<Bytes> sign(const AsymmetricKey& privateKey, SignatureAlgorithm algorithm, ByteView data) {
    const bool ecdsa = keyKindOf(algorithm) != AsymmetricKey::Kind::Rsa;
    if (!privateKey.valid() || privateKey.kind() != keyKindOf(algorithm)) {
        return status::BadInternalError;  // our key does not fit our policy
    }
    MdCtxHandle md(EVP_MD_CTX_new());
    EVP_PKEY_CTX* pctx = nullptr;  // owned by md
    if (!md ||
        EVP_DigestSignInit(md.get(), &pctx, digestOf(algorithm), nullptr, privateKey.get()) != 1 ||
        (!ecdsa && !setSignaturePadding(pctx, algorithm))) {
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
    if (ecdsa) return rawFromDer(signature, privateKey.sizeBytes() / 2);
    return signature;
}

StatusCode verify(const AsymmetricKey& publicKey, SignatureAlgorithm algorithm, ByteView data,
                  ByteView signature) {
    const bool ecdsa = keyKindOf(algorithm) != AsymmetricKey::Kind::Rsa;
    if (!publicKey.valid() || publicKey.kind() != keyKindOf(algorithm)) {
        return status::BadSecurityChecksFailed;
    }
    Bytes der;
    if (ecdsa) {
        auto converted = derFromRaw(signature, publicKey.sizeBytes() / 2);
        if (!converted) return status::BadSecurityChecksFailed;
        der = std::move(*converted);
        signature = der;
    }
    MdCtxHandle md(EVP_MD_CTX_new());
    EVP_PKEY_CTX* pctx = nullptr;
    if (!md ||
        EVP_DigestVerifyInit(md.get(), &pctx, digestOf(algorithm), nullptr, publicKey.get()) != 1 ||
        (!ecdsa && !setSignaturePadding(pctx, algorithm))) {
        return status::BadSecurityChecksFailed;
    }
    return EVP_DigestVerify(md.get(), signature.data(), signature.size(), data.data(),
                            data.size()) == 1
               ? status::Good
               : status::BadSecurityChecksFailed;
}

Bytes hmac(HashAlgorithm hash, ByteView key, ByteView data) {
    Bytes mac(EVP_MAX_MD_SIZE);
    unsigned int size = 0;
    HMAC(mdOf(hash), key.data(), static_cast<int>(key.size()), data.data(), data.size(), mac.data(),
         &size);
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

Result<Bytes> hkdf(HashAlgorithm hash, ByteView salt, ByteView secret, ByteView info,
                   std::size_t length) {
    const std::unique_ptr<EVP_KDF, void (*)(EVP_KDF*)> kdf(EVP_KDF_fetch(nullptr, "HKDF", nullptr),
                                                           EVP_KDF_free);
    const std::unique_ptr<EVP_KDF_CTX, void (*)(EVP_KDF_CTX*)> ctx(
        kdf ? EVP_KDF_CTX_new(kdf.get()) : nullptr, EVP_KDF_CTX_free);
    // OSSL_PARAM takes non-const pointers; OpenSSL only reads them.
    auto* saltData = const_cast<std::uint8_t*>(salt.data());
    auto* secretData = const_cast<std::uint8_t*>(secret.data());
    auto* infoData = const_cast<std::uint8_t*>(info.data());
    // The digest mdOf() picks, by the name OpenSSL knows it by: the HMAC's and this cannot
    // differ.
    std::string digest = EVP_MD_get0_name(mdOf(hash));
    const OSSL_PARAM params[] = {
        OSSL_PARAM_construct_utf8_string(OSSL_KDF_PARAM_DIGEST, digest.data(), 0),
        OSSL_PARAM_construct_octet_string(OSSL_KDF_PARAM_SALT, saltData, salt.size()),
        OSSL_PARAM_construct_octet_string(OSSL_KDF_PARAM_KEY, secretData, secret.size()),
        OSSL_PARAM_construct_octet_string(OSSL_KDF_PARAM_INFO, infoData, info.size()),
        OSSL_PARAM_construct_end(),
    };
    Bytes out(length);
    if (!ctx || EVP_KDF_derive(ctx.get(), out.data(), out.size(), params) != 1) {
        return status::BadInternalError;
    }
    return out;
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
