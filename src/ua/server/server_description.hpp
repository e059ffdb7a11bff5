#pragma once
// ServerDescription: who this server is, and the endpoints it offers. Discovery
// (GetEndpoints, FindServers) and CreateSession describe the server from this one place.
#include <optional>
#include <string>
#include <vector>

#include "ua/messages/discovery.hpp"
#include "ua/server/server_security.hpp"

namespace skillcell::ua {

inline constexpr std::string_view kTransportProfileUaTcp =
    "http://opcfoundation.org/UA-Profile/Transport/uatcp-uasc-uabinary";
inline constexpr std::string_view kAnonymousPolicyId = "anonymous";
inline constexpr std::string_view kUserNamePolicyId = "username";
inline constexpr std::string_view kCertificatePolicyId = "certificate";

struct ServerDescription {
    String applicationUri = "urn:skillcell:server";
    String productUri = "urn:skillcell";
    String applicationName = "skillcell server";
    /// DiscoveryServer for a stand-alone Local Discovery Server.
    ApplicationType applicationType = ApplicationType::Server;
    /// Host name put into endpoint URLs when the client's own URL is not usable.
    String advertisedHost = "localhost";
    std::uint16_t port = 4840;
    /// The application instance certificate (DER), offered in every endpoint even with
    /// SecurityPolicy None: peers expect one (ua/pki/own_certificate.hpp).
    ByteString certificate;
    /// A second certificate, with a P-256 key, for the ECC policies; empty when the server
    /// has none (then `certificate` serves every policy it offers).
    ByteString eccCertificate;

    /// The certificate of the endpoints of `policyUri`: the ECC one for an ECC policy.
    [[nodiscard]] const ByteString& certificateFor(std::string_view policyUri) const;
    /// The security policies and modes offered, one EndpointDescription each. The stack's
    /// default is None alone, for in-process tests and tools; applications offer the
    /// secured ones (apps/server_process.cpp).
    std::vector<SecurityEndpoint> securityEndpoints{
        {std::string(kSecurityPolicyNoneUri), MessageSecurityMode::None}};
    /// The user identity tokens accepted, on every endpoint.
    std::vector<UserTokenPolicy> userTokenPolicies = {anonymousTokenPolicy()};

    [[nodiscard]] static UserTokenPolicy anonymousTokenPolicy();
    /// The security policy that protects a user token (password encryption, token
    /// signature) on a channel with `channelPolicyUri`: the token policy's own, else the
    /// channel's, else (None channel) Basic256Sha256, so that a password never travels in
    /// clear text.
    [[nodiscard]] static std::string_view tokenSecurityPolicy(const UserTokenPolicy& token,
                                                              std::string_view channelPolicyUri);
    [[nodiscard]] bool offers(std::string_view policyUri, MessageSecurityMode mode) const;

    /// "opc.tcp://host:port": the host the client used if it named one, else advertisedHost.
    [[nodiscard]] String endpointUrlFor(const std::string* clientUrl) const;
    [[nodiscard]] ApplicationDescription application(const String& endpointUrl) const;
    [[nodiscard]] std::vector<EndpointDescription> endpoints(const String& endpointUrl) const;
    /// This server's entry in a FindServers answer (its URL as the request or the client's
    /// Hello named it), or nothing when the request's serverUris leave it out.
    [[nodiscard]] std::optional<ApplicationDescription> findServersEntry(
        const FindServersRequest& req, const std::string* clientUrl) const;
};

}  // namespace skillcell::ua
