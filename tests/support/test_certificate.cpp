#include "test_certificate.hpp"

#include <openssl/pem.h>
#include <openssl/x509v3.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace skillcell::test {

namespace {

// Generating RSA keys was most of the CPU of the tests that make certificates: every CTest
// test is a process of its own, and a 4096-bit key takes seconds on a loaded machine. So a
// key, once made, is kept as PEM in SKILLCELL_TEST_KEY_DIR (in the build directory): the
// n-th key of a size for an application URI that a process asks for is the same key in every
// test process of one build. The n keeps two certificates for one URI (a stranger beside the
// client) two keys. Certificates are made per call, as their validity is relative to now.
ua::crypto::AsymmetricKey testKey(int bits, const std::string& applicationUri) {
    static std::mutex mutex;
    static std::map<std::pair<int, std::string>, int> asked;
    const std::lock_guard lock(mutex);
    const int n = asked[{bits, applicationUri}]++;
    std::string name = std::to_string(bits) + "-" + std::to_string(n) + "-";
    for (const char c : applicationUri) {
        name += std::isalnum(static_cast<unsigned char>(c)) != 0 ? c : '_';
    }
    const std::filesystem::path dir(SKILLCELL_TEST_KEY_DIR);
    const std::filesystem::path file = dir / (name + ".pem");
    if (auto kept = ua::crypto::AsymmetricKey::fromPrivateKeyFile(file);
        kept && kept->bits() == bits) {
        return *kept;
    }
    auto key = ua::crypto::AsymmetricKey::generate(bits);
    if (!key) throw std::runtime_error("RSA key generation failed");
    // Written beside, then renamed: a process reading the file sees a whole key or none.
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const std::filesystem::path part = dir / (name + "." + std::to_string(::getpid()) + ".part");
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(std::fopen(part.c_str(), "wb"),
                                                              &std::fclose);
    if (out &&
        PEM_write_PrivateKey(out.get(), key->get(), nullptr, nullptr, 0, nullptr, nullptr) == 1 &&
        std::fflush(out.get()) == 0) {
        std::filesystem::rename(part, file, ec);
    }
    std::filesystem::remove(part, ec);  // when the rename did not happen
    return *key;
}

TestCertificate certify(const ua::crypto::AsymmetricKey& key, const std::string& applicationUri,
                        long validFrom, long validTo) {
    ua::crypto::X509Handle cert(X509_new());
    X509_set_version(cert.get(), 2);
    ASN1_INTEGER_set(X509_get_serialNumber(cert.get()), 1);
    X509_gmtime_adj(X509_getm_notBefore(cert.get()), validFrom);
    X509_gmtime_adj(X509_getm_notAfter(cert.get()), validTo);
    X509_set_pubkey(cert.get(), key.get());
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
         key.kind() == ua::crypto::AsymmetricKey::Kind::Rsa
             ? "critical,digitalSignature,nonRepudiation,keyEncipherment,dataEncipherment"
             : "critical,digitalSignature,nonRepudiation,keyAgreement"},
        {NID_ext_key_usage, "serverAuth,clientAuth"},
    };
    for (const auto& [nid, value] : extensions) {
        X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str());
        if (ext == nullptr) throw std::runtime_error("certificate extension " + value);
        X509_add_ext(cert.get(), ext, -1);
        X509_EXTENSION_free(ext);
    }
    if (X509_sign(cert.get(), key.get(), EVP_sha256()) == 0) {
        throw std::runtime_error("certificate signing failed");
    }
    unsigned char* out = nullptr;
    const int len = i2d_X509(cert.get(), &out);
    ua::ByteString der(std::vector<std::uint8_t>(out, out + len));
    OPENSSL_free(out);
    return {std::move(der), key};
}

}  // namespace

TestCertificate makeTestCertificate(int bits, const std::string& applicationUri, long validFrom,
                                    long validTo) {
    return certify(testKey(bits, applicationUri), applicationUri, validFrom, validTo);
}

TestCertificate makeTestEccCertificate(const std::string& applicationUri, long validFrom,
                                       long validTo) {
    auto key = ua::crypto::AsymmetricKey::generateEccNistP256();
    if (!key) throw std::runtime_error("P-256 key generation failed");
    return certify(*key, applicationUri, validFrom, validTo);
}

TestCertificate makeTestEccCertificate(ua::crypto::AsymmetricKey::Kind curve,
                                       const std::string& applicationUri) {
    auto key = ua::crypto::AsymmetricKey::generateEcc(curve);
    if (!key) throw std::runtime_error("ECC key generation failed");
    return certify(*key, applicationUri, -3600, 3600L * 24 * 365);
}

}  // namespace skillcell::test
