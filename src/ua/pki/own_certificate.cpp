#include "ua/pki/own_certificate.hpp"

#include <openssl/bio.h>
#include <openssl/bn.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/rsa.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>

namespace skillcell::ua::pki {

namespace {

namespace fs = std::filesystem;

template <class T, void (*Free)(T*)>
struct Deleter {
    void operator()(T* p) const { Free(p); }
};
using PKey = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Cert = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Ext = std::unique_ptr<X509_EXTENSION, Deleter<X509_EXTENSION, X509_EXTENSION_free>>;
using Bn = std::unique_ptr<BIGNUM, Deleter<BIGNUM, BN_free>>;
using Names = std::unique_ptr<GENERAL_NAMES, Deleter<GENERAL_NAMES, GENERAL_NAMES_free>>;

std::string opensslError(const std::string& what) {
    const unsigned long e = ERR_get_error();
    char buf[256] = {};
    if (e != 0) ERR_error_string_n(e, buf, sizeof buf);
    return what + (e != 0 ? std::string(": ") + buf : std::string());
}

Result<OwnCertificate> fail(std::string* error, std::string why) {
    if (error != nullptr) *error = std::move(why);
    return status::BadConfigurationError;
}

std::vector<std::uint8_t> readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Writes `bytes` to `path` through a temporary file and a rename: all or nothing.
bool writeAtomically(const fs::path& path, const std::string& bytes, mode_t mode) {
    const fs::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return false;
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.flush();
        if (!out) return false;
    }
    if (::chmod(tmp.c_str(), mode) != 0) return false;
    std::error_code ec;
    fs::rename(tmp, path, ec);
    return !ec;
}

bool addExtension(X509* cert, int nid, const std::string& value) {
    X509V3_CTX ctx;
    X509V3_set_ctx_nodb(&ctx);
    X509V3_set_ctx(&ctx, cert, cert, nullptr, nullptr, 0);
    const Ext ext(X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str()));
    return ext && X509_add_ext(cert, ext.get(), -1) == 1;
}

Result<OwnCertificate> create(const fs::path& certFile, const fs::path& keyFile,
                              const CertificateSubject& subject, std::string* error) {
    PKey key(EVP_RSA_gen(2048));
    if (!key) return fail(error, opensslError("RSA key generation"));
    Cert cert(X509_new());
    if (!cert) return fail(error, opensslError("X509_new"));
    X509_set_version(cert.get(), 2);  // v3
    Bn serial(BN_new());
    if (!serial || BN_rand(serial.get(), 128, BN_RAND_TOP_ANY, BN_RAND_BOTTOM_ANY) != 1 ||
        BN_to_ASN1_INTEGER(serial.get(), X509_get_serialNumber(cert.get())) == nullptr) {
        return fail(error, opensslError("serial number"));
    }
    // A day's slack before now: peers' clocks differ.
    X509_gmtime_adj(X509_getm_notBefore(cert.get()), -86400);
    X509_gmtime_adj(X509_getm_notAfter(cert.get()), 86400L * subject.validDays);
    X509_NAME* name = X509_get_subject_name(cert.get());
    const std::string cn = subject.commonName.substr(0, 64);
    X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_UTF8,
                               reinterpret_cast<const unsigned char*>(cn.c_str()), -1, -1, 0);
    X509_NAME_add_entry_by_txt(name, "O", MBSTRING_UTF8,
                               reinterpret_cast<const unsigned char*>("skillcell"), -1, -1, 0);
    X509_set_issuer_name(cert.get(), name);  // self-signed
    X509_set_pubkey(cert.get(), key.get());

    std::string san = "URI:" + subject.applicationUri;
    for (const auto& d : subject.dnsNames) san += ",DNS:" + d;
    for (const auto& ip : subject.ipAddresses) san += ",IP:" + ip;
    // OPC 10000-6, 6.2.2: the extensions of an application instance certificate; a
    // self-signed one also signs itself (keyCertSign).
    const bool ok =
        addExtension(cert.get(), NID_basic_constraints, "critical,CA:FALSE") &&
        addExtension(cert.get(), NID_key_usage,
                     "critical,digitalSignature,nonRepudiation,keyEncipherment,dataEncipherment,"
                     "keyCertSign") &&
        addExtension(cert.get(), NID_ext_key_usage, "serverAuth,clientAuth") &&
        addExtension(cert.get(), NID_subject_key_identifier, "hash") &&
        addExtension(cert.get(), NID_authority_key_identifier, "keyid:always") &&
        addExtension(cert.get(), NID_subject_alt_name, san);
    if (!ok) return fail(error, opensslError("certificate extensions (" + san + ")"));
    if (X509_sign(cert.get(), key.get(), EVP_sha256()) == 0) {
        return fail(error, opensslError("signing the certificate"));
    }

    unsigned char* derBuf = nullptr;
    const int derLen = i2d_X509(cert.get(), &derBuf);
    if (derLen <= 0) return fail(error, opensslError("encoding the certificate"));
    std::string der(reinterpret_cast<char*>(derBuf), static_cast<std::size_t>(derLen));
    OPENSSL_free(derBuf);

    const std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>> bio(BIO_new(BIO_s_mem()));
    if (!bio || PEM_write_bio_PrivateKey(bio.get(), key.get(), nullptr, nullptr, 0, nullptr,
                                         nullptr) != 1) {
        return fail(error, opensslError("encoding the private key"));
    }
    char* pem = nullptr;
    const long pemLen = BIO_get_mem_data(bio.get(), &pem);
    const std::string keyPem(pem, static_cast<std::size_t>(pemLen));

    // The key first: a certificate on disk always has its key.
    if (!writeAtomically(keyFile, keyPem, 0600) || !writeAtomically(certFile, der, 0644)) {
        return fail(error, "cannot write " + keyFile.string() + " / " + certFile.string());
    }
    OwnCertificate out;
    out.der = ByteString(std::vector<std::uint8_t>(der.begin(), der.end()));
    out.certificateFile = certFile;
    out.privateKeyFile = keyFile;
    out.created = true;
    return out;
}

}  // namespace

std::string certificateApplicationUri(const ByteString& der) {
    const unsigned char* p = der.bytes.data();
    const Cert cert(d2i_X509(nullptr, &p, static_cast<long>(der.bytes.size())));
    if (!cert) return {};
    const Names names(static_cast<GENERAL_NAMES*>(
        X509_get_ext_d2i(cert.get(), NID_subject_alt_name, nullptr, nullptr)));
    if (!names) return {};
    for (int i = 0; i < sk_GENERAL_NAME_num(names.get()); ++i) {
        const GENERAL_NAME* n = sk_GENERAL_NAME_value(names.get(), i);
        if (n->type == GEN_URI) {
            const ASN1_IA5STRING* uri = n->d.uniformResourceIdentifier;
            return {reinterpret_cast<const char*>(ASN1_STRING_get0_data(uri)),
                    static_cast<std::size_t>(ASN1_STRING_length(uri))};
        }
    }
    return {};
}

Result<OwnCertificate> loadOrCreateOwnCertificate(const fs::path& pkiDir,
                                                  const CertificateSubject& subject,
                                                  std::string* error) {
    std::error_code ec;
    // The layout every OPC UA PKI uses; trusted/ rejected/ issuers/ serve the secure
    // channels to come.
    for (const char* sub : {"own/certs", "own/private", "trusted/certs", "trusted/crl",
                            "rejected/certs", "issuers/certs", "issuers/crl"}) {
        fs::create_directories(pkiDir / sub, ec);
        if (ec)
            return fail(error, "cannot create " + (pkiDir / sub).string() + ": " + ec.message());
    }
    ::chmod((pkiDir / "own/private").c_str(), 0700);
    const fs::path certFile = pkiDir / "own/certs/cert.der";
    const fs::path keyFile = pkiDir / "own/private/key.pem";
    if (fs::exists(certFile, ec) && fs::exists(keyFile, ec)) {
        ByteString der(readFile(certFile));
        if (certificateApplicationUri(der) == subject.applicationUri) {
            OwnCertificate out;
            out.der = std::move(der);
            out.certificateFile = certFile;
            out.privateKeyFile = keyFile;
            return out;
        }
        // Another application's certificate (or a damaged file): make a new one.
    }
    return create(certFile, keyFile, subject, error);
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
