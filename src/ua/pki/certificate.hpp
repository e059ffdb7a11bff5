#pragma once
// Reading X.509 certificates as OPC UA carries them: DER ByteStrings, where a chain is the
// leaf followed by its issuers, concatenated (OPC 10000-6, 6.2.3). Pure functions on bytes.
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ua/pki/openssl_handles.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::pki {

using Clock = std::chrono::system_clock;

/// What an operator (and `skillcell pki list`) wants to know about a certificate.
struct CertificateInfo {
    std::string subject;         // one line, e.g. "CN=gripper, O=skillcell"
    std::string issuer;          // same form
    std::string applicationUri;  // the subjectAltName URI, empty when there is none
    std::vector<std::string> dnsNames;
    std::vector<std::string> ipAddresses;
    std::string thumbprint;    // SHA-1 of the DER, lower-case hex (40 characters)
    std::string serialNumber;  // upper-case hex
    Clock::time_point notBefore;
    Clock::time_point notAfter;
    bool isCa = false;        // basicConstraints CA:TRUE
    bool selfSigned = false;  // issuer == subject and its own key verifies the signature
    int keyBits = 0;
    std::string keyType;  // "RSA", "EC P-256", or OpenSSL's name of another
};

/// One certificate of a chain: its DER bytes and the certificate they parse to.
struct ChainCertificate {
    ByteString der;
    ossl::Cert cert;
};

/// Parses a certificate ByteString into its certificates (leaf first), each once. Each must
/// parse and together they must use every byte; else BadCertificateInvalid. Empty input is
/// BadCertificateInvalid too.
[[nodiscard]] Result<std::vector<ChainCertificate>> parseCertificateChain(const ByteString& chain);

/// An ASN.1 time (a validity bound, a CRL's update times) as a time point; nothing when it
/// does not parse. Times past the clock's range (it ends in 2262; 9999-12-31 means "no
/// expiry") are the end of it.
[[nodiscard]] std::optional<Clock::time_point> timePointOf(const ASN1_TIME* time);

/// Parses the first certificate of `der` (a single certificate or a chain).
[[nodiscard]] Result<ossl::Cert> parseCertificate(const ByteString& der);

/// The DER encoding of a parsed certificate.
[[nodiscard]] ByteString certificateDer(X509* cert);

/// SHA-1 of the first certificate's DER bytes (20 bytes): the thumbprint the asymmetric
/// security header of OpenSecureChannel carries (OPC 10000-6, 6.7.2.3).
/// BadCertificateInvalid when `der` does not start with a certificate.
[[nodiscard]] Result<std::array<std::uint8_t, 20>> certificateThumbprint(const ByteString& der);

/// The thumbprint as lower-case hex, or "" when `der` is no certificate.
[[nodiscard]] std::string certificateThumbprintHex(const ByteString& der);
/// The same of a parsed certificate, without encoding and parsing it again (OpenSSL keeps
/// its SHA-1 once the certificate's extensions have been read).
[[nodiscard]] std::string certificateThumbprintHex(X509* cert);

/// The application URI of a parsed certificate: its first URI subject alternative name, or
/// "" when it has none. Reads nothing else (inspectCertificate also reads every extension, the
/// key, and checks a self-issued certificate's signature).
[[nodiscard]] std::string applicationUriOf(X509* cert);

/// Subject, issuer, URI, host names, validity, thumbprint of the first certificate.
[[nodiscard]] Result<CertificateInfo> inspectCertificate(const ByteString& der);
[[nodiscard]] CertificateInfo inspectCertificate(X509* cert);

/// The first certificate's public key, for signature checks and encryption.
[[nodiscard]] Result<ossl::PKey> certificatePublicKey(const ByteString& der);

/// The public key's size in bits (the security policies bound it), or BadCertificateInvalid.
[[nodiscard]] Result<int> certificateKeyBits(const ByteString& der);

}  // namespace skillcell::ua::pki
