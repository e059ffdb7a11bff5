#include "ua/pki/certificate.hpp"

#include <openssl/core_names.h>
#include <openssl/sha.h>
#include <openssl/x509.h>

#include <ctime>

#include "ua/types/hex.hpp"

namespace skillcell::ua::pki {

namespace {

std::string nameString(const X509_NAME* name) {
    const ossl::Bio bio(BIO_new(BIO_s_mem()));
    if (!bio ||
        X509_NAME_print_ex(bio.get(), name, 0, XN_FLAG_ONELINE & ~ASN1_STRFLGS_ESC_MSB) < 0) {
        return {};
    }
    char* data = nullptr;
    const long len = BIO_get_mem_data(bio.get(), &data);
    return {data, static_cast<std::size_t>(len)};
}

std::string asn1String(const ASN1_STRING* s) {
    return {reinterpret_cast<const char*>(ASN1_STRING_get0_data(s)),
            static_cast<std::size_t>(ASN1_STRING_length(s))};
}

}  // namespace

std::optional<Clock::time_point> timePointOf(const ASN1_TIME* time) {
    std::tm tm{};
    if (time == nullptr || ASN1_TIME_to_tm(time, &tm) != 1) return std::nullopt;
    constexpr std::time_t kClockRangeEnd = 9'000'000'000;  // 2255: before the clock's end
    const std::time_t seconds = timegm(&tm);
    if (seconds >= kClockRangeEnd) return Clock::time_point::max();
    return Clock::from_time_t(seconds);
}

Result<std::vector<ChainCertificate>> parseCertificateChain(const ByteString& chain) {
    std::vector<ChainCertificate> out;
    const unsigned char* p = chain.bytes.data();
    const unsigned char* const end = p + chain.bytes.size();
    while (p < end) {
        const unsigned char* start = p;
        ossl::Cert cert(d2i_X509(nullptr, &p, end - p));
        if (!cert || p <= start || p > end) return status::BadCertificateInvalid;
        out.push_back({ByteString(std::vector<std::uint8_t>(start, p)), std::move(cert)});
    }
    if (out.empty()) return status::BadCertificateInvalid;
    return out;
}

Result<ossl::Cert> parseCertificate(const ByteString& der) {
    const unsigned char* p = der.bytes.data();
    ossl::Cert cert(d2i_X509(nullptr, &p, static_cast<long>(der.bytes.size())));
    if (!cert) return status::BadCertificateInvalid;
    return cert;
}

ByteString certificateDer(X509* cert) {
    unsigned char* buf = nullptr;
    const int len = i2d_X509(cert, &buf);
    if (len <= 0) return {};
    ByteString out(std::vector<std::uint8_t>(buf, buf + len));
    OPENSSL_free(buf);
    return out;
}

Result<std::array<std::uint8_t, 20>> certificateThumbprint(const ByteString& der) {
    // Only the leaf's bytes count, so find where the first certificate ends.
    const unsigned char* p = der.bytes.data();
    const ossl::Cert cert(d2i_X509(nullptr, &p, static_cast<long>(der.bytes.size())));
    if (!cert) return status::BadCertificateInvalid;
    std::array<std::uint8_t, 20> digest{};
    SHA1(der.bytes.data(), static_cast<std::size_t>(p - der.bytes.data()), digest.data());
    return digest;
}

std::string certificateThumbprintHex(const ByteString& der) {
    auto t = certificateThumbprint(der);
    return t ? toHex(*t) : std::string();
}

std::string certificateThumbprintHex(X509* cert) {
    std::array<std::uint8_t, 20> digest{};
    unsigned int length = 0;
    if (cert == nullptr || X509_digest(cert, EVP_sha1(), digest.data(), &length) != 1 ||
        length != digest.size()) {
        return {};
    }
    return toHex(digest);
}

std::string applicationUriOf(X509* cert) {
    const ossl::Names names(static_cast<GENERAL_NAMES*>(
        X509_get_ext_d2i(cert, NID_subject_alt_name, nullptr, nullptr)));
    for (int i = 0; names && i < sk_GENERAL_NAME_num(names.get()); ++i) {
        const GENERAL_NAME* n = sk_GENERAL_NAME_value(names.get(), i);
        if (n->type == GEN_URI) return asn1String(n->d.uniformResourceIdentifier);
    }
    return {};
}

CertificateInfo inspectCertificate(X509* cert) {
    CertificateInfo info;
    info.subject = nameString(X509_get_subject_name(cert));
    info.issuer = nameString(X509_get_issuer_name(cert));
    const ossl::Names names(static_cast<GENERAL_NAMES*>(
        X509_get_ext_d2i(cert, NID_subject_alt_name, nullptr, nullptr)));
    for (int i = 0; names && i < sk_GENERAL_NAME_num(names.get()); ++i) {
        const GENERAL_NAME* n = sk_GENERAL_NAME_value(names.get(), i);
        if (n->type == GEN_URI && info.applicationUri.empty()) {
            info.applicationUri = asn1String(n->d.uniformResourceIdentifier);
        } else if (n->type == GEN_DNS) {
            info.dnsNames.push_back(asn1String(n->d.dNSName));
        } else if (n->type == GEN_IPADD) {
            const ASN1_OCTET_STRING* ip = n->d.iPAddress;
            const unsigned char* b = ASN1_STRING_get0_data(ip);
            if (ASN1_STRING_length(ip) == 4) {
                info.ipAddresses.push_back(std::to_string(b[0]) + "." + std::to_string(b[1]) + "." +
                                           std::to_string(b[2]) + "." + std::to_string(b[3]));
            } else {
                info.ipAddresses.push_back(
                    toHex({b, static_cast<std::size_t>(ASN1_STRING_length(ip))}));
            }
        }
    }
    // Reading the extensions (which the chain's verification needs too) keeps the SHA-1.
    info.isCa = X509_check_ca(cert) != 0;
    info.thumbprint = certificateThumbprintHex(cert);
    if (const ossl::Bn serial(ASN1_INTEGER_to_BN(X509_get0_serialNumber(cert), nullptr)); serial) {
        char* hex = BN_bn2hex(serial.get());
        if (hex != nullptr) info.serialNumber = hex;
        OPENSSL_free(hex);
    }
    info.notBefore = timePointOf(X509_get0_notBefore(cert)).value_or(Clock::time_point{});
    info.notAfter = timePointOf(X509_get0_notAfter(cert)).value_or(Clock::time_point{});
    info.selfSigned = X509_self_signed(cert, 1) == 1;
    if (const EVP_PKEY* key = X509_get0_pubkey(cert); key != nullptr) {
        info.keyBits = EVP_PKEY_get_bits(key);
        char group[64] = {};
        std::size_t length = 0;
        if (EVP_PKEY_is_a(key, "RSA") == 1) {
            info.keyType = "RSA";
        } else if (EVP_PKEY_get_utf8_string_param(key, OSSL_PKEY_PARAM_GROUP_NAME, group,
                                                  sizeof group, &length) == 1) {
            info.keyType = std::string_view(group, length) == "prime256v1"
                               ? "EC P-256"
                               : "EC " + std::string(group, length);
        } else {
            info.keyType =
                EVP_PKEY_get0_type_name(key) != nullptr ? EVP_PKEY_get0_type_name(key) : "?";
        }
    }
    return info;
}

Result<CertificateInfo> inspectCertificate(const ByteString& der) {
    auto cert = parseCertificate(der);
    if (!cert) return cert.status();
    return inspectCertificate(cert->get());
}

Result<ossl::PKey> certificatePublicKey(const ByteString& der) {
    auto cert = parseCertificate(der);
    if (!cert) return cert.status();
    ossl::PKey key(X509_get_pubkey(cert->get()));
    if (!key) return status::BadCertificateInvalid;
    return key;
}

Result<int> certificateKeyBits(const ByteString& der) {
    auto key = certificatePublicKey(der);
    if (!key) return key.status();
    return EVP_PKEY_get_bits(key->get());
}

}  // namespace skillcell::ua::pki
