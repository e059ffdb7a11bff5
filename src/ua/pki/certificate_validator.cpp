#include "ua/pki/certificate_validator.hpp"

#include <openssl/err.h>
#include <openssl/x509_vfy.h>

#include <algorithm>
#include <vector>

namespace skillcell::ua::pki {

namespace {

// The steps of OPC 10000-4 Table 106 that can fail, in the order they are checked: the
// smallest step among all findings decides the status code.
enum class Step {
    Structure,
    Chain,
    Signature,
    Policy,
    Trust,
    Validity,
    IssuerValidity,
    HostName,
    Uri,
    Usage,
    IssuerUsage,
    RevocationList,
    IssuerRevocationList,
    Revocation,
    IssuerRevocation,
};

StatusCode statusOf(Step s) {
    switch (s) {
        case Step::Structure:
        case Step::Signature:
            return status::BadCertificateInvalid;
        case Step::Chain:
            return status::BadCertificateChainIncomplete;
        case Step::Policy:
            return status::BadCertificatePolicyCheckFailed;
        case Step::Trust:
            return status::BadCertificateUntrusted;
        case Step::Validity:
            return status::BadCertificateTimeInvalid;
        case Step::IssuerValidity:
            return status::BadCertificateIssuerTimeInvalid;
        case Step::HostName:
            return status::BadCertificateHostNameInvalid;
        case Step::Uri:
            return status::BadCertificateUriInvalid;
        case Step::Usage:
            return status::BadCertificateUseNotAllowed;
        case Step::IssuerUsage:
            return status::BadCertificateIssuerUseNotAllowed;
        case Step::RevocationList:
            return status::BadCertificateRevocationUnknown;
        case Step::IssuerRevocationList:
            return status::BadCertificateIssuerRevocationUnknown;
        case Step::Revocation:
            return status::BadCertificateRevoked;
        case Step::IssuerRevocation:
            return status::BadCertificateIssuerRevoked;
    }
    return status::BadCertificateInvalid;
}

struct Finding {
    Step step;
    std::string reason;
};

/// What the verify callback collects; OpenSSL hands it back through the context's app data.
struct Collector {
    const TrustList* trustList = nullptr;
    bool requireRevocationLists = true;
    std::vector<Finding> findings;
};

Step stepOf(int error, bool leaf) {
    switch (error) {
        case X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT:
        case X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY:
        case X509_V_ERR_UNABLE_TO_VERIFY_LEAF_SIGNATURE:
            return Step::Chain;
        case X509_V_ERR_DEPTH_ZERO_SELF_SIGNED_CERT:
        case X509_V_ERR_SELF_SIGNED_CERT_IN_CHAIN:
        case X509_V_ERR_CERT_UNTRUSTED:
        case X509_V_ERR_CERT_REJECTED:
            return Step::Trust;
        case X509_V_ERR_CERT_SIGNATURE_FAILURE:
        case X509_V_ERR_UNABLE_TO_DECRYPT_CERT_SIGNATURE:
        case X509_V_ERR_UNABLE_TO_DECODE_ISSUER_PUBLIC_KEY:
            return Step::Signature;
        case X509_V_ERR_CERT_NOT_YET_VALID:
        case X509_V_ERR_CERT_HAS_EXPIRED:
            return leaf ? Step::Validity : Step::IssuerValidity;
        case X509_V_ERR_INVALID_CA:
        case X509_V_ERR_INVALID_PURPOSE:
        case X509_V_ERR_KEYUSAGE_NO_CERTSIGN:
        case X509_V_ERR_PATH_LENGTH_EXCEEDED:
        case X509_V_ERR_INVALID_NON_CA:
            return leaf ? Step::Usage : Step::IssuerUsage;
        case X509_V_ERR_UNABLE_TO_GET_CRL:
        case X509_V_ERR_UNABLE_TO_GET_CRL_ISSUER:
        case X509_V_ERR_CRL_NOT_YET_VALID:
        case X509_V_ERR_CRL_HAS_EXPIRED:
        case X509_V_ERR_CRL_SIGNATURE_FAILURE:
        case X509_V_ERR_UNABLE_TO_DECRYPT_CRL_SIGNATURE:
        case X509_V_ERR_KEYUSAGE_NO_CRL_SIGN:
        case X509_V_ERR_DIFFERENT_CRL_SCOPE:
        case X509_V_ERR_ERROR_IN_CRL_LAST_UPDATE_FIELD:
        case X509_V_ERR_ERROR_IN_CRL_NEXT_UPDATE_FIELD:
            return leaf ? Step::RevocationList : Step::IssuerRevocationList;
        case X509_V_ERR_CERT_REVOKED:
            return leaf ? Step::Revocation : Step::IssuerRevocation;
        default:
            return Step::Structure;
    }
}

std::string describe(X509* cert) {
    if (cert == nullptr) return "certificate";
    const CertificateInfo info = inspectCertificate(cert);
    return "certificate \"" + info.subject + "\" (thumbprint " + info.thumbprint + ")";
}

int verifyCallback(int ok, X509_STORE_CTX* ctx) {
    if (ok == 1) return 1;
    auto* collector = static_cast<Collector*>(X509_STORE_CTX_get_app_data(ctx));
    const int error = X509_STORE_CTX_get_error(ctx);
    const int depth = X509_STORE_CTX_get_error_depth(ctx);
    X509* cert = X509_STORE_CTX_get_current_cert(ctx);
    const Step step = stepOf(error, depth == 0);
    if (step == Step::RevocationList || step == Step::IssuerRevocationList) {
        // A directly trusted certificate needs no CRL (see the header).
        const bool trustedItself =
            cert != nullptr && collector->trustList->isTrusted(certificateThumbprintHex(cert));
        if (trustedItself || !collector->requireRevocationLists) return 1;
    }
    std::string why = describe(cert) + ": " + X509_verify_cert_error_string(error);
    if (step == Step::Trust) {
        why += "; it is not in trusted/certs, nor issued by a CA there";
    } else if (step == Step::Chain) {
        why += "; its issuer is neither in the chain sent, nor in trusted/certs or issuers/certs";
    } else if (step == Step::RevocationList || step == Step::IssuerRevocationList) {
        why += "; put its issuer's CRL into trusted/crl or issuers/crl";
    }
    collector->findings.push_back({step, std::move(why)});
    return 1;  // go on: all findings are collected, the earliest step decides
}

bool hostMatches(X509* leaf, const std::string& host) {
    // An IP literal is compared with the IP addresses, anything else with the DNS names.
    if (X509_check_ip_asc(leaf, host.c_str(), 0) == 1) return true;
    return X509_check_host(leaf, host.data(), host.size(), 0, nullptr) == 1;
}

/// What `expected` asks of the leaf beside its chain: a finding for each expectation it misses.
void checkExpectations(X509* leaf, const CertificateInfo& info, const PeerExpectations& expected,
                       std::vector<Finding>& findings) {
    if ((expected.minimumKeyBits > 0 && info.keyBits < expected.minimumKeyBits) ||
        (expected.maximumKeyBits > 0 && info.keyBits > expected.maximumKeyBits)) {
        findings.push_back({Step::Policy, describe(leaf) + " has a " +
                                              std::to_string(info.keyBits) +
                                              "-bit key; the security policy needs " +
                                              std::to_string(expected.minimumKeyBits) + ".." +
                                              std::to_string(expected.maximumKeyBits) + " bits"});
    }
    if (!expected.hostName.empty() && !hostMatches(leaf, expected.hostName)) {
        findings.push_back(
            {Step::HostName, describe(leaf) + " is not issued for host " + expected.hostName});
    }
    if (!expected.applicationUri.empty() && info.applicationUri != expected.applicationUri) {
        findings.push_back({Step::Uri, describe(leaf) + " names application URI \"" +
                                           info.applicationUri + "\", expected \"" +
                                           expected.applicationUri + "\""});
    }
}

}  // namespace

CertificateValidator::CertificateValidator(std::filesystem::path pkiDir, ValidatorOptions options)
    : trustList_(std::move(pkiDir)), options_(options) {}

CertificateVerdict CertificateValidator::validate(const ByteString& certificate,
                                                  std::string_view expectedApplicationUri) {
    PeerExpectations expected;
    expected.applicationUri = std::string(expectedApplicationUri);
    return validate(certificate, expected);
}

void CertificateValidator::preload() {
    if (trustList_.refresh()) remembered_.clear();
}

CertificateVerdict CertificateValidator::validate(const ByteString& certificate,
                                                  const PeerExpectations& expected) {
    if (trustList_.refresh()) remembered_.clear();  // trust changed: every verdict with it
    const Clock::time_point now = expected.now.value_or(Clock::now());
    std::string key(certificate.bytes.begin(), certificate.bytes.end());
    std::optional<Remembered> good;
    if (auto it = remembered_.find(key); it != remembered_.end()) {
        const Remembered& r = it->second;
        if (r.from <= now && now <= r.until) {
            // The chain holds; what this caller expects of the leaf is checked anew. One it
            // misses is refused in full, with its reason.
            std::vector<Finding> missed;
            checkExpectations(r.leaf.get(), r.info, expected, missed);
            if (missed.empty()) return r.verdict;
            return validateInFull(certificate, expected, &good);
        }
        remembered_.erase(it);
    }
    CertificateVerdict verdict = validateInFull(certificate, expected, &good);
    if (good) {
        if (remembered_.size() >= kRememberedMax) remembered_.clear();
        remembered_.emplace(std::move(key), std::move(*good));
    }
    return verdict;
}

CertificateVerdict CertificateValidator::validateInFull(const ByteString& certificate,
                                                        const PeerExpectations& expected,
                                                        std::optional<Remembered>* good) {
    ++fullValidations_;
    CertificateVerdict verdict;
    auto chain = parseCertificateChain(certificate);
    if (!chain) {
        verdict.status = status::BadCertificateInvalid;
        verdict.reason = "the certificate is not DER X.509 (nor a chain of them)";
        return verdict;
    }
    const ossl::Cert& leaf = chain->front().cert;
    const CertificateInfo info = inspectCertificate(leaf.get());
    verdict.thumbprint = info.thumbprint;
    verdict.subject = info.subject;

    const ossl::Store store(X509_STORE_new());
    const ossl::CertStack untrusted(sk_X509_new_null());
    const ossl::StoreCtx ctx(X509_STORE_CTX_new());
    if (!store || !untrusted || !ctx) {
        verdict.status = status::BadOutOfMemory;
        verdict.reason = "OpenSSL could not allocate a certificate store";
        return verdict;
    }
    for (const auto& cert : trustList_.trusted()) X509_STORE_add_cert(store.get(), cert.get());
    for (const auto& crl : trustList_.crls()) X509_STORE_add_crl(store.get(), crl.get());
    // The issuers the peer sent and issuers/certs complete chains; neither is trusted.
    // The stack owns one reference of each certificate (freed with it).
    const auto addUntrusted = [&untrusted](X509* cert) {
        X509_up_ref(cert);
        if (sk_X509_push(untrusted.get(), cert) == 0) X509_free(cert);
    };
    for (std::size_t i = 1; i < chain->size(); ++i) addUntrusted((*chain)[i].cert.get());
    for (const auto& cert : trustList_.issuers()) addUntrusted(cert.get());

    Collector collector;
    collector.trustList = &trustList_;
    collector.requireRevocationLists = options_.requireRevocationLists;
    if (X509_STORE_CTX_init(ctx.get(), store.get(), leaf.get(), untrusted.get()) != 1) {
        verdict.status = status::BadInternalError;
        verdict.reason = "X509_STORE_CTX_init failed";
        return verdict;
    }
    X509_STORE_CTX_set_app_data(ctx.get(), &collector);
    X509_STORE_CTX_set_verify_cb(ctx.get(), verifyCallback);
    X509_VERIFY_PARAM* param = X509_STORE_CTX_get0_param(ctx.get());
    // PARTIAL_CHAIN: any certificate in trusted/ is a trust anchor, not only self-signed
    // roots (OPC UA trusts what the operator put there). CHECK_SS_SIGNATURE: a self-signed
    // certificate's own signature is checked too, trusted or not, so a tampered certificate
    // is invalid rather than merely untrusted (and does not land in rejected/).
    X509_VERIFY_PARAM_set_flags(param, X509_V_FLAG_PARTIAL_CHAIN | X509_V_FLAG_CHECK_SS_SIGNATURE |
                                           X509_V_FLAG_CRL_CHECK | X509_V_FLAG_CRL_CHECK_ALL);
    X509_VERIFY_PARAM_set_time(param, Clock::to_time_t(expected.now.value_or(Clock::now())));
    const bool chainVerified = X509_verify_cert(ctx.get()) == 1;
    ERR_clear_error();  // the callback kept what matters; leave no errors for others to see

    X509* leafCert = leaf.get();
    checkExpectations(leafCert, info, expected, collector.findings);
    // An application instance certificate signs and (RSA) receives encrypted keys
    // (OPC 10000-6, 6.2.2); an ECC key agrees on keys instead of receiving them. A CA's
    // certificate must not act as one.
    const std::uint32_t usage = X509_get_key_usage(leafCert);
    const bool ecc = EVP_PKEY_is_a(X509_get0_pubkey(leafCert), "EC") == 1;
    if (usage != UINT32_MAX &&
        ((usage & KU_DIGITAL_SIGNATURE) == 0 || (!ecc && (usage & KU_KEY_ENCIPHERMENT) == 0))) {
        collector.findings.push_back(
            {Step::Usage, describe(leafCert) + (ecc ? ": keyUsage lacks digitalSignature"
                                                    : ": keyUsage lacks digitalSignature or "
                                                      "keyEncipherment")});
    }
    if ((X509_get_extension_flags(leafCert) & EXFLAG_XKUSAGE) != 0 &&
        (X509_get_extended_key_usage(leafCert) & (XKU_SSL_SERVER | XKU_SSL_CLIENT)) == 0) {
        collector.findings.push_back(
            {Step::Usage, describe(leafCert) + ": extendedKeyUsage allows neither serverAuth "
                                               "nor clientAuth"});
    }
    if (info.isCa && !info.selfSigned) {
        collector.findings.push_back(
            {Step::Usage, describe(leafCert) + " is a CA certificate, not an application's"});
    }

    if (collector.findings.empty()) {
        // Good: it stays so from the latest start to the earliest end of the validity
        // periods of the chain and of the CRLs checked against (second precision).
        Remembered kept{verdict, Clock::time_point::min(), Clock::time_point::max(), nullptr, info};
        X509_up_ref(leafCert);
        kept.leaf.reset(leafCert);
        bool bounded = chainVerified;
        const auto within = [&](const ASN1_TIME* from, const ASN1_TIME* until) {
            const auto f = timePointOf(from);
            const auto u =
                until == nullptr ? std::optional(Clock::time_point::max()) : timePointOf(until);
            if (!f || !u) {
                bounded = false;
                return;
            }
            kept.from = std::max(kept.from, *f);
            kept.until = std::min(kept.until, *u);
        };
        if (STACK_OF(X509)* verified = X509_STORE_CTX_get0_chain(ctx.get())) {
            for (int i = 0; i < sk_X509_num(verified); ++i) {
                X509* c = sk_X509_value(verified, i);
                within(X509_get0_notBefore(c), X509_get0_notAfter(c));
            }
        } else {
            bounded = false;
        }
        for (const auto& crl : trustList_.crls()) {
            within(X509_CRL_get0_lastUpdate(crl.get()), X509_CRL_get0_nextUpdate(crl.get()));
        }
        if (bounded) *good = std::move(kept);
        return verdict;
    }
    const auto first =
        std::min_element(collector.findings.begin(), collector.findings.end(),
                         [](const Finding& a, const Finding& b) { return a.step < b.step; });
    verdict.status = statusOf(first->step);
    verdict.reason = first->reason;
    if (options_.copyRejected && (first->step == Step::Trust || first->step == Step::Chain)) {
        auto stored = storeRejectedCertificate(trustList_.paths().rejectedCerts(),
                                               chain->front().der, options_.maxRejectedFiles);
        if (stored) {
            verdict.rejectedFile = *stored;
            verdict.reason += "; copied to " + stored->string() +
                              " (move it to trusted/certs, or run `skillcell pki trust " +
                              verdict.thumbprint.substr(0, 8) + " --pki-dir " +
                              trustList_.paths().root.string() + "`, to trust it)";
        }
    }
    return verdict;
}

}  // namespace skillcell::ua::pki
