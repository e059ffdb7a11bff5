// UA-TCP framing (OPC 10000-6, 7.1.2).
#include "ua/transport/tcp_framing.hpp"

#include <algorithm>
#include <optional>

namespace skillcell::ua {

namespace {

/// ERR and abort reasons, like endpoint URLs, are at most 4096 bytes (OPC 10000-6, 7.1.2.5).

struct TypeName {
    MessageType type;
    std::array<std::uint8_t, 3> ascii;
};

constexpr std::array<TypeName, 7> kTypeNames{{
    {MessageType::Hello, {'H', 'E', 'L'}},
    {MessageType::Acknowledge, {'A', 'C', 'K'}},
    {MessageType::Error, {'E', 'R', 'R'}},
    {MessageType::ReverseHello, {'R', 'H', 'E'}},
    {MessageType::Message, {'M', 'S', 'G'}},
    {MessageType::OpenChannel, {'O', 'P', 'N'}},
    {MessageType::CloseChannel, {'C', 'L', 'O'}},
}};

std::optional<MessageType> typeFromAscii(std::span<const std::uint8_t, 8> b) {
    for (const auto& t : kTypeNames) {
        if (b[0] == t.ascii[0] && b[1] == t.ascii[1] && b[2] == t.ascii[2]) return t.type;
    }
    return std::nullopt;
}

std::optional<ChunkType> chunkFromAscii(std::uint8_t c) {
    switch (c) {
        case 'F':
            return ChunkType::Final;
        case 'C':
            return ChunkType::Intermediate;
        case 'A':
            return ChunkType::Abort;
        default:
            return std::nullopt;
    }
}

std::uint8_t chunkAscii(ChunkType c) {
    switch (c) {
        case ChunkType::Intermediate:
            return 'C';
        case ChunkType::Abort:
            return 'A';
        case ChunkType::Final:
            break;
    }
    return 'F';
}

/// 0 means "no limit": the stricter of two limits is the smaller non-zero one.
std::uint32_t stricter(std::uint32_t a, std::uint32_t b) {
    if (a == 0) return b;
    if (b == 0) return a;
    return std::min(a, b);
}

template <class T>
std::vector<std::uint8_t> encodeFrame(MessageType type, const T& body) {
    std::vector<std::uint8_t> out;
    BinaryWriter w(out);
    writeMessageHeader(w, type, ChunkType::Final);
    encode(w, body);
    finishFrame(w, 0);
    return out;
}

/// Checks the header of a whole frame against its expected type and length, then decodes the
/// body; trailing bytes are malformed.
template <class T>
Result<T> decodeFrame(std::span<const std::uint8_t> frame, MessageType expected) {
    if (frame.size() < kMessageHeaderSize) return status::BadDecodingError;
    // The frame is already in memory: a size field that disagrees with it is malformed, not
    // too large.
    auto header = parseMessageHeader(frame.first<kMessageHeaderSize>(), UINT32_MAX);
    if (!header) return header.status();
    if (header->type != expected) return status::BadTcpMessageTypeInvalid;
    if (header->size != frame.size()) return status::BadDecodingError;
    T out{};
    const auto s = decodeFromBytes(frame.subspan(kMessageHeaderSize), out);
    if (s.isBad()) return s;
    return out;
}

}  // namespace

Result<MessageHeader> parseMessageHeader(std::span<const std::uint8_t, 8> bytes,
                                         std::uint32_t maxFrameSize) {
    const auto type = typeFromAscii(bytes);
    if (!type) return status::BadTcpMessageTypeInvalid;
    const auto chunk = chunkFromAscii(bytes[3]);
    if (!chunk) return status::BadTcpMessageTypeInvalid;
    if (*type != MessageType::Message && *chunk != ChunkType::Final) {
        return status::BadTcpMessageTypeInvalid;
    }
    BinaryReader r(bytes.subspan<4>());
    const auto size = r.read<std::uint32_t>();
    if (size < kMessageHeaderSize) return status::BadDecodingError;
    if (size > maxFrameSize) return status::BadTcpMessageTooLarge;
    return MessageHeader{*type, *chunk, size};
}

void writeMessageHeader(BinaryWriter& w, MessageType type, ChunkType chunk) {
    for (const auto& t : kTypeNames) {
        if (t.type == type) w.writeBytes(t.ascii);
    }
    w.write(chunkAscii(chunk));
    w.write(std::uint32_t{0});  // patched by finishFrame
}

void finishFrame(BinaryWriter& w, std::size_t frameStart) {
    w.patchUInt32(frameStart + 4, static_cast<std::uint32_t>(w.size() - frameStart));
}

Result<Negotiated> negotiateAsServer(const TransportLimits& own, const HelloMessage& hello) {
    if (hello.endpointUrl.size() > kMaxEndpointUrlLength) return status::BadTcpEndpointUrlInvalid;
    if (hello.receiveBufferSize < kMinBufferSize || hello.sendBufferSize < kMinBufferSize) {
        return status::BadConnectionRejected;
    }
    // A client may ask for a newer protocol version: the server answers with the one it
    // speaks (OPC 10000-6, 7.1.2.3), and version 0 is the lowest there is.
    Negotiated n;
    n.limits.receiveBufferSize = std::min(own.receiveBufferSize, hello.sendBufferSize);
    n.limits.sendBufferSize = std::min(own.sendBufferSize, hello.receiveBufferSize);
    // Our own configuration may be below the protocol minimum; refuse rather than announce it.
    if (n.limits.receiveBufferSize < kMinBufferSize || n.limits.sendBufferSize < kMinBufferSize) {
        return status::BadConnectionRejected;
    }
    n.limits.maxMessageSize = own.maxMessageSize;
    n.limits.maxChunkCount = own.maxChunkCount;
    n.limits.sendMaxMessageSize = stricter(own.sendMaxMessageSize, hello.maxMessageSize);
    n.limits.sendMaxChunkCount = stricter(own.sendMaxChunkCount, hello.maxChunkCount);

    n.ack.protocolVersion = kProtocolVersion;
    n.ack.receiveBufferSize = n.limits.receiveBufferSize;
    n.ack.sendBufferSize = n.limits.sendBufferSize;
    n.ack.maxMessageSize = n.limits.maxMessageSize;
    n.ack.maxChunkCount = n.limits.maxChunkCount;
    return n;
}

Result<TransportLimits> negotiateAsClient(const TransportLimits& own,
                                          const AcknowledgeMessage& ack) {
    // The server must use a version no higher than the one we asked for.
    if (ack.protocolVersion > kProtocolVersion) return status::BadProtocolVersionUnsupported;
    if (ack.receiveBufferSize < kMinBufferSize || ack.sendBufferSize < kMinBufferSize) {
        return status::BadConnectionRejected;
    }
    TransportLimits l;
    // The server shall not exceed what the Hello asked for; min() holds us to our own
    // buffers even if it does.
    l.receiveBufferSize = std::min(own.receiveBufferSize, ack.sendBufferSize);
    l.sendBufferSize = std::min(own.sendBufferSize, ack.receiveBufferSize);
    if (l.receiveBufferSize < kMinBufferSize || l.sendBufferSize < kMinBufferSize) {
        return status::BadConnectionRejected;
    }
    l.maxMessageSize = own.maxMessageSize;
    l.maxChunkCount = own.maxChunkCount;
    l.sendMaxMessageSize = stricter(own.sendMaxMessageSize, ack.maxMessageSize);
    l.sendMaxChunkCount = stricter(own.sendMaxChunkCount, ack.maxChunkCount);
    return l;
}

Result<HelloMessage> decodeHello(std::span<const std::uint8_t> frame) {
    return decodeFrame<HelloMessage>(frame, MessageType::Hello);
}

Result<AcknowledgeMessage> decodeAcknowledge(std::span<const std::uint8_t> frame) {
    return decodeFrame<AcknowledgeMessage>(frame, MessageType::Acknowledge);
}

Result<ErrorMessage> decodeError(std::span<const std::uint8_t> frame) {
    auto m = decodeFrame<ErrorMessage>(frame, MessageType::Error);
    if (m && m->reason.size() > kMaxReasonLength) m->reason.clear();
    return m;
}

std::vector<std::uint8_t> encodeHello(const HelloMessage& m) {
    return encodeFrame(MessageType::Hello, m);
}

std::vector<std::uint8_t> encodeAcknowledge(const AcknowledgeMessage& m) {
    return encodeFrame(MessageType::Acknowledge, m);
}

std::vector<std::uint8_t> encodeError(StatusCode error, std::string_view reason) {
    return encodeFrame(MessageType::Error,
                       ErrorMessage{error, String(reason.substr(0, kMaxReasonLength))});
}

}  // namespace skillcell::ua
