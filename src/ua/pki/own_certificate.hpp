#pragma once
// The application instance certificate (OPC 10000-4, 6.1; OPC 10000-6, 6.2.2): every OPC UA
// application has one, even when it only offers SecurityPolicy None, and peers expect to find
// it in its EndpointDescriptions (node-opcua's servers will not register with an LDS whose
// endpoints carry none). A component creates its own on first start, self-signed, and keeps
// it in the "own" part of its PKI directory:
//
//   <pki>/own/certs/cert.der      the certificate (DER)
//   <pki>/own/private/key.pem     its RSA private key (PEM, mode 0600)
//
// and reuses it on every later start, unless it no longer names the application's URI. A
// second certificate with a NIST P-256 key, for the ECC_nistP256 policy, lives beside it as
// cert-nistP256.der and key-nistP256.pem.
//
// With a cell CA (certificate_authority.hpp) the certificate is issued by the CA instead,
// a self-signed one (or one of another CA) is replaced, and the CA's certificate and CRL are
// put into trusted/, so that the cell's components trust each other without manual steps.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::pki {

/// The key of an application instance certificate: RSA for the RSA policies (the one every
/// OPC UA application has), P-256 for ECC_nistP256.
enum class CertificateKey : std::uint8_t { Rsa2048, EccNistP256 };

struct CertificateSubject {
    CertificateKey key = CertificateKey::Rsa2048;
    std::string applicationUri;  // the subjectAltName URI, as OPC UA requires
    std::string commonName;
    std::vector<std::string> dnsNames;
    std::vector<std::string> ipAddresses;
    int validDays = 3650;
};

struct OwnCertificate {
    ByteString der;
    std::filesystem::path certificateFile;
    std::filesystem::path privateKeyFile;
    bool created = false;          // true when this call made it
    std::filesystem::path issuer;  // the cell CA's directory when the CA issued it, else empty
};

struct CertificateAuthority;  // certificate_authority.hpp

/// Loads the certificate from `pkiDir`, or creates it (RSA 2048 or P-256 as `subject.key`
/// says, SHA-256, self-signed,
/// with the extensions OPC 10000-6 asks for) when there is none or it names another
/// applicationUri. When cellCaDirectory(pkiDir) names a CA, the four-argument form below
/// runs with it (and fails when that CA cannot be loaded, rather than silently going
/// self-signed). Files are written to a temporary name and renamed, so a crash never
/// leaves half a certificate. BadConfigurationError with `error` set on failure.
[[nodiscard]] Result<OwnCertificate> loadOrCreateOwnCertificate(const std::filesystem::path& pkiDir,
                                                                const CertificateSubject& subject,
                                                                std::string* error = nullptr);

/// The same with an explicit issuer: `ca` null means self-signed as above (pass a typed
/// null: a bare nullptr would also match the `error` parameter of the form above). With a CA, an
/// existing certificate is kept only when it names `subject.applicationUri`, was issued by
/// `ca` and is valid for 30 more days; else a new key and certificate replace it. The CA
/// certificate and CRL are (re)installed in trusted/ on every call.
[[nodiscard]] Result<OwnCertificate> loadOrCreateOwnCertificate(const std::filesystem::path& pkiDir,
                                                                const CertificateSubject& subject,
                                                                const CertificateAuthority* ca,
                                                                std::string* error = nullptr);

/// The cell CA a PKI directory points at: $SKILLCELL_CA_DIR when set, else `pkiDir`/cell-ca
/// when it exists (a directory or a symbolic link to one made by `skillcell pki init-ca`);
/// empty when there is none. The three-argument loadOrCreateOwnCertificate uses it.
[[nodiscard]] std::filesystem::path cellCaDirectory(const std::filesystem::path& pkiDir);

/// The URI in a DER certificate's subjectAltName, or empty.
[[nodiscard]] std::string certificateApplicationUri(const ByteString& der);

/// The default PKI directory of an application: $SKILLCELL_PKI_DIR, else
/// ${XDG_DATA_HOME:-~/.local/share}/skillcell/pki/<applicationUri made a file name>.
[[nodiscard]] std::filesystem::path defaultPkiDirectory(const std::string& applicationUri);

}  // namespace skillcell::ua::pki
