#include "ua/crypto/security_policy_profile.hpp"

#include <array>

namespace skillcell::ua::crypto {
namespace {

constexpr std::string_view kRsaSha256 = "http://www.w3.org/2001/04/xmldsig-more#rsa-sha256";
constexpr std::string_view kRsaPssSha256 = "http://opcfoundation.org/UA/security/rsa-pss-sha2-256";
constexpr std::string_view kRsaOaep = "http://www.w3.org/2001/04/xmlenc#rsa-oaep";
constexpr std::string_view kRsaOaepSha256 =
    "http://opcfoundation.org/UA/security/rsa-oaep-sha2-256";
constexpr std::string_view kEcdsaSha256 = "http://www.w3.org/2001/04/xmldsig-more#ecdsa-sha256";
constexpr std::string_view kEcdsaSha384 = "http://www.w3.org/2001/04/xmldsig-more#ecdsa-sha384";

constexpr std::array<SecurityPolicyProfile, 5> kProfiles{{
    {kPolicyAes128Sha256RsaOaep, "Aes128_Sha256_RsaOaep", RsaEncryption::OaepSha1,
     SignatureAlgorithm::Pkcs1v15Sha256, kRsaSha256, kRsaOaep, 16, 32, 32, 32, 2048, 4096, 2},
    {kPolicyBasic256Sha256, "Basic256Sha256", RsaEncryption::OaepSha1,
     SignatureAlgorithm::Pkcs1v15Sha256, kRsaSha256, kRsaOaep, 32, 32, 32, 32, 2048, 4096, 3},
    {kPolicyAes256Sha256RsaPss, "Aes256_Sha256_RsaPss", RsaEncryption::OaepSha256,
     SignatureAlgorithm::PssSha256, kRsaPssSha256, kRsaOaepSha256, 32, 32, 32, 32, 2048, 4096, 4},
    // OPC 10000-7, ECC_nistP256: ECDSA-SHA2-256 and ECDH on P-256, HKDF-SHA2-256,
    // AES128-CBC, HMAC-SHA2-256; the nonces are 64-byte EphemeralKeys. Ranked above the RSA
    // policies: P-256 is a 128-bit security level, RSA 2048 a 112-bit one (NIST SP 800-57).
    {kPolicyEccNistP256,
     "ECC_nistP256",
     RsaEncryption::OaepSha256,
     SignatureAlgorithm::EcdsaSha256,
     kEcdsaSha256,
     {},
     16,
     32,
     32,
     64,
     256,
     256,
     5,
     AsymmetricKey::Kind::EccNistP256},
    // OPC 10000-7, ECC_nistP384: ECDSA-SHA2-384 and ECDH on P-384, HKDF-SHA2-384,
    // AES256-CBC, HMAC-SHA2-384 (48-byte keys and signatures); 96-byte nonces. A 192-bit
    // security level: the strongest policy here.
    {kPolicyEccNistP384,
     "ECC_nistP384",
     RsaEncryption::OaepSha256,
     SignatureAlgorithm::EcdsaSha384,
     kEcdsaSha384,
     {},
     32,
     48,
     48,
     96,
     384,
     384,
     6,
     AsymmetricKey::Kind::EccNistP384,
     HashAlgorithm::Sha384},
}};

}  // namespace

std::span<const SecurityPolicyProfile> securityPolicyProfiles() {
    return kProfiles;
}

const SecurityPolicyProfile* findSecurityPolicyProfile(std::string_view uri) {
    for (const auto& p : kProfiles) {
        if (p.uri == uri) return &p;
    }
    return nullptr;
}

const SecurityPolicyProfile* findSecurityPolicyProfileByName(std::string_view name) {
    for (const auto& p : kProfiles) {
        if (p.uri == name || p.shortName == name) return &p;
    }
    return nullptr;
}

}  // namespace skillcell::ua::crypto
