#include "test_certificate.hpp"

#include <openssl/x509v3.h>

#include <stdexcept>
#include <utility>

namespace skillcell::test {

TestCertificate makeTestCertificate(int bits, const std::string& applicationUri, long validFrom,
                                    long validTo) {
    auto key = ua::crypto::RsaKey::generate(bits);
    if (!key) throw std::runtime_error("RSA key generation failed");
    ua::crypto::X509Handle cert(X509_new());
    X509_set_version(cert.get(), 2);
    ASN1_INTEGER_set(X509_get_serialNumber(cert.get()), 1);
    X509_gmtime_adj(X509_getm_notBefore(cert.get()), validFrom);
    X509_gmtime_adj(X509_getm_notAfter(cert.get()), validTo);
    X509_set_pubkey(cert.get(), key->get());
    X509_NAME* name = X509_get_subject_name(cert.get());
    X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC,
                               reinterpret_cast<const unsigned char*>("skillcell test"), -1, -1, 0);
    X509_set_issuer_name(cert.get(), name);
    X509V3_CTX ctx;
    X509V3_set_ctx_nodb(&ctx);
    X509V3_set_ctx(&ctx, cert.get(), cert.get(), nullptr, nullptr, 0);
    const std::string san = "URI:" + applicationUri + ",DNS:localhost";
    // The extensions OPC 10000-6 6.2.2 asks of an application instance certificate; peers
    // such as node-opcua refuse one without them (BadCertificateUseNotAllowed).
    const std::pair<int, std::string> extensions[] = {
        {NID_subject_alt_name, san},
        {NID_basic_constraints, "critical,CA:FALSE"},
        {NID_key_usage,
         "critical,digitalSignature,nonRepudiation,keyEncipherment,dataEncipherment"},
        {NID_ext_key_usage, "serverAuth,clientAuth"},
    };
    for (const auto& [nid, value] : extensions) {
        X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str());
        if (ext == nullptr) throw std::runtime_error("certificate extension " + value);
        X509_add_ext(cert.get(), ext, -1);
        X509_EXTENSION_free(ext);
    }
    if (X509_sign(cert.get(), key->get(), EVP_sha256()) == 0) {
        throw std::runtime_error("certificate signing failed");
    }
    unsigned char* out = nullptr;
    const int len = i2d_X509(cert.get(), &out);
    ua::ByteString der(std::vector<std::uint8_t>(out, out + len));
    OPENSSL_free(out);
    return {std::move(der), std::move(*key)};
}

}  // namespace skillcell::test
