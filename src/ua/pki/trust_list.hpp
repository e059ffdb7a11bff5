#pragma once
// The PKI directory (the layout every OPC UA stack uses, OPC 10000-12 F.1):
//
//   own/certs, own/private     this application's certificate and key (own_certificate.hpp)
//   trusted/certs, trusted/crl  peers and CAs trusted directly, and their CRLs
//   issuers/certs, issuers/crl  CAs used only to complete chains, and their CRLs
//   rejected/certs              peers refused as untrusted, for an operator to trust by moving
//
// Certificates are DER (*.der, *.cer, *.crt) or PEM (*.pem); CRLs DER or PEM (*.crl, *.der,
// *.pem). TrustList is a snapshot of trusted/ and issuers/ that reloads itself when a file
// there is added, removed or replaced, so trusting a peer needs no restart.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "ua/pki/certificate.hpp"
#include "ua/pki/openssl_handles.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua::pki {

/// The directories of one PKI directory.
struct PkiPaths {
    std::filesystem::path root;
    [[nodiscard]] std::filesystem::path ownCerts() const { return root / "own/certs"; }
    [[nodiscard]] std::filesystem::path ownPrivate() const { return root / "own/private"; }
    [[nodiscard]] std::filesystem::path trustedCerts() const { return root / "trusted/certs"; }
    [[nodiscard]] std::filesystem::path trustedCrl() const { return root / "trusted/crl"; }
    [[nodiscard]] std::filesystem::path issuersCerts() const { return root / "issuers/certs"; }
    [[nodiscard]] std::filesystem::path issuersCrl() const { return root / "issuers/crl"; }
    [[nodiscard]] std::filesystem::path rejectedCerts() const { return root / "rejected/certs"; }
};

/// Creates the directories of the layout (own/private mode 0700). BadConfigurationError
/// with `error` set when one cannot be created.
[[nodiscard]] StatusCode createPkiLayout(const std::filesystem::path& root,
                                         std::string* error = nullptr);

/// Every certificate in one file: one DER certificate, or any number of PEM ones.
[[nodiscard]] std::vector<ossl::Cert> readCertificateFile(const std::filesystem::path& file);
/// Every CRL in one file (DER or PEM).
[[nodiscard]] std::vector<ossl::Crl> readCrlFile(const std::filesystem::path& file);

/// One certificate file of a directory, as `skillcell pki list` shows it.
struct StoredCertificate {
    std::filesystem::path file;
    ByteString der;                       // empty when the file holds no certificate
    std::optional<CertificateInfo> info;  // nullopt when the file holds no certificate
};

/// The certificate files of `dir` (not recursive), sorted by file name; a PEM file with
/// several certificates gives several entries. A missing directory gives none.
[[nodiscard]] std::vector<StoredCertificate> listCertificates(const std::filesystem::path& dir);

/// Finds the certificate in `dir` whose thumbprint starts with `thumbprintPrefix`
/// (case-insensitive, at least 8 hex digits) or whose file name is exactly it.
/// BadNotFound when none, BadInvalidArgument when several match (error says which).
[[nodiscard]] Result<std::filesystem::path> findCertificate(const std::filesystem::path& dir,
                                                            std::string_view thumbprintOrName,
                                                            std::string* error = nullptr);

/// Moves `file` into `toDir` (created if missing) under the same name, by rename.
/// BadConfigurationError when that fails, or when `toDir` already has such a file.
[[nodiscard]] Result<std::filesystem::path> moveCertificateFile(const std::filesystem::path& file,
                                                                const std::filesystem::path& toDir,
                                                                std::string* error = nullptr);

/// Stores a rejected certificate as `dir`/<thumbprint>.der (atomic write; an existing copy is
/// kept), then deletes the oldest *.der files beyond `maxFiles`, so that a peer retrying
/// with new certificates cannot fill the disk. The stored file's path, or a Bad status.
[[nodiscard]] Result<std::filesystem::path> storeRejectedCertificate(
    const std::filesystem::path& dir, const ByteString& leafDer, std::size_t maxFiles);

/// trusted/ and issuers/ of one PKI directory, loaded into memory. Not thread-safe: one
/// validator owns it (one io_context thread per process).
class TrustList {
public:
    explicit TrustList(std::filesystem::path pkiDir);

    /// Reloads the lists when a file of the four directories was added, removed, resized or
    /// touched since the last load (one readdir + stat per file: cheap next to an RSA
    /// handshake). True when it reloaded.
    bool refresh();

    [[nodiscard]] const PkiPaths& paths() const { return paths_; }
    [[nodiscard]] const std::vector<ossl::Cert>& trusted() const { return trusted_; }
    [[nodiscard]] const std::vector<ossl::Cert>& issuers() const { return issuers_; }
    /// The CRLs of trusted/crl and issuers/crl.
    [[nodiscard]] const std::vector<ossl::Crl>& crls() const { return crls_; }
    /// True when this exact certificate (by thumbprint) is in trusted/certs.
    [[nodiscard]] bool isTrusted(const std::string& thumbprintHex) const;

private:
    [[nodiscard]] std::string scanState() const;

    PkiPaths paths_;
    std::string state_;  // names, sizes and mtimes of the files last loaded
    bool loaded_ = false;
    std::vector<ossl::Cert> trusted_;
    std::vector<ossl::Cert> issuers_;
    std::vector<ossl::Crl> crls_;
    std::unordered_set<std::string> trustedThumbprints_;
};

}  // namespace skillcell::ua::pki
