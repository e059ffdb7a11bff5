#include "ua/server/server_description.hpp"

#include <algorithm>

#include "ua/crypto/security_policy_profile.hpp"
#include "ua/transport/security_policy.hpp"

namespace skillcell::ua {

String ServerDescription::endpointUrlFor(const std::string* clientUrl) const {
    // Answer with the host the client already reached us by: it is the one name we know
    // works from where the client sits (hostname versus IP across hosts).
    std::string host = advertisedHost;
    if (clientUrl != nullptr && clientUrl->starts_with("opc.tcp://")) {
        std::string_view rest = std::string_view(*clientUrl).substr(10);
        const auto end = rest.find_first_of('/');
        rest = rest.substr(0, end);
        const auto colon = rest.rfind(':');
        const auto bracket = rest.rfind(']');
        if (colon != std::string_view::npos &&
            (bracket == std::string_view::npos || colon > bracket)) {
            rest = rest.substr(0, colon);
        }
        if (!rest.empty()) host = std::string(rest);
    }
    return "opc.tcp://" + host + ":" + std::to_string(port);
}

ApplicationDescription ServerDescription::application(const String& endpointUrl) const {
    ApplicationDescription app;
    app.applicationUri = applicationUri;
    app.productUri = productUri;
    app.applicationName = LocalizedText{"en", applicationName};
    app.applicationType = applicationType;
    app.discoveryUrls = {endpointUrl};
    return app;
}

UserTokenPolicy ServerDescription::anonymousTokenPolicy() {
    UserTokenPolicy anonymous;
    anonymous.policyId = String(kAnonymousPolicyId);
    anonymous.tokenType = UserTokenType::Anonymous;
    return anonymous;
}

std::string_view ServerDescription::tokenSecurityPolicy(const UserTokenPolicy& token,
                                                        std::string_view channelPolicyUri) {
    if (!token.securityPolicyUri.empty()) return token.securityPolicyUri;
    if (channelPolicyUri != kSecurityPolicyNoneUri && !channelPolicyUri.empty()) {
        return channelPolicyUri;
    }
    return crypto::kPolicyBasic256Sha256;
}

const ByteString& ServerDescription::certificateFor(std::string_view policyUri) const {
    const auto* profile = crypto::findSecurityPolicyProfile(policyUri);
    return profile != nullptr && profile->isEcc() && !eccCertificate.empty() ? eccCertificate
                                                                             : certificate;
}

bool ServerDescription::offers(std::string_view policyUri, MessageSecurityMode mode) const {
    return std::any_of(
        securityEndpoints.begin(), securityEndpoints.end(),
        [&](const SecurityEndpoint& e) { return e.policyUri == policyUri && e.mode == mode; });
}

std::vector<EndpointDescription> ServerDescription::endpoints(const String& endpointUrl) const {
    std::vector<EndpointDescription> out;
    for (const auto& offered : securityEndpoints) {
        EndpointDescription ep;
        ep.endpointUrl = endpointUrl;
        ep.server = application(endpointUrl);
        ep.serverCertificate = certificateFor(offered.policyUri);
        ep.securityMode = offered.mode;
        ep.securityPolicyUri = offered.policyUri;
        ep.userIdentityTokens = userTokenPolicies;
        if (offered.policyUri == kSecurityPolicyNoneUri) {
            // Without channel security a password or a token signature still needs a
            // policy of its own: the strongest one that encrypts with RSA-OAEP-SHA1, which
            // every client implements.
            for (auto& token : ep.userIdentityTokens) {
                if (token.tokenType != UserTokenType::Anonymous) {
                    token.securityPolicyUri = String(tokenSecurityPolicy(token, offered.policyUri));
                }
            }
        }
        ep.transportProfileUri = String(kTransportProfileUaTcp);
        const auto* profile = crypto::findSecurityPolicyProfile(offered.policyUri);
        if (profile != nullptr && profile->isEcc()) {
            // A password over ECC needs an EccEncryptedSecret (OPC 10000-4, 7.40.2.5), which
            // this stack does not implement: people log in on the RSA endpoints.
            std::erase_if(ep.userIdentityTokens, [](const UserTokenPolicy& token) {
                return token.tokenType == UserTokenType::UserName;
            });
        }
        // Clients that pick "the most secure endpoint" pick by this: None 0, then by the
        // policy's strength, SignAndEncrypt above Sign.
        ep.securityLevel = profile == nullptr
                               ? 0
                               : static_cast<std::uint8_t>(
                                     profile->strength * 10 +
                                     (offered.mode == MessageSecurityMode::SignAndEncrypt ? 5 : 0));
        out.push_back(std::move(ep));
    }
    return out;
}

std::optional<ApplicationDescription> ServerDescription::findServersEntry(
    const FindServersRequest& req, const std::string* clientUrl) const {
    if (!req.serverUris.empty() && std::find(req.serverUris.begin(), req.serverUris.end(),
                                             applicationUri) == req.serverUris.end()) {
        return std::nullopt;  // filtered out: an empty list, not an error
    }
    return application(endpointUrlFor(req.endpointUrl.empty() ? clientUrl : &req.endpointUrl));
}

}  // namespace skillcell::ua
