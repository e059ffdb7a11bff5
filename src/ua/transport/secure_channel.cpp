// UA Secure Conversation (OPC 10000-6, 6.7): chunking, reassembly, sequence numbers and
// security tokens. See secure_channel.hpp for the contract and README.md for the decisions
// taken where the specification leaves room.
#include "ua/transport/secure_channel.hpp"

#include <algorithm>
#include <limits>

#include "ua/crypto/primitives.hpp"
#include "ua/encoding/codec.hpp"

namespace skillcell::ua {

namespace {

/// Message header + SecureChannelId + TokenId.
constexpr std::size_t kSymmetricSecurityHeaderEnd = kMessageHeaderSize + 8;
/// OPC 10000-6, 6.7.2.4 (legacy sequence numbers): a sender may wrap only once it is past
/// UInt32Max - 1024, and the first number after the wrap is below 1024.
constexpr std::uint32_t kWrapThreshold = std::numeric_limits<std::uint32_t>::max() - 1024;
constexpr std::uint32_t kWrappedBelow = 1024;

bool isNonePolicy(const SecurityPolicy& p) {
    return p.uri() == kSecurityPolicyNoneUri;
}

bool isSecured(MessageSecurityMode mode) {
    return mode == MessageSecurityMode::Sign || mode == MessageSecurityMode::SignAndEncrypt;
}

std::chrono::milliseconds ms(std::uint64_t v) {
    return std::chrono::milliseconds(static_cast<std::chrono::milliseconds::rep>(v));
}

/// A token stays acceptable for 25% past its lifetime, so that messages secured just before
/// it expired survive network delays (OPC 10000-4, 5.5.2).
SteadyTime acceptableUntil(SteadyTime created, std::uint32_t lifetimeMs) {
    return created + ms(std::uint64_t{lifetimeMs} + std::uint64_t{lifetimeMs} / 4);
}

/// 0 means "no limit".
bool withinLimit(std::uint64_t value, std::uint32_t limit) {
    return limit == 0 || value <= limit;
}

std::size_t encodedLength(std::size_t bytes) {
    return 4 + bytes;
}  // Int32 prefix + bytes

}  // namespace

SecureChannel::SecureChannel(Role role, TransportLimits limits,
                             std::unique_ptr<SecurityPolicy> policy, SecureChannelConfig config)
    : role_(role), limits_(limits), policy_(std::move(policy)), config_(config) {
    // A channel without a policy would have nothing to call; None is the only safe default.
    if (!policy_) policy_ = std::make_unique<SecurityPolicyNone>();
    if (role_ == Role::Client && !isNonePolicy(*policy_)) {
        mode_ = config_.securityMode;
        policy_->setSecurityMode(mode_);
    }
}

SecureChannel::SecureChannel(TransportLimits limits, SecurityPolicySelector selector,
                             SecureChannelConfig config)
    : role_(Role::Server),
      limits_(limits),
      selector_(std::move(selector)),
      config_(std::move(config)) {}

// ---------------------------------------------------------------------------------------
// Receiving

Result<std::optional<ChannelMessage>> SecureChannel::receiveFrame(
    std::span<const std::uint8_t> frame, SteadyTime now) {
    lastAbort_.reset();
    if (frame.size() < kMessageHeaderSize) return status::BadDecodingError;
    // Checked against our receive buffer before anything is copied.
    const auto header =
        parseMessageHeader(frame.first<kMessageHeaderSize>(), limits_.receiveBufferSize);
    if (!header) return header.status();
    if (header->size != frame.size()) return status::BadDecodingError;
    const auto type = header->type;
    if (type != MessageType::OpenChannel && type != MessageType::Message &&
        type != MessageType::CloseChannel) {
        return status::BadTcpMessageTypeInvalid;
    }
    const bool asymmetric = type == MessageType::OpenChannel;

    BinaryReader r(frame.subspan(kMessageHeaderSize));
    const auto channelId = r.read<std::uint32_t>();
    const SymmetricKeys* keys = nullptr;
    if (asymmetric) {
        AsymmetricSecurityHeader security;
        decode(r, security.securityPolicyUri);
        decode(r, security.senderCertificate);
        decode(r, security.receiverCertificateThumbprint);
        if (!r.ok()) return status::BadDecodingError;
        if (!acceptsOpenChannelId(channelId)) return status::BadTcpSecureChannelUnknown;
        if (const auto s = acceptAsymmetricHeader(security); s.isBad()) return s;
    } else {
        const auto tokenId = r.read<std::uint32_t>();
        if (!r.ok()) return status::BadDecodingError;
        // No channel yet: MSG/CLO are not acceptable message types in this state.
        if (!current_) return status::BadTcpMessageTypeInvalid;
        if (channelId != channelId_) return status::BadTcpSecureChannelUnknown;
        auto tokenKeys = checkToken(tokenId, now);
        if (!tokenKeys) return tokenKeys.status();
        keys = *tokenKeys;
    }
    const std::size_t clearSize = kMessageHeaderSize + r.position();

    // Bounded by receiveBufferSize through parseMessageHeader above.
    std::vector<std::uint8_t> chunk(frame.begin(), frame.end());
    if (const auto s = policy_->unprotect(chunk, clearSize, keys); s.isBad()) return s;
    if (chunk.size() < clearSize) return status::BadSecurityChecksFailed;

    const auto payload = std::span<const std::uint8_t>(chunk).subspan(clearSize);
    BinaryReader seq(payload);
    const auto sequenceNumber = seq.read<std::uint32_t>();
    const auto requestId = seq.read<std::uint32_t>();
    if (!seq.ok()) return status::BadDecodingError;
    // Only after security is verified (OPC 10000-6, 6.7.6).
    if (const auto s = checkSequenceNumber(sequenceNumber); s.isBad()) return s;

    if (asymmetric && role_ == Role::Client) openResponseChannelId_ = channelId;
    return assemble(type, header->chunkType, requestId, payload.subspan(kSequenceHeaderSize));
}

bool SecureChannel::acceptsOpenChannelId(std::uint32_t channelId) const {
    if (role_ == Role::Client) {
        // The server assigns the id in its first response; after that it is fixed.
        return channelId_ == 0 || channelId == channelId_;
    }
    // A request may carry 0 (OPC 10000-6, 6.7.6); a non-zero id must be ours. 0 on an open
    // channel is let through so that openOrRenew can answer a second Issue properly.
    return channelId == 0 || (channelId_ != 0 && channelId == channelId_);
}

StatusCode SecureChannel::acceptAsymmetricHeader(const AsymmetricSecurityHeader& header) {
    if (!policy_) {
        // Server, first OPN: the client chooses the policy; the selector checks that we offer
        // it and trust the sender's certificate.
        if (!selector_) return status::BadSecurityPolicyRejected;
        auto chosen = selector_(header);
        if (!chosen) return chosen.status();
        policy_ = std::move(*chosen);
        if (!policy_) return status::BadSecurityPolicyRejected;
    }
    if (header.securityPolicyUri != policy_->uri()) return status::BadSecurityPolicyRejected;
    return policy_->checkAsymmetricHeader(header);
}

Result<const SymmetricKeys*> SecureChannel::checkToken(std::uint32_t tokenId, SteadyTime now) {
    if (previous_ && now > previous_->expiresAt) previous_.reset();
    if (tokenId == current_->tokenId) {
        if (now > acceptableUntil(currentCreated_, current_->revisedLifetime)) {
            return status::BadSecureChannelTokenUnknown;
        }
        // The peer has switched to the new token: the old one is done (server: OPC 10000-4,
        // 5.5.2; client: the server only switches once the client has).
        previous_.reset();
        return &currentKeys_.receiving;
    }
    if (previous_ && tokenId == previous_->token.tokenId) return &previous_->keys.receiving;
    return status::BadSecureChannelTokenUnknown;
}

StatusCode SecureChannel::checkSequenceNumber(std::uint32_t sequenceNumber) {
    if (lastReceivedSequenceNumber_) {
        const auto last = *lastReceivedSequenceNumber_;
        const bool next = sequenceNumber == static_cast<std::uint32_t>(last + 1);
        const bool wrapped = last > kWrapThreshold && sequenceNumber < kWrappedBelow;
        if (!next && !wrapped) return status::BadSequenceNumberInvalid;
    }
    // The first chunk on the channel sets the start: the sender chooses it.
    lastReceivedSequenceNumber_ = sequenceNumber;
    return status::Good;
}

Result<std::optional<ChannelMessage>> SecureChannel::assemble(MessageType type, ChunkType chunk,
                                                              std::uint32_t requestId,
                                                              std::span<const std::uint8_t> body) {
    // Chunks of one message are sent back to back (OPC 10000-6, 6.7.3); anything else in
    // between fails the RequestId check of 6.7.6.
    if (partial_ && (type != MessageType::Message || partial_->requestId != requestId)) {
        return status::BadSecurityChecksFailed;
    }

    if (chunk == ChunkType::Abort) {
        BinaryReader r(body);
        ChannelAbort abort;
        abort.requestId = requestId;
        decode(r, abort.error);
        decode(r, abort.reason);
        if (!r.ok() || r.remaining() != 0) return status::BadDecodingError;
        if (abort.reason.size() > kMaxReasonLength) abort.reason.clear();  // spec: ignore it
        partial_.reset();
        partialChunks_ = 0;
        lastAbort_ = std::move(abort);
        return std::optional<ChannelMessage>{};
    }

    if (!partial_) {
        partial_ = ChannelMessage{type, requestId, {}};
        partialChunks_ = 0;
    }
    ++partialChunks_;
    // Limits are on the decrypted body (OPC 10000-6, 7.1.2.3), checked before it grows.
    if (!withinLimit(partialChunks_, limits_.maxChunkCount) ||
        !withinLimit(std::uint64_t{partial_->body.size()} + body.size(), limits_.maxMessageSize)) {
        return status::BadTcpMessageTooLarge;
    }
    partial_->body.insert(partial_->body.end(), body.begin(), body.end());
    if (chunk == ChunkType::Intermediate) return std::optional<ChannelMessage>{};

    std::optional<ChannelMessage> done = std::move(partial_);
    partial_.reset();
    partialChunks_ = 0;
    return done;
}

// ---------------------------------------------------------------------------------------
// Sending

std::size_t SecureChannel::headerSize(MessageType type) const {
    if (type != MessageType::OpenChannel) return kSymmetricSecurityHeaderEnd + kSequenceHeaderSize;
    if (!policy_) return kMessageHeaderSize + 4 + 3 * encodedLength(0) + kSequenceHeaderSize;
    return kMessageHeaderSize + 4 + encodedLength(policy_->uri().size()) +
           encodedLength(policy_->localCertificate().size()) +
           encodedLength(policy_->remoteThumbprint().size()) + kSequenceHeaderSize;
}

std::uint32_t SecureChannel::sendingTokenId() const {
    // After a renewal the server keeps securing with the old token until the client has
    // used the new one (OPC 10000-4, 5.5.2); the client switches at once.
    if (role_ == Role::Server && previous_) return previous_->token.tokenId;
    return current_->tokenId;
}

const SymmetricKeys& SecureChannel::sendingKeys() const {
    if (role_ == Role::Server && previous_) return previous_->keys.sending;
    return currentKeys_.sending;
}

StatusCode SecureChannel::tooLarge() const {
    return role_ == Role::Server ? status::BadResponseTooLarge : status::BadRequestTooLarge;
}

Result<std::vector<std::vector<std::uint8_t>>> SecureChannel::encodeMessage(
    MessageType type, std::uint32_t requestId, std::span<const std::uint8_t> body) {
    if (type != MessageType::OpenChannel && type != MessageType::Message &&
        type != MessageType::CloseChannel) {
        return status::BadInvalidArgument;
    }
    if (type != MessageType::OpenChannel && !current_) return status::BadInvalidState;
    if (!policy_) return status::BadInvalidState;  // server before the client's first OPN
    const bool asymmetric = type == MessageType::OpenChannel;
    const auto maxBody = policy_->maxBodySize(limits_.sendBufferSize, headerSize(type), asymmetric);
    if (maxBody == 0) return tooLarge();  // headers alone fill the peer's buffer

    // Every limit is checked before a sequence number is spent, so a refused message leaves
    // the channel usable.
    if (!withinLimit(body.size(), limits_.sendMaxMessageSize)) return tooLarge();
    const std::size_t chunkCount = body.empty() ? 1 : (body.size() + maxBody - 1) / maxBody;
    if (type != MessageType::Message && chunkCount > 1) return tooLarge();
    if (!withinLimit(chunkCount, limits_.sendMaxChunkCount)) return tooLarge();

    std::vector<std::vector<std::uint8_t>> frames;
    frames.reserve(chunkCount);
    for (std::size_t i = 0; i < chunkCount; ++i) {
        const auto offset = i * maxBody;
        const auto piece = body.subspan(offset, std::min(maxBody, body.size() - offset));
        const auto chunk = i + 1 == chunkCount ? ChunkType::Final : ChunkType::Intermediate;
        auto frame = buildChunk(type, chunk, requestId, piece);
        if (!frame) return frame.status();
        frames.push_back(std::move(*frame));
    }
    return frames;
}

Result<std::vector<std::uint8_t>> SecureChannel::encodeAbort(std::uint32_t requestId,
                                                             StatusCode error,
                                                             std::string_view reason) {
    if (!current_ || !policy_) return status::BadInvalidState;
    const auto maxBody =
        policy_->maxBodySize(limits_.sendBufferSize, headerSize(MessageType::Message), false);
    const std::size_t fixed = 4 + 4;  // Error + reason length
    if (maxBody < fixed) return tooLarge();
    // An abort is a single chunk: the reason gives way if the buffer is small.
    reason = reason.substr(0, std::min(kMaxReasonLength, maxBody - fixed));
    std::vector<std::uint8_t> body;
    BinaryWriter w(body);
    encode(w, error);
    encode(w, String(reason));
    return buildChunk(MessageType::Message, ChunkType::Abort, requestId, body);
}

Result<std::vector<std::uint8_t>> SecureChannel::buildChunk(MessageType type, ChunkType chunk,
                                                            std::uint32_t requestId,
                                                            std::span<const std::uint8_t> body) {
    const bool asymmetric = type == MessageType::OpenChannel;
    std::vector<std::uint8_t> out;
    out.reserve(headerSize(type) + body.size());
    BinaryWriter w(out);
    writeMessageHeader(w, type, chunk);
    w.write(channelId_);  // 0 in a client's first OPN
    if (asymmetric) {
        encode(w, String(policy_->uri()));
        encode(w, ByteString(policy_->localCertificate()));
        encode(w, ByteString(policy_->remoteThumbprint()));
    } else {
        w.write(sendingTokenId());
    }
    const auto clearSize = w.size();
    // Starts at 1; uint32 arithmetic wraps UInt32Max to 0, which is below 1024 as
    // OPC 10000-6, 6.7.2.4 requires.
    w.write(++sendSequenceNumber_);
    w.write(requestId);
    w.writeBytes(body);
    finishFrame(w, 0);
    if (!w.ok()) return w.status();

    if (const auto s = policy_->protect(out, clearSize, asymmetric ? nullptr : &sendingKeys());
        s.isBad()) {
        return s;
    }
    // A policy that overruns its own maxBodySize is a bug, not something to send.
    if (out.size() > limits_.sendBufferSize) return status::BadInternalError;
    BinaryWriter patch(out);
    finishFrame(patch, 0);
    return out;
}

// ---------------------------------------------------------------------------------------
// Tokens

Result<OpenSecureChannelResponse> SecureChannel::openOrRenew(
    const OpenSecureChannelRequest& request, std::uint32_t channelId, SteadyTime now) {
    if (role_ != Role::Server) return status::BadInvalidState;
    switch (request.requestType) {
        case SecurityTokenRequestType::Issue:
            if (current_) return status::BadRequestTypeInvalid;
            if (channelId == 0) return status::BadInvalidArgument;  // 0 means "no channel"
            break;
        case SecurityTokenRequestType::Renew:
            if (!current_) return status::BadRequestTypeInvalid;
            break;
        default:
            return status::BadRequestTypeInvalid;
    }

    if (!policy_) return status::BadInvalidState;  // openOrRenew before any OPN chunk
    const auto mode = request.securityMode;
    if (!modeAccepted(mode)) return status::BadSecurityModeRejected;
    // A renewal keeps the mode the channel was opened with.
    if (current_ && mode != mode_) return status::BadSecurityModeRejected;
    const std::size_t nonceLength = policy_->nonceLength();
    if (nonceLength != 0 && request.clientNonce.bytes.size() != nonceLength) {
        return status::BadNonceInvalid;
    }

    const auto maxLifetime = std::max(config_.tokenLifetimeMs, config_.minTokenLifetimeMs);
    const auto lifetime =
        request.requestedLifetime == 0
            ? maxLifetime
            : std::clamp(request.requestedLifetime, config_.minTokenLifetimeMs, maxLifetime);

    ByteString serverNonce = policy_->newNonce();
    if (serverNonce.bytes.size() != nonceLength) return status::BadInternalError;
    // Before anything changes: a nonce that yields no keys leaves the channel as it was.
    auto keys = policy_->deriveKeys(request.clientNonce.bytes, serverNonce.bytes, false);
    if (!keys) return keys.status();
    ChannelSecurityToken token;
    token.channelId = current_ ? channelId_ : channelId;
    token.tokenId = nextTokenId_++;
    if (nextTokenId_ == 0) nextTokenId_ = 1;  // 0 is never a token id
    token.createdAt = DateTime::now();        // informational only; lifetimes run on `now`
    token.revisedLifetime = lifetime;

    if (current_) {
        // The old token stays valid until the client uses the new one or it expires.
        previous_ =
            TokenState{*current_, acceptableUntil(currentCreated_, current_->revisedLifetime),
                       std::move(currentKeys_)};
    } else {
        channelId_ = channelId;
        mode_ = mode;
        policy_->setSecurityMode(mode);
    }
    current_ = token;
    currentCreated_ = now;
    currentKeys_ = std::move(*keys);

    OpenSecureChannelResponse response;
    response.responseHeader.timestamp = token.createdAt;
    response.responseHeader.requestHandle = request.requestHeader.requestHandle;
    response.responseHeader.serviceResult = status::Good;
    response.serverProtocolVersion = kProtocolVersion;
    response.securityToken = token;
    response.serverNonce = std::move(serverNonce);
    return response;
}

bool SecureChannel::modeAccepted(MessageSecurityMode mode) const {
    if (config_.acceptsMode) return config_.acceptsMode(policy_->uri(), mode);
    return isNonePolicy(*policy_) ? mode == MessageSecurityMode::None : isSecured(mode);
}

OpenSecureChannelRequest SecureChannel::makeOpenRequest(SecurityTokenRequestType type) {
    ownNonce_ = policy_->newNonce();
    OpenSecureChannelRequest request;
    request.requestHeader.timestamp = DateTime::now();
    request.clientProtocolVersion = kProtocolVersion;
    request.requestType = type;
    request.securityMode =
        isNonePolicy(*policy_) ? MessageSecurityMode::None : config_.securityMode;
    request.requestedLifetime = config_.tokenLifetimeMs;
    request.clientNonce = ownNonce_;
    return request;
}

StatusCode SecureChannel::acceptOpenResponse(const OpenSecureChannelResponse& response,
                                             SteadyTime now) {
    if (role_ != Role::Client) return status::BadInvalidState;
    if (response.responseHeader.serviceResult.isBad()) {
        return response.responseHeader.serviceResult;
    }
    const auto& token = response.securityToken;
    if (token.channelId == 0) return status::BadSecureChannelIdInvalid;
    const std::size_t nonceLength = policy_->nonceLength();
    if (nonceLength != 0 && response.serverNonce.bytes.size() != nonceLength) {
        return status::BadNonceInvalid;
    }
    if (openResponseChannelId_ != 0 && token.channelId != openResponseChannelId_) {
        return status::BadSecureChannelIdInvalid;
    }
    if (current_ && token.channelId != channelId_) return status::BadSecureChannelIdInvalid;
    auto keys = policy_->deriveKeys(ownNonce_.bytes, response.serverNonce.bytes, true);
    if (!keys) return keys.status();
    if (current_) {
        // Server messages secured with the old token may still be on their way.
        previous_ =
            TokenState{*current_, acceptableUntil(currentCreated_, current_->revisedLifetime),
                       std::move(currentKeys_)};
    }
    channelId_ = token.channelId;
    current_ = token;
    currentCreated_ = now;
    currentKeys_ = std::move(*keys);
    return status::Good;
}

bool SecureChannel::renewalDue(SteadyTime now) const {
    if (!current_) return false;
    return now >= currentCreated_ + ms(std::uint64_t{current_->revisedLifetime} * 3 / 4);
}

}  // namespace skillcell::ua
