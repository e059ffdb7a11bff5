#pragma once
// ServerSecurity: the secrets and trust decisions behind a server's endpoints. What the
// server offers (policy + mode pairs, user token policies) is public and lives in
// ServerDescription; here are the private key that proves the server's certificate and the
// validator that decides about every client certificate (trust list, validity, chain;
// ua/pki). The connection asks selectPolicy() at a channel's first OpenSecureChannel.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ua/crypto/primitives.hpp"
#include "ua/messages/common.hpp"
#include "ua/server/user_identity.hpp"
#include "ua/transport/security_policy.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

/// One security policy offered with one mode.
struct SecurityEndpoint {
    std::string policyUri;
    MessageSecurityMode mode = MessageSecurityMode::None;
    friend bool operator==(const SecurityEndpoint&, const SecurityEndpoint&) = default;
};

/// Good when the peer certificate (DER, possibly a chain) is trusted, else the status that
/// refuses it (BadCertificateUntrusted, BadCertificateTimeInvalid, ...) with `reason` set.
/// `applicationUri` is the URI the certificate must name, empty to skip that check.
using CertificateCheck = std::function<StatusCode(
    const ByteString& certificate, std::string_view applicationUri, std::string* reason)>;

struct ServerSecurity {
    /// The private key of ServerDescription::certificate; needed for any secured endpoint.
    crypto::AsymmetricKey privateKey;
    /// The private key of ServerDescription::eccCertificate, when there is one.
    crypto::AsymmetricKey eccPrivateKey;

    /// The key of ServerDescription::certificateFor(policyUri).
    [[nodiscard]] const crypto::AsymmetricKey& privateKeyFor(std::string_view policyUri) const;
    /// Decides about client certificates; unset means every well-formed certificate is
    /// accepted (tests only: applications always set it).
    CertificateCheck validateCertificate;

    /// Whether anonymous sessions are accepted, and with which roles. The stack's default
    /// (everything, for in-process tests) is not what an application offers: device
    /// servers refuse anonymous users unless told otherwise (apps/server_process.cpp).
    bool allowAnonymous = true;
    RoleSet anonymousRoles{Role::Anonymous, Role::Admin};
    /// Checks user names with passwords and user certificates; none: only anonymous.
    std::shared_ptr<const UserAuthenticator> users;
};

/// Every secured policy and mode this stack implements for certificates with keys of
/// `keyKinds`, strongest first, then None when `withNone` (development only).
[[nodiscard]] std::vector<SecurityEndpoint> allSecurityEndpoints(
    bool withNone,
    const std::vector<crypto::AsymmetricKey::Kind>& keyKinds = {crypto::AsymmetricKey::Kind::Rsa});

/// The policy for a channel's first OpenSecureChannel: None always (for discovery),
/// BadSecurityPolicyRejected for another policy not offered, the validator's status for a
/// certificate not trusted (logged with its reason), BadConfigurationError when a secured policy is
/// offered without a private key. `ownCertificate` is the certificate of the header's policy
/// (ServerDescription::certificateFor).
[[nodiscard]] Result<std::unique_ptr<SecurityPolicy>> selectPolicy(
    const std::vector<SecurityEndpoint>& offered, const ServerSecurity& security,
    const ByteString& ownCertificate, const AsymmetricSecurityHeader& header,
    std::string_view peer);

}  // namespace skillcell::ua
