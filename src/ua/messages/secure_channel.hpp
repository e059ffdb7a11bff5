#pragma once
// SecureChannel service set (OPC 10000-4, 5.5).
#include "ua/messages/common.hpp"

namespace skillcell::ua {

enum class SecurityTokenRequestType : std::int32_t { Issue = 0, Renew = 1 };

struct ChannelSecurityToken {
    std::uint32_t channelId = 0;
    std::uint32_t tokenId = 0;
    DateTime createdAt;
    std::uint32_t revisedLifetime = 0;  // milliseconds
    static auto tie(auto& s) {
        return std::tie(s.channelId, s.tokenId, s.createdAt, s.revisedLifetime);
    }
};

struct OpenSecureChannelRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 446;
    RequestHeader requestHeader;
    std::uint32_t clientProtocolVersion = 0;
    SecurityTokenRequestType requestType = SecurityTokenRequestType::Issue;
    MessageSecurityMode securityMode = MessageSecurityMode::None;
    ByteString clientNonce;
    std::uint32_t requestedLifetime = 0;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.clientProtocolVersion, s.requestType, s.securityMode,
                        s.clientNonce, s.requestedLifetime);
    }
};

struct OpenSecureChannelResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 449;
    ResponseHeader responseHeader;
    std::uint32_t serverProtocolVersion = 0;
    ChannelSecurityToken securityToken;
    ByteString serverNonce;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.serverProtocolVersion, s.securityToken, s.serverNonce);
    }
};

struct CloseSecureChannelRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 452;
    RequestHeader requestHeader;
    static auto tie(auto& s) { return std::tie(s.requestHeader); }
};

struct CloseSecureChannelResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 455;
    ResponseHeader responseHeader;
    static auto tie(auto& s) { return std::tie(s.responseHeader); }
};

}  // namespace skillcell::ua
