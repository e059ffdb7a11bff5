#pragma once
// Certificates for the PKI tests, made with OpenSSL directly (not with the code under test),
// so that the tests can build what production code never would: expired, tampered, revoked,
// wrong key usage.
#include <filesystem>
#include <string>
#include <vector>

#include "ua/pki/openssl_handles.hpp"
#include "ua/types/builtin.hpp"

namespace skillcell::ua::pki::test {

struct CertSpec {
    std::string commonName = "peer";
    std::string applicationUri = "urn:test:peer";
    std::vector<std::string> dnsNames{"localhost"};
    long notBeforeDays = -1;  // relative to now
    long notAfterDays = 365;
    bool ca = false;
    int keyBits = 2048;
    std::string keyUsage =
        "critical,digitalSignature,nonRepudiation,keyEncipherment,dataEncipherment,keyCertSign";
};

struct KeyAndCert {
    ossl::PKey key;
    ossl::Cert cert;
    [[nodiscard]] ByteString der() const;
};

/// A certificate for `spec`, self-signed when `issuer` is null.
KeyAndCert makeCertificate(const CertSpec& spec, const KeyAndCert* issuer = nullptr);
/// A CA (CA:TRUE, keyCertSign, cRLSign), self-signed or issued by `issuer`.
KeyAndCert makeCa(const std::string& name, const KeyAndCert* issuer = nullptr);
/// A CRL of `ca` listing `revoked`.
ossl::Crl makeCrl(const KeyAndCert& ca, const std::vector<const KeyAndCert*>& revoked);

ByteString concat(const ByteString& a, const ByteString& b);
void writeFile(const std::filesystem::path& file, const ByteString& bytes);
void writeCrl(const std::filesystem::path& file, X509_CRL* crl);

/// A fresh directory under the system's temporary directory, removed at scope end.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace skillcell::ua::pki::test
