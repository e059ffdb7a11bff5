#pragma once
// SecureChannel: UA Secure Conversation (OPC 10000-6, 6.7) as a state machine on bytes.
//
// It is fed complete frames of type OPN/MSG/CLO (as read off the connection, header
// included) and a "now", and gives back complete messages; it turns message bodies into
// frames ready to write. It owns chunking and reassembly with the negotiated limits,
// sequence numbers, security tokens and their lifetimes, and the security policy. It does
// no I/O and reads no clock: the connection around it (server or client) does both, which
// is what lets tests drive it byte by byte with a fake clock.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "ua/messages/secure_channel.hpp"
#include "ua/transport/security_policy.hpp"
#include "ua/transport/tcp_framing.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

using SteadyTime = std::chrono::steady_clock::time_point;

/// One reassembled message: the service body starts with the request/response type's
/// encoding NodeId.
struct ChannelMessage {
    MessageType type = MessageType::Message;  // OpenChannel, Message or CloseChannel
    std::uint32_t requestId = 0;
    std::vector<std::uint8_t> body;
};

struct SecureChannelConfig {
    /// Server: the longest token lifetime granted; client: the lifetime asked for.
    std::uint32_t tokenLifetimeMs = 600'000;
    /// Server: lifetimes below this are raised to it.
    std::uint32_t minTokenLifetimeMs = 10'000;
};

class SecureChannel {
public:
    enum class Role : std::uint8_t { Client, Server };

    SecureChannel(Role role, TransportLimits limits, std::unique_ptr<SecurityPolicy> policy,
                  SecureChannelConfig config = {});

    /// Feeds one whole OPN/MSG/CLO frame. Returns the message once its final chunk arrived,
    /// std::nullopt after an intermediate chunk, or a StatusCode that is fatal for the
    /// channel (the connection sends ERR with it and closes): BadTcpMessageTooLarge when a
    /// message exceeds maxMessageSize/maxChunkCount, BadSequenceNumberInvalid,
    /// BadSecureChannelIdInvalid, BadSecureChannelTokenUnknown (unknown or expired token),
    /// BadTcpMessageTypeInvalid (MSG before OPN), BadDecodingError (malformed headers),
    /// BadSecurityChecksFailed. An abort chunk ('A') discards the message being
    /// reassembled and yields std::nullopt.
    [[nodiscard]] Result<std::optional<ChannelMessage>> receiveFrame(
        std::span<const std::uint8_t> frame, SteadyTime now);

    /// Splits `body` into frames no larger than the peer's receive buffer, each with the
    /// right security header and the next sequence number. BadResponseTooLarge (server) /
    /// BadRequestTooLarge (client) when the message would exceed the peer's limits.
    [[nodiscard]] Result<std::vector<std::vector<std::uint8_t>>> encodeMessage(
        MessageType type, std::uint32_t requestId, std::span<const std::uint8_t> body);

    /// Server: handles a decoded OpenSecureChannelRequest (Issue or Renew): assigns the
    /// channel id on Issue, creates a new token, and returns the response to send.
    /// BadRequestTypeInvalid for Renew before Issue or Issue twice,
    /// BadSecurityModeRejected for a mode the policy does not match.
    [[nodiscard]] Result<OpenSecureChannelResponse> openOrRenew(
        const OpenSecureChannelRequest& request, std::uint32_t channelId, SteadyTime now);

    /// Client: builds the request for a first open or a renewal.
    [[nodiscard]] OpenSecureChannelRequest makeOpenRequest(SecurityTokenRequestType type) const;
    /// Client: takes the server's answer; the new token is used for everything sent next.
    [[nodiscard]] StatusCode acceptOpenResponse(const OpenSecureChannelResponse& response,
                                                SteadyTime now);

    [[nodiscard]] std::uint32_t channelId() const { return channelId_; }
    [[nodiscard]] bool isOpen() const { return current_.has_value(); }
    [[nodiscard]] const TransportLimits& limits() const { return limits_; }
    /// The current token, if any (its revisedLifetime tells a client when to renew).
    [[nodiscard]] const std::optional<ChannelSecurityToken>& currentToken() const {
        return current_;
    }
    /// Client: true once 75% of the current token's lifetime has passed.
    [[nodiscard]] bool renewalDue(SteadyTime now) const;

private:
    struct TokenState {
        ChannelSecurityToken token;
        SteadyTime expiresAt;
    };

    Role role_;
    TransportLimits limits_;
    std::unique_ptr<SecurityPolicy> policy_;
    SecureChannelConfig config_;
    std::uint32_t channelId_ = 0;
    std::optional<ChannelSecurityToken> current_;
    SteadyTime currentCreated_{};
    std::optional<TokenState> previous_;  // valid until the peer uses the new one or it expires
    std::uint32_t nextTokenId_ = 1;
    std::uint32_t sendSequenceNumber_ = 0;
    std::optional<std::uint32_t> lastReceivedSequenceNumber_;

    // Reassembly of the message in progress.
    std::optional<ChannelMessage> partial_;
    std::uint32_t partialChunks_ = 0;
};

}  // namespace skillcell::ua
