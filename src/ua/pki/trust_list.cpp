#include "ua/pki/trust_list.hpp"

#include <openssl/pem.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <chrono>

#include "ua/pki/file_util.hpp"

namespace skillcell::ua::pki {

namespace fs = std::filesystem;

namespace {

bool hasExtension(const fs::path& p, std::initializer_list<const char*> exts) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return std::any_of(exts.begin(), exts.end(), [&](const char* e) { return ext == e; });
}

bool isCertificateFile(const fs::path& p) {
    return hasExtension(p, {".der", ".cer", ".crt", ".pem"});
}
bool isCrlFile(const fs::path& p) {
    return hasExtension(p, {".crl", ".der", ".pem"});
}

std::vector<fs::path> regularFiles(const fs::path& dir) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->is_regular_file(ec)) out.push_back(it->path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

bool startsWithPem(const std::vector<std::uint8_t>& bytes) {
    static constexpr std::string_view kPem = "-----BEGIN";
    const std::string_view head(reinterpret_cast<const char*>(bytes.data()),
                                std::min(bytes.size(), std::size_t{64}));
    return head.find(kPem) != std::string_view::npos;
}

std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

}  // namespace

StatusCode createPkiLayout(const fs::path& root, std::string* error) {
    const PkiPaths p{root};
    for (const fs::path& dir : {p.ownCerts(), p.ownPrivate(), p.trustedCerts(), p.trustedCrl(),
                                p.issuersCerts(), p.issuersCrl(), p.rejectedCerts()}) {
        std::error_code ec;
        fs::create_directories(dir, ec);
        if (ec) {
            setError(error, "cannot create " + dir.string() + ": " + ec.message());
            return status::BadConfigurationError;
        }
    }
    ::chmod(p.ownPrivate().c_str(), 0700);
    return status::Good;
}

std::vector<ossl::Cert> readCertificateFile(const fs::path& file) {
    std::vector<ossl::Cert> out;
    const std::vector<std::uint8_t> bytes = readWholeFile(file);
    if (bytes.empty()) return out;
    if (!startsWithPem(bytes)) {
        auto cert = parseCertificate(ByteString(bytes));
        if (cert) out.push_back(std::move(*cert));
        return out;
    }
    const ossl::Bio bio(BIO_new_mem_buf(bytes.data(), static_cast<int>(bytes.size())));
    while (bio) {
        ossl::Cert cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
        if (!cert) break;
        out.push_back(std::move(cert));
    }
    return out;
}

std::vector<ossl::Crl> readCrlFile(const fs::path& file) {
    std::vector<ossl::Crl> out;
    const std::vector<std::uint8_t> bytes = readWholeFile(file);
    if (bytes.empty()) return out;
    if (!startsWithPem(bytes)) {
        const unsigned char* p = bytes.data();
        ossl::Crl crl(d2i_X509_CRL(nullptr, &p, static_cast<long>(bytes.size())));
        if (crl) out.push_back(std::move(crl));
        return out;
    }
    const ossl::Bio bio(BIO_new_mem_buf(bytes.data(), static_cast<int>(bytes.size())));
    while (bio) {
        ossl::Crl crl(PEM_read_bio_X509_CRL(bio.get(), nullptr, nullptr, nullptr));
        if (!crl) break;
        out.push_back(std::move(crl));
    }
    return out;
}

std::vector<StoredCertificate> listCertificates(const fs::path& dir) {
    std::vector<StoredCertificate> out;
    for (const fs::path& file : regularFiles(dir)) {
        if (!isCertificateFile(file)) continue;
        auto certs = readCertificateFile(file);
        if (certs.empty()) {
            out.push_back({file, {}, std::nullopt});
            continue;
        }
        for (auto& cert : certs) {
            out.push_back({file, certificateDer(cert.get()), inspectCertificate(cert.get())});
        }
    }
    return out;
}

Result<fs::path> findCertificate(const fs::path& dir, std::string_view thumbprintOrName,
                                 std::string* error) {
    const std::string wanted = lower(thumbprintOrName);
    std::vector<fs::path> matches;
    for (const auto& stored : listCertificates(dir)) {
        const bool byName = stored.file.filename().string() == thumbprintOrName;
        const bool byThumbprint = stored.info && wanted.size() >= 8 &&
                                  stored.info->thumbprint.compare(0, wanted.size(), wanted) == 0;
        if ((byName || byThumbprint) &&
            std::find(matches.begin(), matches.end(), stored.file) == matches.end()) {
            matches.push_back(stored.file);
        }
    }
    if (matches.empty()) {
        setError(error, "no certificate " + std::string(thumbprintOrName) + " in " + dir.string() +
                            " (a file name, or at least 8 hex digits of the thumbprint)");
        return status::BadNotFound;
    }
    if (matches.size() > 1) {
        std::string list;
        for (const auto& m : matches) list += " " + m.filename().string();
        setError(error, std::string(thumbprintOrName) + " matches several files:" + list);
        return status::BadInvalidArgument;
    }
    return matches.front();
}

Result<fs::path> moveCertificateFile(const fs::path& file, const fs::path& toDir,
                                     std::string* error) {
    std::error_code ec;
    fs::create_directories(toDir, ec);
    const fs::path target = toDir / file.filename();
    if (fs::exists(target, ec)) {
        setError(error, target.string() + " exists already");
        return status::BadConfigurationError;
    }
    // A rename within one file system is atomic: the validator sees the file in one place.
    fs::rename(file, target, ec);
    if (ec) {
        setError(error,
                 "cannot move " + file.string() + " to " + toDir.string() + ": " + ec.message());
        return status::BadConfigurationError;
    }
    return target;
}

Result<fs::path> storeRejectedCertificate(const fs::path& dir, const ByteString& leafDer,
                                          std::size_t maxFiles) {
    const std::string thumbprint = certificateThumbprintHex(leafDer);
    if (thumbprint.empty()) return status::BadCertificateInvalid;
    std::error_code ec;
    fs::create_directories(dir, ec);
    const fs::path file = dir / (thumbprint + ".der");
    if (fs::exists(file, ec)) {
        // Known already: touch it, so that the bound drops others first.
        fs::last_write_time(file, fs::file_time_type::clock::now(), ec);
    } else {
        const std::string_view bytes(reinterpret_cast<const char*>(leafDer.bytes.data()),
                                     leafDer.bytes.size());
        if (!writeFileAtomically(file, bytes, 0644)) return status::BadConfigurationError;
    }
    std::vector<std::pair<fs::file_time_type, fs::path>> files;
    for (const fs::path& f : regularFiles(dir)) {
        if (hasExtension(f, {".der"})) files.emplace_back(fs::last_write_time(f, ec), f);
    }
    if (files.size() > maxFiles) {
        std::sort(files.begin(), files.end());
        for (std::size_t i = 0; i + maxFiles < files.size(); ++i) {
            if (files[i].second != file) fs::remove(files[i].second, ec);
        }
    }
    return file;
}

TrustList::TrustList(fs::path pkiDir) : paths_{std::move(pkiDir)} {}

std::string TrustList::scanState() const {
    std::string state;
    for (const fs::path& dir :
         {paths_.trustedCerts(), paths_.trustedCrl(), paths_.issuersCerts(), paths_.issuersCrl()}) {
        for (const fs::path& f : regularFiles(dir)) {
            struct stat st {};
            if (::stat(f.c_str(), &st) != 0) continue;
            state += f.string() + '\n' + std::to_string(st.st_size) + ' ' +
                     std::to_string(st.st_mtim.tv_sec) + '.' + std::to_string(st.st_mtim.tv_nsec) +
                     ' ' + std::to_string(st.st_ino) + '\n';
        }
    }
    return state;
}

bool TrustList::refresh() {
    std::string state = scanState();
    if (loaded_ && state == state_) return false;
    trusted_.clear();
    issuers_.clear();
    crls_.clear();
    trustedThumbprints_.clear();
    for (const fs::path& f : regularFiles(paths_.trustedCerts())) {
        if (!isCertificateFile(f)) continue;
        for (auto& cert : readCertificateFile(f)) {
            trustedThumbprints_.insert(certificateThumbprintHex(cert.get()));
            trusted_.push_back(std::move(cert));
        }
    }
    for (const fs::path& f : regularFiles(paths_.issuersCerts())) {
        if (!isCertificateFile(f)) continue;
        for (auto& cert : readCertificateFile(f)) issuers_.push_back(std::move(cert));
    }
    for (const fs::path& dir : {paths_.trustedCrl(), paths_.issuersCrl()}) {
        for (const fs::path& f : regularFiles(dir)) {
            if (!isCrlFile(f)) continue;
            for (auto& crl : readCrlFile(f)) crls_.push_back(std::move(crl));
        }
    }
    state_ = std::move(state);
    loaded_ = true;
    return true;
}

bool TrustList::isTrusted(const std::string& thumbprintHex) const {
    return trustedThumbprints_.count(thumbprintHex) != 0;
}

}  // namespace skillcell::ua::pki
