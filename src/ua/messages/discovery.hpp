#pragma once
// Discovery service set (OPC 10000-4, 5.4): FindServers, GetEndpoints.
#include "ua/messages/common.hpp"

namespace skillcell::ua {

struct ApplicationDescription {
    String applicationUri;
    String productUri;
    LocalizedText applicationName;
    ApplicationType applicationType = ApplicationType::Server;
    String gatewayServerUri;
    String discoveryProfileUri;
    std::vector<String> discoveryUrls;
    static auto tie(auto& s) {
        return std::tie(s.applicationUri, s.productUri, s.applicationName, s.applicationType,
                        s.gatewayServerUri, s.discoveryProfileUri, s.discoveryUrls);
    }
};

struct UserTokenPolicy {
    String policyId;
    UserTokenType tokenType = UserTokenType::Anonymous;
    String issuedTokenType;
    String issuerEndpointUrl;
    String securityPolicyUri;
    static auto tie(auto& s) {
        return std::tie(s.policyId, s.tokenType, s.issuedTokenType, s.issuerEndpointUrl,
                        s.securityPolicyUri);
    }
};

struct EndpointDescription {
    String endpointUrl;
    ApplicationDescription server;
    ByteString serverCertificate;
    MessageSecurityMode securityMode = MessageSecurityMode::None;
    String securityPolicyUri;
    std::vector<UserTokenPolicy> userIdentityTokens;
    String transportProfileUri;
    std::uint8_t securityLevel = 0;
    static auto tie(auto& s) {
        return std::tie(s.endpointUrl, s.server, s.serverCertificate, s.securityMode,
                        s.securityPolicyUri, s.userIdentityTokens, s.transportProfileUri,
                        s.securityLevel);
    }
};

struct GetEndpointsRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 428;
    RequestHeader requestHeader;
    String endpointUrl;
    std::vector<String> localeIds;
    std::vector<String> profileUris;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.endpointUrl, s.localeIds, s.profileUris);
    }
};

struct GetEndpointsResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 431;
    ResponseHeader responseHeader;
    std::vector<EndpointDescription> endpoints;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.endpoints); }
};

struct FindServersRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 422;
    RequestHeader requestHeader;
    String endpointUrl;
    std::vector<String> localeIds;
    std::vector<String> serverUris;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.endpointUrl, s.localeIds, s.serverUris);
    }
};

struct FindServersResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 425;
    ResponseHeader responseHeader;
    std::vector<ApplicationDescription> servers;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.servers); }
};

}  // namespace skillcell::ua
