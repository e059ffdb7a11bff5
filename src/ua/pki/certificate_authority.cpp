#include "ua/pki/certificate_authority.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/rsa.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <ctime>

#include "ua/pki/certificate.hpp"
#include "ua/pki/file_util.hpp"
#include "ua/pki/trust_list.hpp"

namespace skillcell::ua::pki {

namespace fs = std::filesystem;

namespace {

constexpr long kDay = 86400;

std::string opensslError(const std::string& what) {
    const unsigned long e = ERR_get_error();
    ERR_clear_error();
    if (e == 0) return what;
    char buf[256] = {};
    ERR_error_string_n(e, buf, sizeof buf);
    return what + ": " + buf;
}

bool addExtension(X509* cert, X509* issuer, int nid, const std::string& value) {
    X509V3_CTX ctx;
    X509V3_set_ctx_nodb(&ctx);
    X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
    const ossl::Ext ext(X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str()));
    return ext && X509_add_ext(cert, ext.get(), -1) == 1;
}

bool setRandomSerial(X509* cert) {
    const ossl::Bn serial(BN_new());
    // 127 bits keeps the DER INTEGER positive and within the 20 octets RFC 5280 allows.
    return serial && BN_rand(serial.get(), 127, BN_RAND_TOP_ANY, BN_RAND_BOTTOM_ANY) == 1 &&
           BN_to_ASN1_INTEGER(serial.get(), X509_get_serialNumber(cert)) != nullptr;
}

void addNameEntry(X509_NAME* name, const char* field, const std::string& value) {
    X509_NAME_add_entry_by_txt(name, field, MBSTRING_UTF8,
                               reinterpret_cast<const unsigned char*>(value.c_str()), -1, -1, 0);
}

std::string keyToPem(EVP_PKEY* key) {
    const ossl::Bio bio(BIO_new(BIO_s_mem()));
    if (!bio ||
        PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1) {
        return {};
    }
    char* pem = nullptr;
    const long len = BIO_get_mem_data(bio.get(), &pem);
    return {pem, static_cast<std::size_t>(len)};
}

std::string_view asBytes(const ByteString& b) {
    return {reinterpret_cast<const char*>(b.bytes.data()), b.bytes.size()};
}

/// A new certificate with serial, validity, subject; issuer and signature left to the caller.
ossl::Cert newCertificate(EVP_PKEY* key, const std::string& commonName, long validDays) {
    ossl::Cert cert(X509_new());
    if (!cert || X509_set_version(cert.get(), 2) != 1 || !setRandomSerial(cert.get())) return {};
    // A day's slack before now: peers' clocks differ.
    X509_gmtime_adj(X509_getm_notBefore(cert.get()), -kDay);
    X509_gmtime_adj(X509_getm_notAfter(cert.get()), kDay * validDays);
    X509_NAME* name = X509_get_subject_name(cert.get());
    addNameEntry(name, "CN", commonName.substr(0, 64));
    addNameEntry(name, "O", "skillcell");
    X509_set_pubkey(cert.get(), key);
    return cert;
}

ByteString der(X509* cert) {
    return certificateDer(cert);
}

/// The application instance certificate for `subject`, signed by `issuer` and `issuerKey`,
/// or self-signed when they are null.
Result<IssuedCertificate> buildApplicationCertificate(const CertificateSubject& subject,
                                                      X509* issuer, EVP_PKEY* issuerKey,
                                                      std::string* error) {
    const bool ecc = subject.key == CertificateKey::EccNistP256;
    const ossl::PKey key(ecc ? EVP_EC_gen("P-256") : EVP_RSA_gen(2048));
    if (!key) {
        setError(error, opensslError(ecc ? "P-256 key generation" : "RSA key generation"));
        return status::BadConfigurationError;
    }
    ossl::Cert cert = newCertificate(key.get(), subject.commonName, subject.validDays);
    if (!cert) {
        setError(error, opensslError("creating the certificate"));
        return status::BadConfigurationError;
    }
    const bool selfSigned = issuer == nullptr;
    if (!selfSigned &&
        ASN1_TIME_compare(X509_get0_notAfter(issuer), X509_get0_notAfter(cert.get())) < 0) {
        X509_set1_notAfter(cert.get(), X509_get0_notAfter(issuer));  // not beyond the CA
    }
    X509_set_issuer_name(
        cert.get(), selfSigned ? X509_get_subject_name(cert.get()) : X509_get_subject_name(issuer));
    std::string san = "URI:" + subject.applicationUri;
    for (const auto& d : subject.dnsNames) san += ",DNS:" + d;
    for (const auto& ip : subject.ipAddresses) san += ",IP:" + ip;
    // OPC 10000-6, 6.2.2: the extensions of an application instance certificate; a
    // self-signed one also signs itself (keyCertSign).
    // An ECC key signs and agrees on keys; it encrypts nothing.
    const std::string usage =
        std::string(ecc ? "critical,digitalSignature,nonRepudiation,keyAgreement"
                        : "critical,digitalSignature,nonRepudiation,keyEncipherment,"
                          "dataEncipherment") +
        (selfSigned ? ",keyCertSign" : "");
    X509* signer = selfSigned ? cert.get() : issuer;
    const bool ok =
        addExtension(cert.get(), signer, NID_basic_constraints, "critical,CA:FALSE") &&
        addExtension(cert.get(), signer, NID_key_usage, usage) &&
        addExtension(cert.get(), signer, NID_ext_key_usage, "serverAuth,clientAuth") &&
        addExtension(cert.get(), signer, NID_subject_key_identifier, "hash") &&
        addExtension(cert.get(), signer, NID_authority_key_identifier, "keyid:always") &&
        addExtension(cert.get(), signer, NID_subject_alt_name, san);
    if (!ok) {
        setError(error, opensslError("certificate extensions (" + san + ")"));
        return status::BadConfigurationError;
    }
    if (X509_sign(cert.get(), selfSigned ? key.get() : issuerKey, EVP_sha256()) == 0) {
        setError(error, opensslError("signing the certificate"));
        return status::BadConfigurationError;
    }
    IssuedCertificate out;
    out.der = der(cert.get());
    out.privateKeyPem = keyToPem(key.get());
    if (out.der.empty() || out.privateKeyPem.empty()) {
        setError(error, opensslError("encoding the certificate or key"));
        return status::BadConfigurationError;
    }
    return out;
}

/// Builds and signs the CA's CRL listing `revoked` (copied), numbered `number`.
ossl::Crl buildCrl(const CertificateAuthority& ca, const STACK_OF(X509_REVOKED) * revoked,
                   long number) {
    ossl::Crl crl(X509_CRL_new());
    if (!crl || X509_CRL_set_version(crl.get(), 1) != 1 ||
        X509_CRL_set_issuer_name(crl.get(), X509_get_subject_name(ca.certificate.get())) != 1) {
        return {};
    }
    const ossl::Time last(X509_gmtime_adj(nullptr, -3600));
    // nextUpdate = the CA's end: the CRL travels by file copy, not from a distribution
    // point, so a short period would only make every component fail when it lapses.
    if (!last || X509_CRL_set1_lastUpdate(crl.get(), last.get()) != 1 ||
        X509_CRL_set1_nextUpdate(crl.get(), X509_get0_notAfter(ca.certificate.get())) != 1) {
        return {};
    }
    for (int i = 0; revoked != nullptr && i < sk_X509_REVOKED_num(revoked); ++i) {
        const X509_REVOKED* r = sk_X509_REVOKED_value(revoked, i);
        ossl::Revoked copy(X509_REVOKED_new());
        // The setters copy their argument; OpenSSL's signatures just lack the const.
        auto* serial = const_cast<ASN1_INTEGER*>(X509_REVOKED_get0_serialNumber(r));
        auto* date = const_cast<ASN1_TIME*>(X509_REVOKED_get0_revocationDate(r));
        if (!copy || X509_REVOKED_set_serialNumber(copy.get(), serial) != 1 ||
            X509_REVOKED_set_revocationDate(copy.get(), date) != 1 ||
            X509_CRL_add0_revoked(crl.get(), copy.get()) != 1) {
            return {};
        }
        copy.release();  // NOLINT(bugprone-unused-return-value): the CRL owns it now
    }
    const ossl::Integer crlNumber(ASN1_INTEGER_new());
    X509V3_CTX ctx;
    X509V3_set_ctx_nodb(&ctx);
    X509V3_set_ctx(&ctx, ca.certificate.get(), nullptr, nullptr, crl.get(), 0);
    const ossl::Ext aki(
        X509V3_EXT_conf_nid(nullptr, &ctx, NID_authority_key_identifier, "keyid:always"));
    if (!crlNumber || ASN1_INTEGER_set(crlNumber.get(), number) != 1 || !aki ||
        X509_CRL_add1_ext_i2d(crl.get(), NID_crl_number, crlNumber.get(), 0, 0) != 1 ||
        X509_CRL_add_ext(crl.get(), aki.get(), -1) != 1) {
        return {};
    }
    X509_CRL_sort(crl.get());
    if (X509_CRL_sign(crl.get(), ca.key.get(), EVP_sha256()) == 0) return {};
    return crl;
}

bool writeCrl(const fs::path& file, X509_CRL* crl) {
    unsigned char* buf = nullptr;
    const int len = i2d_X509_CRL(crl, &buf);
    if (len <= 0) return false;
    const std::string bytes(reinterpret_cast<char*>(buf), static_cast<std::size_t>(len));
    OPENSSL_free(buf);
    return writeFileAtomically(file, bytes, 0644);
}

}  // namespace

Result<CertificateAuthority> createCertificateAuthority(const fs::path& dir,
                                                        const CaOptions& options,
                                                        std::string* error) {
    if (options.keyBits != 2048 && options.keyBits != 3072 && options.keyBits != 4096) {
        setError(error, "key size must be 2048, 3072 or 4096 bits");
        return status::BadInvalidArgument;
    }
    CertificateAuthority ca;
    ca.directory = dir;
    std::error_code ec;
    if (fs::exists(ca.certificateFile(), ec) || fs::exists(ca.keyFile(), ec)) {
        setError(error, dir.string() + " holds a CA already (certs/ca.der); not replacing it");
        return status::BadConfigurationError;
    }
    for (const char* sub : {"certs", "private", "crl"}) {
        fs::create_directories(dir / sub, ec);
        if (ec) {
            setError(error, "cannot create " + (dir / sub).string() + ": " + ec.message());
            return status::BadConfigurationError;
        }
    }
    ::chmod((dir / "private").c_str(), 0700);

    ca.key.reset(EVP_RSA_gen(static_cast<unsigned>(options.keyBits)));
    if (!ca.key) {
        setError(error, opensslError("RSA key generation"));
        return status::BadConfigurationError;
    }
    ca.certificate = newCertificate(ca.key.get(), options.name, options.validDays);
    if (!ca.certificate) {
        setError(error, opensslError("creating the CA certificate"));
        return status::BadConfigurationError;
    }
    X509* cert = ca.certificate.get();
    X509_set_issuer_name(cert, X509_get_subject_name(cert));
    const bool ok = addExtension(cert, cert, NID_basic_constraints, "critical,CA:TRUE") &&
                    addExtension(cert, cert, NID_key_usage, "critical,keyCertSign,cRLSign") &&
                    addExtension(cert, cert, NID_subject_key_identifier, "hash") &&
                    addExtension(cert, cert, NID_authority_key_identifier, "keyid:always");
    if (!ok || X509_sign(cert, ca.key.get(), EVP_sha256()) == 0) {
        setError(error, opensslError("signing the CA certificate"));
        return status::BadConfigurationError;
    }
    const ossl::Crl crl = buildCrl(ca, nullptr, 1);
    if (!crl) {
        setError(error, opensslError("creating the CRL"));
        return status::BadConfigurationError;
    }
    // The key first: a certificate on disk always has its key.
    if (!writeFileAtomically(ca.keyFile(), keyToPem(ca.key.get()), 0600) ||
        !writeFileAtomically(ca.certificateFile(), asBytes(der(cert)), 0644) ||
        !writeCrl(ca.crlFile(), crl.get())) {
        setError(error, "cannot write the CA's files in " + dir.string());
        return status::BadConfigurationError;
    }
    return ca;
}

Result<CertificateAuthority> loadCaCertificate(const fs::path& dir, std::string* error) {
    CertificateAuthority ca;
    ca.directory = dir;
    auto certs = readCertificateFile(ca.certificateFile());
    if (certs.size() != 1) {
        setError(error, ca.certificateFile().string() + " is missing or not one certificate");
        return status::BadConfigurationError;
    }
    ca.certificate = std::move(certs.front());
    if (X509_check_ca(ca.certificate.get()) == 0) {
        setError(error, ca.certificateFile().string() + " is no CA certificate");
        return status::BadConfigurationError;
    }
    return ca;
}

Result<std::optional<CertificateAuthority>> loadCellCaCertificate(const fs::path& pkiDir,
                                                                  std::string* error) {
    const fs::path caDir = cellCaDirectory(pkiDir);
    if (caDir.empty()) return std::optional<CertificateAuthority>();
    std::string why;
    auto ca = loadCaCertificate(caDir, &why);
    if (!ca) {
        setError(error, "cell CA " + caDir.string() + ": " + why);
        return ca.status();
    }
    return std::optional<CertificateAuthority>(std::move(*ca));
}

Result<CertificateAuthority> loadCertificateAuthority(const fs::path& dir, std::string* error) {
    auto loaded = loadCaCertificate(dir, error);
    if (!loaded) return loaded.status();
    CertificateAuthority ca = std::move(*loaded);
    const std::vector<std::uint8_t> pem = readWholeFile(ca.keyFile());
    const ossl::Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
    if (!pem.empty() && bio) {
        ca.key.reset(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
    }
    if (!ca.key) {
        setError(error, opensslError("cannot read the CA key " + ca.keyFile().string()));
        return status::BadConfigurationError;
    }
    if (X509_check_private_key(ca.certificate.get(), ca.key.get()) != 1) {
        ERR_clear_error();
        setError(error, dir.string() + ": the key does not belong to the certificate");
        return status::BadConfigurationError;
    }
    return ca;
}

Result<IssuedCertificate> issueCertificate(const CertificateAuthority& ca,
                                           const CertificateSubject& subject, std::string* error) {
    return buildApplicationCertificate(subject, ca.certificate.get(), ca.key.get(), error);
}

Result<IssuedCertificate> createSelfSignedCertificate(const CertificateSubject& subject,
                                                      std::string* error) {
    return buildApplicationCertificate(subject, nullptr, nullptr, error);
}

StatusCode revokeCertificate(const CertificateAuthority& ca, const ByteString& certificate,
                             std::string* error) {
    auto cert = parseCertificate(certificate);
    if (!cert || !issuedBy(certificate, ca)) {
        setError(error, "the certificate is not one this CA issued");
        return status::BadCertificateInvalid;
    }
    auto existing = readCrlFile(ca.crlFile());
    const STACK_OF(X509_REVOKED)* old =
        existing.empty() ? nullptr : X509_CRL_get_REVOKED(existing.front().get());
    long number = 1;
    if (!existing.empty()) {
        int crit = 0;
        const ossl::Integer n(static_cast<ASN1_INTEGER*>(
            X509_CRL_get_ext_d2i(existing.front().get(), NID_crl_number, &crit, nullptr)));
        if (n) number = ASN1_INTEGER_get(n.get()) + 1;
    }
    // Copy the old entries, then add this one unless it is there already.
    ossl::Crl crl = buildCrl(ca, old, number);
    if (!crl) {
        setError(error, opensslError("building the CRL"));
        return status::BadConfigurationError;
    }
    X509_REVOKED* found = nullptr;
    if (X509_CRL_get0_by_serial(crl.get(), &found, X509_get0_serialNumber(cert->get())) == 0) {
        ossl::Revoked entry(X509_REVOKED_new());
        const ossl::Time now(X509_gmtime_adj(nullptr, 0));
        if (!entry || !now ||
            X509_REVOKED_set_serialNumber(
                entry.get(), const_cast<ASN1_INTEGER*>(X509_get0_serialNumber(cert->get()))) != 1 ||
            X509_REVOKED_set_revocationDate(entry.get(), now.get()) != 1 ||
            X509_CRL_add0_revoked(crl.get(), entry.get()) != 1) {
            setError(error, opensslError("adding the CRL entry"));
            return status::BadConfigurationError;
        }
        entry.release();  // NOLINT(bugprone-unused-return-value): the CRL owns it now
        X509_CRL_sort(crl.get());
        if (X509_CRL_sign(crl.get(), ca.key.get(), EVP_sha256()) == 0) {
            setError(error, opensslError("signing the CRL"));
            return status::BadConfigurationError;
        }
    }
    if (!writeCrl(ca.crlFile(), crl.get())) {
        setError(error, "cannot write " + ca.crlFile().string());
        return status::BadConfigurationError;
    }
    return status::Good;
}

StatusCode installCertificateAuthority(const CertificateAuthority& ca, const fs::path& pkiDir,
                                       std::string* error) {
    if (const StatusCode s = createPkiLayout(pkiDir, error); s.isBad()) return s;
    const PkiPaths paths{pkiDir};
    const ByteString caDer = der(ca.certificate.get());
    const std::string thumbprint = certificateThumbprintHex(caDer);
    char cn[64] = {};
    X509_NAME_get_text_by_NID(X509_get_subject_name(ca.certificate.get()), NID_commonName, cn,
                              sizeof cn);
    std::string name;
    for (const char c : std::string_view(cn)) {
        const bool keep = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-';
        name.push_back(keep ? c : '_');
    }
    // Named by thumbprint so that a second CA or a renewed one never overwrites the first.
    const fs::path certFile = paths.trustedCerts() / (name + "_" + thumbprint + ".der");
    const fs::path crlFile = paths.trustedCrl() / (thumbprint + ".crl");
    const std::vector<std::uint8_t> crl = readWholeFile(ca.crlFile());
    const bool ok = (readWholeFile(certFile) == caDer.bytes ||
                     writeFileAtomically(certFile, asBytes(caDer), 0644)) &&
                    (crl.empty() || readWholeFile(crlFile) == crl ||
                     writeFileAtomically(
                         crlFile, {reinterpret_cast<const char*>(crl.data()), crl.size()}, 0644));
    if (!ok) {
        setError(error, "cannot install the CA certificate and CRL in " + pkiDir.string());
        return status::BadConfigurationError;
    }
    return status::Good;
}

bool issuedBy(const ByteString& certificate, const CertificateAuthority& ca) {
    auto cert = parseCertificate(certificate);
    return cert && issuedBy(cert->get(), ca);
}

bool issuedBy(X509* certificate, const CertificateAuthority& ca) {
    // The CA certificate's public key: the CA's private key is not needed to check.
    const bool ok = X509_check_issued(ca.certificate.get(), certificate) == X509_V_OK &&
                    X509_verify(certificate, X509_get0_pubkey(ca.certificate.get())) == 1;
    ERR_clear_error();
    return ok;
}

}  // namespace skillcell::ua::pki
