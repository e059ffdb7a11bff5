#pragma once
// SecurityPolicyProfile: what one OPC UA security policy URI stands for (OPC 10000-7, the
// SecurityPolicy facets): which algorithms, which key and nonce lengths. A value type and a
// table; the secure channel and the session services read it, nothing else decides.
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "ua/crypto/primitives.hpp"

namespace skillcell::ua::crypto {

inline constexpr std::string_view kPolicyBasic256Sha256 =
    "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256";
inline constexpr std::string_view kPolicyAes128Sha256RsaOaep =
    "http://opcfoundation.org/UA/SecurityPolicy#Aes128_Sha256_RsaOaep";
inline constexpr std::string_view kPolicyAes256Sha256RsaPss =
    "http://opcfoundation.org/UA/SecurityPolicy#Aes256_Sha256_RsaPss";
inline constexpr std::string_view kPolicyEccNistP256 =
    "http://opcfoundation.org/UA/SecurityPolicy#ECC_nistP256";
inline constexpr std::string_view kPolicyEccNistP384 =
    "http://opcfoundation.org/UA/SecurityPolicy#ECC_nistP384";

struct SecurityPolicyProfile {
    std::string_view uri;
    std::string_view shortName;  // for command lines and logs: "Basic256Sha256"
    /// RSA policies only: ECC encrypts nothing asymmetrically.
    RsaEncryption asymmetricEncryption = RsaEncryption::OaepSha1;
    SignatureAlgorithm asymmetricSignature = SignatureAlgorithm::Pkcs1v15Sha256;
    /// The URIs OPC UA names these algorithms by in SignatureData and identity tokens.
    std::string_view asymmetricSignatureUri;
    std::string_view asymmetricEncryptionUri;
    std::size_t symmetricKeyLength = 32;  // AES key, bytes
    std::size_t signingKeyLength = 32;    // HMAC key, bytes
    std::size_t symmetricSignatureSize = 32;
    /// ECC: an EphemeralKey's public half (X || Y).
    std::size_t nonceLength = 32;
    int minAsymmetricKeyBits = 2048;
    int maxAsymmetricKeyBits = 4096;
    /// Relative strength, for EndpointDescription.securityLevel.
    std::uint8_t strength = 1;
    /// The kind of key the certificates of both ends must have.
    AsymmetricKey::Kind keyKind = AsymmetricKey::Kind::Rsa;
    /// The symmetric signature's HMAC and the ECC key derivation's HKDF hash.
    HashAlgorithm hash = HashAlgorithm::Sha256;

    [[nodiscard]] bool isEcc() const { return keyKind != AsymmetricKey::Kind::Rsa; }
};

/// The policies this stack implements besides None, strongest last (each key kind's).
[[nodiscard]] std::span<const SecurityPolicyProfile> securityPolicyProfiles();
/// The profile of a policy URI, or nothing for None and unknown URIs.
[[nodiscard]] const SecurityPolicyProfile* findSecurityPolicyProfile(std::string_view uri);
/// By URI or short name ("Basic256Sha256"), for command lines.
[[nodiscard]] const SecurityPolicyProfile* findSecurityPolicyProfileByName(std::string_view name);

}  // namespace skillcell::ua::crypto
