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
// and reuses it on every later start, unless it no longer names the application's URI.
#include <filesystem>
#include <string>
#include <vector>

#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::pki {

struct CertificateSubject {
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
    bool created = false;  // true when this call made it
};

/// Loads the certificate from `pkiDir`, or creates it (RSA 2048, SHA-256, self-signed,
/// with the extensions OPC 10000-6 asks for) when there is none or it names another
/// applicationUri. Files are written to a temporary name and renamed, so a crash never
/// leaves half a certificate. BadConfigurationError with `error` set on failure.
[[nodiscard]] Result<OwnCertificate> loadOrCreateOwnCertificate(const std::filesystem::path& pkiDir,
                                                                const CertificateSubject& subject,
                                                                std::string* error = nullptr);

/// The URI in a DER certificate's subjectAltName, or empty.
[[nodiscard]] std::string certificateApplicationUri(const ByteString& der);

/// The default PKI directory of an application: $SKILLCELL_PKI_DIR, else
/// ${XDG_DATA_HOME:-~/.local/share}/skillcell/pki/<applicationUri made a file name>.
[[nodiscard]] std::filesystem::path defaultPkiDirectory(const std::string& applicationUri);

}  // namespace skillcell::ua::pki
