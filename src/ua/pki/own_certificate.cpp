#include "ua/pki/own_certificate.hpp"

#include <openssl/x509.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <optional>

#include "ua/pki/certificate.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/pki/file_util.hpp"
#include "ua/pki/trust_list.hpp"

namespace skillcell::ua::pki {

namespace {

namespace fs = std::filesystem;

Result<OwnCertificate> fail(std::string* error, std::string why) {
    if (error != nullptr) *error = std::move(why);
    return status::BadConfigurationError;
}

/// True when `cert` is issued by `ca` and stays valid for at least another 30 days. Asked at
/// every start, of each of the component's certificates: its validity is compared as it is
/// encoded, without inspecting the whole certificate.
bool keepUnderCa(X509* cert, const CertificateAuthority& ca) {
    std::time_t limit = Clock::to_time_t(Clock::now() + std::chrono::hours(24 * 30));
    return X509_cmp_time(X509_get0_notAfter(cert), &limit) > 0 && issuedBy(cert, ca);
}

}  // namespace

std::string certificateApplicationUri(const ByteString& der) {
    // Asked at every start (is the certificate there still ours?) and for every secured
    // registration at an LDS: one parse, not a whole inspection.
    auto cert = parseCertificate(der);
    return cert ? applicationUriOf(cert->get()) : std::string();
}

fs::path cellCaDirectory(const fs::path& pkiDir) {
    if (const char* dir = std::getenv("SKILLCELL_CA_DIR"); dir != nullptr && *dir != '\0') {
        return dir;
    }
    std::error_code ec;
    const fs::path link = pkiDir / "cell-ca";
    return fs::is_directory(link, ec) ? link : fs::path();
}

Result<OwnCertificate> loadOrCreateOwnCertificate(const fs::path& pkiDir,
                                                  const CertificateSubject& subject,
                                                  std::string* error) {
    // The CA's key is read only when a certificate must be issued (below): a component that
    // starts with one the CA issued reads the CA certificate and CRL, not the key.
    auto ca = loadCellCaCertificate(pkiDir, error);
    if (!ca) return status::BadConfigurationError;
    return loadOrCreateOwnCertificate(pkiDir, subject, *ca ? &**ca : nullptr, error);
}

Result<OwnCertificate> loadOrCreateOwnCertificate(const fs::path& pkiDir,
                                                  const CertificateSubject& subject,
                                                  const CertificateAuthority* ca,
                                                  std::string* error) {
    // The layout every OPC UA PKI uses; see trust_list.hpp.
    if (createPkiLayout(pkiDir, error).isBad()) return status::BadConfigurationError;
    if (ca != nullptr && installCertificateAuthority(*ca, pkiDir, error).isBad()) {
        return status::BadConfigurationError;
    }
    const PkiPaths paths{pkiDir};
    OwnCertificate out;
    const bool ecc = subject.key == CertificateKey::EccNistP256;
    out.certificateFile = paths.ownCerts() / (ecc ? "cert-nistP256.der" : "cert.der");
    out.privateKeyFile = paths.ownPrivate() / (ecc ? "key-nistP256.pem" : "key.pem");
    if (ca != nullptr) out.issuer = ca->directory;
    std::error_code ec;
    if (fs::exists(out.certificateFile, ec) && fs::exists(out.privateKeyFile, ec)) {
        ByteString der(readWholeFile(out.certificateFile));
        // Parsed once for the URI, the validity and the issuer (130 us a parse).
        const auto cert = parseCertificate(der);
        if (cert && applicationUriOf(cert->get()) == subject.applicationUri &&
            (ca == nullptr || keepUnderCa(cert->get(), *ca))) {
            out.der = std::move(der);
            return out;
        }
        // Another application's certificate, a damaged file, or (with a CA) a self-signed
        // or expiring one: make a new one.
    }
    std::optional<CertificateAuthority> signer;  // the CA with its key, read to issue only
    if (ca != nullptr && !ca->key) {
        std::string why;
        auto full = loadCertificateAuthority(ca->directory, &why);
        if (!full) return fail(error, "cell CA " + ca->directory.string() + ": " + why);
        signer = std::move(*full);
        ca = &*signer;
    }
    auto made = ca != nullptr ? issueCertificate(*ca, subject, error)
                              : createSelfSignedCertificate(subject, error);
    if (!made) return made.status();
    const std::string_view derBytes(reinterpret_cast<const char*>(made->der.bytes.data()),
                                    made->der.bytes.size());
    // The key first: a certificate on disk always has its key.
    if (!writeFileAtomically(out.privateKeyFile, made->privateKeyPem, 0600) ||
        !writeFileAtomically(out.certificateFile, derBytes, 0644)) {
        return fail(error, "cannot write " + out.privateKeyFile.string() + " / " +
                               out.certificateFile.string());
    }
    out.der = std::move(made->der);
    out.created = true;
    return out;
}

fs::path defaultPkiDirectory(const std::string& applicationUri) {
    if (const char* dir = std::getenv("SKILLCELL_PKI_DIR"); dir != nullptr && *dir != '\0') {
        return dir;
    }
    fs::path base;
    if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg != nullptr && *xdg != '\0') {
        base = xdg;
    } else if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
        base = fs::path(home) / ".local/share";
    } else {
        base = fs::current_path();
    }
    std::string file;
    for (char c : applicationUri) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
        file.push_back(ok ? c : '_');
    }
    return base / "skillcell/pki" / (file.empty() ? std::string("default") : file);
}

}  // namespace skillcell::ua::pki
