#include "pki_test_support.hpp"

#include <openssl/rsa.h>
#include <stdlib.h>

#include <fstream>
#include <stdexcept>

namespace skillcell::ua::pki::test {

namespace {

void require(bool ok, const char* what) {
    if (!ok) throw std::runtime_error(std::string("test certificate: ") + what);
}

void addExt(X509* cert, X509* issuer, int nid, const std::string& value) {
    X509V3_CTX ctx;
    X509V3_set_ctx_nodb(&ctx);
    X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
    const ossl::Ext ext(X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str()));
    require(ext && X509_add_ext(cert, ext.get(), -1) == 1, value.c_str());
}

KeyAndCert build(const CertSpec& spec, const KeyAndCert* issuer) {
    KeyAndCert out;
    out.key.reset(EVP_RSA_gen(static_cast<unsigned>(spec.keyBits)));
    out.cert.reset(X509_new());
    require(out.key && out.cert, "allocation");
    X509* c = out.cert.get();
    X509_set_version(c, 2);
    const ossl::Bn serial(BN_new());
    require(serial && BN_rand(serial.get(), 64, BN_RAND_TOP_ANY, BN_RAND_BOTTOM_ANY) == 1 &&
                BN_to_ASN1_INTEGER(serial.get(), X509_get_serialNumber(c)) != nullptr,
            "serial");
    X509_gmtime_adj(X509_getm_notBefore(c), spec.notBeforeDays * 86400L);
    X509_gmtime_adj(X509_getm_notAfter(c), spec.notAfterDays * 86400L);
    X509_NAME_add_entry_by_txt(X509_get_subject_name(c), "CN", MBSTRING_UTF8,
                               reinterpret_cast<const unsigned char*>(spec.commonName.c_str()), -1,
                               -1, 0);
    X509_set_issuer_name(c, issuer != nullptr ? X509_get_subject_name(issuer->cert.get())
                                              : X509_get_subject_name(c));
    X509_set_pubkey(c, out.key.get());
    X509* signerCert = issuer != nullptr ? issuer->cert.get() : c;
    addExt(c, signerCert, NID_basic_constraints,
           spec.ca ? "critical,CA:TRUE" : "critical,CA:FALSE");
    addExt(c, signerCert, NID_key_usage, spec.keyUsage);
    addExt(c, signerCert, NID_subject_key_identifier, "hash");
    addExt(c, signerCert, NID_authority_key_identifier, "keyid:always");
    if (!spec.ca) {
        std::string san = "URI:" + spec.applicationUri;
        for (const auto& d : spec.dnsNames) san += ",DNS:" + d;
        addExt(c, signerCert, NID_subject_alt_name, san);
    }
    EVP_PKEY* signerKey = issuer != nullptr ? issuer->key.get() : out.key.get();
    require(X509_sign(c, signerKey, EVP_sha256()) != 0, "sign");
    return out;
}

}  // namespace

ByteString KeyAndCert::der() const {
    unsigned char* buf = nullptr;
    const int len = i2d_X509(cert.get(), &buf);
    require(len > 0, "encode");
    ByteString out(std::vector<std::uint8_t>(buf, buf + len));
    OPENSSL_free(buf);
    return out;
}

KeyAndCert makeCertificate(const CertSpec& spec, const KeyAndCert* issuer) {
    return build(spec, issuer);
}

KeyAndCert makeCa(const std::string& name, const KeyAndCert* issuer) {
    CertSpec spec;
    spec.commonName = name;
    spec.ca = true;
    spec.notAfterDays = 3650;
    spec.keyUsage = "critical,keyCertSign,cRLSign";
    return build(spec, issuer);
}

ossl::Crl makeCrl(const KeyAndCert& ca, const std::vector<const KeyAndCert*>& revoked) {
    ossl::Crl crl(X509_CRL_new());
    require(crl != nullptr, "crl");
    X509_CRL_set_version(crl.get(), 1);
    X509_CRL_set_issuer_name(crl.get(), X509_get_subject_name(ca.cert.get()));
    const ossl::Time last(X509_gmtime_adj(nullptr, -3600));
    const ossl::Time next(X509_gmtime_adj(nullptr, 30 * 86400L));
    X509_CRL_set1_lastUpdate(crl.get(), last.get());
    X509_CRL_set1_nextUpdate(crl.get(), next.get());
    for (const KeyAndCert* r : revoked) {
        ossl::Revoked entry(X509_REVOKED_new());
        X509_REVOKED_set_serialNumber(
            entry.get(), const_cast<ASN1_INTEGER*>(X509_get0_serialNumber(r->cert.get())));
        X509_REVOKED_set_revocationDate(entry.get(), last.get());
        require(X509_CRL_add0_revoked(crl.get(), entry.release()) == 1, "revoked entry");
    }
    X509_CRL_sort(crl.get());
    require(X509_CRL_sign(crl.get(), ca.key.get(), EVP_sha256()) != 0, "crl sign");
    return crl;
}

ByteString concat(const ByteString& a, const ByteString& b) {
    std::vector<std::uint8_t> out = a.bytes;
    out.insert(out.end(), b.bytes.begin(), b.bytes.end());
    return ByteString(std::move(out));
}

void writeFile(const std::filesystem::path& file, const ByteString& bytes) {
    std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.bytes.data()),
              static_cast<std::streamsize>(bytes.bytes.size()));
    require(out.good(), "write");
}

void writeCrl(const std::filesystem::path& file, X509_CRL* crl) {
    unsigned char* buf = nullptr;
    const int len = i2d_X509_CRL(crl, &buf);
    require(len > 0, "encode crl");
    writeFile(file, ByteString(std::vector<std::uint8_t>(buf, buf + len)));
    OPENSSL_free(buf);
}

TempDir::TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "skillcell-pki-XXXXXX").string();
    require(::mkdtemp(tmpl.data()) != nullptr, "mkdtemp");
    path_ = tmpl;
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

}  // namespace skillcell::ua::pki::test
