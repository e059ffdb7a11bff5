#pragma once
// Validation of a peer's application instance certificate against the PKI directory, in the
// order of OPC 10000-4, 6.1.3 (Table 106): structure, chain, signature, security policy (key
// length), trust list, validity,
// host name, URI, key usage, revocation list, revocation. The first failing step decides the
// status code; the reason names the certificate and what to do about it.
//
// Trust: a certificate is trusted when it, or a certificate of its chain, is in
// trusted/certs (a trusted CA trusts everything it issued). issuers/certs only completes
// chains. A self-signed certificate is therefore trusted only when it is itself in
// trusted/certs.
//
// Revocation: every certificate of the chain that is not itself in trusted/certs needs a
// CRL of its issuer in trusted/crl or issuers/crl (BadCertificateRevocationUnknown /
// BadCertificateIssuerRevocationUnknown without one). A certificate an operator trusts
// directly needs none: removing it from trusted/ is its revocation. `skillcell pki init-ca`
// creates the CA's CRL, and components copy it beside the CA certificate, so a cell CA
// satisfies this rule without manual steps.
//
// Rejected certificates: when the verdict is BadCertificateUntrusted or
// BadCertificateChainIncomplete the leaf is copied to rejected/certs/<thumbprint>.der, so an
// operator can trust it by moving the file (or `skillcell pki trust`). The next validation
// sees the move: the lists reload when trusted/ or issuers/ change.
//
// A Good verdict is remembered for the same certificate bytes while the trust list is
// unchanged and the moment checked lies within the validity periods of the chain and the CRLs
// used; what a later caller expects of the leaf (application URI, host, key length) is
// checked anew, and one it misses runs in full. A peer validated for its secure channel is not
// validated again, in full, for its session, its X.509 user token, nor at every reconnect.
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "ua/pki/certificate.hpp"
#include "ua/pki/trust_list.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/status_code.hpp"

namespace skillcell::ua::pki {

struct ValidatorOptions {
    std::size_t maxRejectedFiles = 100;  // rejected/certs keeps at most this many
    bool copyRejected = true;
    /// False: a missing CRL is not an error (for cells whose CAs publish none). Default strict.
    bool requireRevocationLists = true;
};

/// What the peer is expected to be. Empty fields are not checked.
struct PeerExpectations {
    /// The ApplicationUri of the peer's ApplicationDescription (CreateSession) or of the
    /// endpoint (client side): must be the certificate's subjectAltName URI.
    std::string applicationUri;
    /// The host name (or IP address) of the endpoint URL a client connected to: must be a
    /// DNS name or IP address of the certificate (client side only).
    std::string hostName;
    /// The security policy's bounds on the leaf's RSA key (OPC 10000-7: Basic256Sha256 and
    /// the Aes* policies 2048..4096); 0: unbounded. Outside: BadCertificatePolicyCheckFailed.
    int minimumKeyBits = 0;
    int maximumKeyBits = 0;
    /// The time to check validity periods and CRLs at; empty: now.
    std::optional<Clock::time_point> now;
};

struct CertificateVerdict {
    StatusCode status = status::Good;
    std::string reason;                  // for logs and for the operator; empty when Good
    std::string thumbprint;              // the leaf's, lower-case hex; empty when it did not parse
    std::string subject;                 // the leaf's
    std::filesystem::path rejectedFile;  // where the leaf was copied, when it was
    [[nodiscard]] bool ok() const { return status.isGood(); }
};

/// Validates peer certificates against one PKI directory. Not thread-safe (it reloads its
/// TrustList on use); one per server or client, used from its io_context's thread.
class CertificateValidator {
public:
    explicit CertificateValidator(std::filesystem::path pkiDir, ValidatorOptions options = {});

    /// `certificate`: the peer's DER certificate, possibly followed by its issuers' (the
    /// SenderCertificate of OpenSecureChannel, the ClientCertificate of CreateSession).
    [[nodiscard]] CertificateVerdict validate(const ByteString& certificate,
                                              const PeerExpectations& expected);
    /// The same, checking only the application URI (empty: not checked).
    [[nodiscard]] CertificateVerdict validate(const ByteString& certificate,
                                              std::string_view expectedApplicationUri = {});

    /// Loads the trust list now (validate() would at its first use), so that the first peer
    /// does not wait for it.
    void preload();

    [[nodiscard]] const PkiPaths& paths() const { return trustList_.paths(); }

    /// How many validations ran in full, the chain verified against the trust list; the
    /// others were answered from a Good verdict remembered for the same certificate.
    [[nodiscard]] std::size_t fullValidations() const { return fullValidations_; }

private:
    /// A Good verdict, the times between which it holds, and the leaf, against which the
    /// expectations of the next callers are checked (they differ: a server checks a client's
    /// certificate without an application URI when the channel opens, with one when the
    /// session is created).
    struct Remembered {
        CertificateVerdict verdict;
        Clock::time_point from;
        Clock::time_point until;
        ossl::Cert leaf;
        CertificateInfo info;
    };
    static constexpr std::size_t kRememberedMax = 64;  // peers of one component, with room

    [[nodiscard]] CertificateVerdict validateInFull(const ByteString& certificate,
                                                    const PeerExpectations& expected,
                                                    std::optional<Remembered>* good);

    TrustList trustList_;
    ValidatorOptions options_;
    std::map<std::string, Remembered> remembered_;  // by certificate (its DER bytes)
    std::size_t fullValidations_ = 0;
};

}  // namespace skillcell::ua::pki
