#pragma once
// Discovery service set (OPC 10000-4, 5.4): FindServers, GetEndpoints, and the services of a
// Local Discovery Server: RegisterServer, RegisterServer2, FindServersOnNetwork (OPC 10000-12).
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

/// A server's registration with a discovery server (OPC 10000-4, 7.32).
struct RegisteredServer {
    static constexpr std::uint32_t kBinaryEncodingId = 434;
    String serverUri;
    String productUri;
    std::vector<LocalizedText> serverNames;
    ApplicationType serverType = ApplicationType::Server;
    String gatewayServerUri;
    std::vector<String> discoveryUrls;
    String semaphoreFilePath;
    bool isOnline = true;
    static auto tie(auto& s) {
        return std::tie(s.serverUri, s.productUri, s.serverNames, s.serverType, s.gatewayServerUri,
                        s.discoveryUrls, s.semaphoreFilePath, s.isOnline);
    }
};

struct RegisterServerRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 437;
    RequestHeader requestHeader;
    RegisteredServer server;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.server); }
};

struct RegisterServerResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 440;
    ResponseHeader responseHeader;
    static auto tie(auto& s) { return std::tie(s.responseHeader); }
};

/// The only discovery configuration the standard defines: how an LDS-ME announces the
/// registered server by mDNS.
struct MdnsDiscoveryConfiguration {
    static constexpr std::uint32_t kBinaryEncodingId = 12901;
    String mdnsServerName;
    std::vector<String> serverCapabilities;
    static auto tie(auto& s) { return std::tie(s.mdnsServerName, s.serverCapabilities); }
};

struct RegisterServer2Request {
    static constexpr std::uint32_t kBinaryEncodingId = 12211;
    RequestHeader requestHeader;
    RegisteredServer server;
    std::vector<ExtensionObject> discoveryConfiguration;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.server, s.discoveryConfiguration);
    }
};

struct RegisterServer2Response {
    static constexpr std::uint32_t kBinaryEncodingId = 12212;
    ResponseHeader responseHeader;
    std::vector<StatusCode> configurationResults;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.configurationResults, s.diagnosticInfos);
    }
};

/// One server seen on the network by an LDS-ME (OPC 10000-4, 7.33).
struct ServerOnNetwork {
    static constexpr std::uint32_t kBinaryEncodingId = 12207;
    std::uint32_t recordId = 0;
    String serverName;
    String discoveryUrl;
    std::vector<String> serverCapabilities;
    static auto tie(auto& s) {
        return std::tie(s.recordId, s.serverName, s.discoveryUrl, s.serverCapabilities);
    }
};

struct FindServersOnNetworkRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 12208;
    RequestHeader requestHeader;
    std::uint32_t startingRecordId = 0;
    std::uint32_t maxRecordsToReturn = 0;
    std::vector<String> serverCapabilityFilter;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.startingRecordId, s.maxRecordsToReturn,
                        s.serverCapabilityFilter);
    }
};

struct FindServersOnNetworkResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 12209;
    ResponseHeader responseHeader;
    DateTime lastCounterResetTime;
    std::vector<ServerOnNetwork> servers;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.lastCounterResetTime, s.servers);
    }
};

}  // namespace skillcell::ua
