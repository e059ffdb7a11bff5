#pragma once
// Session service set (OPC 10000-4, 5.6) and the user identity tokens (7.41).
#include "ua/messages/discovery.hpp"

namespace skillcell::ua {

struct SignedSoftwareCertificate {
    ByteString certificateData;
    ByteString signature;
    static auto tie(auto& s) { return std::tie(s.certificateData, s.signature); }
};

struct SignatureData {
    String algorithm;
    ByteString signature;
    static auto tie(auto& s) { return std::tie(s.algorithm, s.signature); }
};

struct CreateSessionRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 461;
    RequestHeader requestHeader;
    ApplicationDescription clientDescription;
    String serverUri;
    String endpointUrl;
    String sessionName;
    ByteString clientNonce;
    ByteString clientCertificate;
    double requestedSessionTimeout = 0;  // milliseconds
    std::uint32_t maxResponseMessageSize = 0;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.clientDescription, s.serverUri, s.endpointUrl,
                        s.sessionName, s.clientNonce, s.clientCertificate,
                        s.requestedSessionTimeout, s.maxResponseMessageSize);
    }
};

struct CreateSessionResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 464;
    ResponseHeader responseHeader;
    NodeId sessionId;
    NodeId authenticationToken;
    double revisedSessionTimeout = 0;
    ByteString serverNonce;
    ByteString serverCertificate;
    std::vector<EndpointDescription> serverEndpoints;
    std::vector<SignedSoftwareCertificate> serverSoftwareCertificates;
    SignatureData serverSignature;
    std::uint32_t maxRequestMessageSize = 0;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.sessionId, s.authenticationToken,
                        s.revisedSessionTimeout, s.serverNonce, s.serverCertificate,
                        s.serverEndpoints, s.serverSoftwareCertificates, s.serverSignature,
                        s.maxRequestMessageSize);
    }
};

struct ActivateSessionRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 467;
    RequestHeader requestHeader;
    SignatureData clientSignature;
    std::vector<SignedSoftwareCertificate> clientSoftwareCertificates;
    std::vector<String> localeIds;
    ExtensionObject userIdentityToken;
    SignatureData userTokenSignature;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.clientSignature, s.clientSoftwareCertificates,
                        s.localeIds, s.userIdentityToken, s.userTokenSignature);
    }
};

struct ActivateSessionResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 470;
    ResponseHeader responseHeader;
    ByteString serverNonce;
    std::vector<StatusCode> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.serverNonce, s.results, s.diagnosticInfos);
    }
};

struct CloseSessionRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 473;
    RequestHeader requestHeader;
    bool deleteSubscriptions = true;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.deleteSubscriptions); }
};

struct CloseSessionResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 476;
    ResponseHeader responseHeader;
    static auto tie(auto& s) { return std::tie(s.responseHeader); }
};

struct AnonymousIdentityToken {
    static constexpr std::uint32_t kBinaryEncodingId = 321;
    String policyId;
    static auto tie(auto& s) { return std::tie(s.policyId); }
};

struct UserNameIdentityToken {
    static constexpr std::uint32_t kBinaryEncodingId = 324;
    String policyId;
    String userName;
    ByteString password;
    String encryptionAlgorithm;
    static auto tie(auto& s) {
        return std::tie(s.policyId, s.userName, s.password, s.encryptionAlgorithm);
    }
};

struct X509IdentityToken {
    static constexpr std::uint32_t kBinaryEncodingId = 327;
    String policyId;
    ByteString certificateData;
    static auto tie(auto& s) { return std::tie(s.policyId, s.certificateData); }
};

}  // namespace skillcell::ua
