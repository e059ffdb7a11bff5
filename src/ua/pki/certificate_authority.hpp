#pragma once
// The cell CA: one issuer that a cell's components share, so that they trust each other
// without an operator trusting each component's certificate on each other component
// (`skillcell pki init-ca`). Its directory:
//
//   <ca>/certs/ca.der          the CA certificate (self-signed, CA:TRUE, keyCertSign cRLSign)
//   <ca>/private/ca_key.pem    its private key (mode 0600, directory 0700)
//   <ca>/crl/ca.crl            its CRL (DER), empty at first; `revokeCertificate` adds to it
//
// A component whose PKI directory is given a CA (loadOrCreateOwnCertificate) gets its
// application instance certificate issued by it, and the CA certificate and CRL in its
// trusted/ lists.
#include <filesystem>
#include <optional>
#include <string>

#include "ua/pki/openssl_handles.hpp"
#include "ua/pki/own_certificate.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::pki {

struct CaOptions {
    std::string name = "skillcell cell CA";  // the CA's CN
    int keyBits = 2048;                      // 2048 or 4096
    int validDays = 7300;                    // twenty years: a cell outlives its certificates
};

/// A loaded CA: certificate and private key in memory.
struct CertificateAuthority {
    std::filesystem::path directory;
    ossl::Cert certificate;
    ossl::PKey key;
    [[nodiscard]] std::filesystem::path certificateFile() const {
        return directory / "certs/ca.der";
    }
    [[nodiscard]] std::filesystem::path keyFile() const { return directory / "private/ca_key.pem"; }
    [[nodiscard]] std::filesystem::path crlFile() const { return directory / "crl/ca.crl"; }
};

/// A certificate the CA issued, with its new key.
struct IssuedCertificate {
    ByteString der;
    std::string privateKeyPem;
};

/// Creates a CA in `dir` (made if missing). Refuses (BadConfigurationError) when `dir`
/// already holds one, so that a typo cannot replace a cell's CA.
[[nodiscard]] Result<CertificateAuthority> createCertificateAuthority(
    const std::filesystem::path& dir, const CaOptions& options, std::string* error = nullptr);

/// Loads the CA of `dir`; BadConfigurationError with `error` set when it is not one.
[[nodiscard]] Result<CertificateAuthority> loadCertificateAuthority(
    const std::filesystem::path& dir, std::string* error = nullptr);

/// The CA of `dir` without its private key (`key` empty): enough to tell what it issued
/// (issuedBy) and to install it as trusted, not to issue. A component starting with a
/// certificate the CA issued reads no more than this.
[[nodiscard]] Result<CertificateAuthority> loadCaCertificate(const std::filesystem::path& dir,
                                                             std::string* error = nullptr);

/// The cell CA a PKI directory points at (cellCaDirectory), as loadCaCertificate reads it;
/// nothing when it points at none. BadConfigurationError with `error` ("cell CA DIR: why")
/// when the CA it points at cannot be read: a component then fails rather than silently
/// going self-signed.
[[nodiscard]] Result<std::optional<CertificateAuthority>> loadCellCaCertificate(
    const std::filesystem::path& pkiDir, std::string* error = nullptr);

/// Issues an application instance certificate (new RSA 2048 key, SHA-256, the extensions of
/// OPC 10000-6 6.2.2, CA:FALSE) for `subject`, valid for subject.validDays but never
/// beyond the CA's own end.
[[nodiscard]] Result<IssuedCertificate> issueCertificate(const CertificateAuthority& ca,
                                                         const CertificateSubject& subject,
                                                         std::string* error = nullptr);

/// A self-signed application instance certificate (what a component without CA uses).
[[nodiscard]] Result<IssuedCertificate> createSelfSignedCertificate(
    const CertificateSubject& subject, std::string* error = nullptr);

/// Adds `certificate` (issued by `ca`) to the CA's CRL and re-signs it.
[[nodiscard]] StatusCode revokeCertificate(const CertificateAuthority& ca,
                                           const ByteString& certificate,
                                           std::string* error = nullptr);

/// Puts the CA certificate into `pkiDir`/trusted/certs/<ca name>_<thumbprint>.der and its
/// CRL into trusted/crl/ (replacing an older copy of that CRL), atomically.
[[nodiscard]] StatusCode installCertificateAuthority(const CertificateAuthority& ca,
                                                     const std::filesystem::path& pkiDir,
                                                     std::string* error = nullptr);

/// True when `certificate` was issued (and signed) by `ca`.
[[nodiscard]] bool issuedBy(const ByteString& certificate, const CertificateAuthority& ca);
/// The same for a certificate parsed already.
[[nodiscard]] bool issuedBy(X509* certificate, const CertificateAuthority& ca);

}  // namespace skillcell::ua::pki
