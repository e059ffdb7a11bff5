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
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
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
    /// Client: the mode asked for in OpenSecureChannel (None with policy None).
    MessageSecurityMode securityMode = MessageSecurityMode::None;
    /// Server: whether an endpoint offers this policy with this mode. Unset: None goes with
    /// mode None only, any other policy with Sign or SignAndEncrypt.
    std::function<bool(std::string_view policyUri, MessageSecurityMode mode)> acceptsMode;
};

/// Server: picks and builds the policy for a channel from its first OpenSecureChannel's
/// security header: an unknown or disabled policy gives BadSecurityPolicyRejected, a
/// certificate the server does not trust the validation's status (BadCertificateUntrusted,
/// BadCertificateTimeInvalid, ...). Runs before the chunk is decrypted.
using SecurityPolicySelector =
    std::function<Result<std::unique_ptr<SecurityPolicy>>(const AsymmetricSecurityHeader&)>;

/// An abort chunk ('A', OPC 10000-6, 6.7.3) as received: the message `requestId` was
/// discarded by its sender because of `error`.
struct ChannelAbort {
    std::uint32_t requestId = 0;
    StatusCode error;
    String reason;
};

class SecureChannel {
public:
    enum class Role : std::uint8_t { Client, Server };

    SecureChannel(Role role, TransportLimits limits, std::unique_ptr<SecurityPolicy> policy,
                  SecureChannelConfig config = {});
    /// A server channel whose policy the client chooses in its first OpenSecureChannel.
    SecureChannel(TransportLimits limits, SecurityPolicySelector selector,
                  SecureChannelConfig config = {});

    /// Feeds one whole OPN/MSG/CLO frame. Returns the message once its final chunk arrived,
    /// std::nullopt after an intermediate chunk, or a StatusCode that is fatal for the
    /// channel (the connection sends ERR with it and closes): BadTcpMessageTooLarge when a
    /// frame exceeds receiveBufferSize or a message maxMessageSize/maxChunkCount,
    /// BadSequenceNumberInvalid, BadTcpSecureChannelUnknown (a SecureChannelId that is not
    /// this channel's: the transport error OPC 10000-6, 7.1.5 names for it),
    /// BadSecureChannelTokenUnknown (unknown or expired token), BadTcpMessageTypeInvalid
    /// (MSG/CLO before OPN, or a frame type other than OPN/MSG/CLO),
    /// BadSecurityPolicyRejected (OPN for another policy), BadDecodingError (malformed
    /// headers), BadSecurityChecksFailed (failed unprotect, or a chunk of another message
    /// while one is being reassembled: OPC 10000-6, 6.7.6). An abort chunk ('A') discards
    /// the message being reassembled, yields std::nullopt and is reported by lastAbort().
    [[nodiscard]] Result<std::optional<ChannelMessage>> receiveFrame(
        std::span<const std::uint8_t> frame, SteadyTime now);

    /// Splits `body` into frames no larger than the peer's receive buffer, each with the
    /// right security header and the next sequence number. BadResponseTooLarge (server) /
    /// BadRequestTooLarge (client) when the message would exceed the peer's limits.
    /// OPN and CLO are always single-chunk (OPC 10000-6, 6.7.2.2). BadInvalidState for
    /// MSG/CLO before the channel has a token.
    [[nodiscard]] Result<std::vector<std::vector<std::uint8_t>>> encodeMessage(
        MessageType type, std::uint32_t requestId, std::span<const std::uint8_t> body);

    /// An abort chunk (MSG 'A') for `requestId`, for a sender that fails after it has sent
    /// some chunks of a message. The reason is cut to 4096 bytes. BadInvalidState before
    /// the channel has a token.
    [[nodiscard]] Result<std::vector<std::uint8_t>> encodeAbort(std::uint32_t requestId,
                                                                StatusCode error,
                                                                std::string_view reason);
    /// The abort chunk the last receiveFrame call consumed, if it consumed one.
    [[nodiscard]] const std::optional<ChannelAbort>& lastAbort() const { return lastAbort_; }

    /// Server: handles a decoded OpenSecureChannelRequest (Issue or Renew): assigns the
    /// channel id on Issue, creates a new token, and returns the response to send.
    /// BadRequestTypeInvalid for Renew before Issue or Issue twice,
    /// BadSecurityModeRejected for a mode the policy does not match (or a Renew that changes
    /// it), BadNonceInvalid for a client nonce of the wrong length. createdAt in the token
    /// is the only wall-clock value; lifetimes are measured on `now`.
    [[nodiscard]] Result<OpenSecureChannelResponse> openOrRenew(
        const OpenSecureChannelRequest& request, std::uint32_t channelId, SteadyTime now);

    /// Client: builds the request for a first open or a renewal, with a fresh nonce.
    [[nodiscard]] OpenSecureChannelRequest makeOpenRequest(SecurityTokenRequestType type);
    /// Client: takes the server's answer; the new token is used for everything sent next.
    /// The response's serviceResult if it is bad; BadSecureChannelIdInvalid when the token's
    /// channel id is 0, differs from the OPN header's, or changes on renewal;
    /// BadNonceInvalid for a server nonce of the wrong length.
    [[nodiscard]] StatusCode acceptOpenResponse(const OpenSecureChannelResponse& response,
                                                SteadyTime now);

    [[nodiscard]] std::uint32_t channelId() const { return channelId_; }
    /// The channel's policy; nullptr on a server channel before its first OpenSecureChannel.
    [[nodiscard]] const SecurityPolicy* policy() const { return policy_.get(); }
    /// The mode agreed in OpenSecureChannel (None before).
    [[nodiscard]] MessageSecurityMode securityMode() const { return mode_; }
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
        ChannelKeys keys;
    };

    [[nodiscard]] bool acceptsOpenChannelId(std::uint32_t channelId) const;
    [[nodiscard]] StatusCode acceptAsymmetricHeader(const AsymmetricSecurityHeader& header);
    [[nodiscard]] bool modeAccepted(MessageSecurityMode mode) const;
    /// The receiving keys of the token a chunk names, or the status that refuses it.
    [[nodiscard]] Result<const SymmetricKeys*> checkToken(std::uint32_t tokenId, SteadyTime now);
    [[nodiscard]] StatusCode checkSequenceNumber(std::uint32_t sequenceNumber);
    [[nodiscard]] Result<std::optional<ChannelMessage>> assemble(
        MessageType type, ChunkType chunk, std::uint32_t requestId,
        std::span<const std::uint8_t> body);
    [[nodiscard]] Result<std::vector<std::uint8_t>> buildChunk(MessageType type, ChunkType chunk,
                                                               std::uint32_t requestId,
                                                               std::span<const std::uint8_t> body);
    [[nodiscard]] std::size_t headerSize(MessageType type) const;
    [[nodiscard]] std::uint32_t sendingTokenId() const;
    [[nodiscard]] const SymmetricKeys& sendingKeys() const;
    [[nodiscard]] StatusCode tooLarge() const;

    Role role_;
    TransportLimits limits_;
    std::unique_ptr<SecurityPolicy> policy_;
    SecurityPolicySelector selector_;  // server: builds policy_ at the first OPN
    SecureChannelConfig config_;
    MessageSecurityMode mode_ = MessageSecurityMode::None;
    ChannelKeys currentKeys_;
    ByteString ownNonce_;  // client: the nonce of the OPN request in flight
    std::uint32_t channelId_ = 0;
    std::optional<ChannelSecurityToken> current_;
    SteadyTime currentCreated_{};
    std::optional<TokenState> previous_;  // valid until the peer uses the new one or it expires
    std::uint32_t nextTokenId_ = 1;
    std::uint32_t sendSequenceNumber_ = 0;
    std::optional<std::uint32_t> lastReceivedSequenceNumber_;
    std::uint32_t openResponseChannelId_ = 0;  // client: SecureChannelId of the last OPN frame
    std::optional<ChannelAbort> lastAbort_;

    // Reassembly of the message in progress.
    std::optional<ChannelMessage> partial_;
    std::uint32_t partialChunks_ = 0;
};

}  // namespace skillcell::ua
