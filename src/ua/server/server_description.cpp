#include "ua/server/server_description.hpp"

#include <algorithm>

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

std::vector<EndpointDescription> ServerDescription::endpoints(const String& endpointUrl) const {
    EndpointDescription ep;
    ep.endpointUrl = endpointUrl;
    ep.server = application(endpointUrl);
    ep.serverCertificate = certificate;
    ep.securityMode = MessageSecurityMode::None;
    ep.securityPolicyUri = String(kSecurityPolicyNoneUri);
    UserTokenPolicy anonymous;
    anonymous.policyId = String(kAnonymousPolicyId);
    anonymous.tokenType = UserTokenType::Anonymous;
    ep.userIdentityTokens = {anonymous};
    ep.transportProfileUri = String(kTransportProfileUaTcp);
    ep.securityLevel = 0;
    return {ep};
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
