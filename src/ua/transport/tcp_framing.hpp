#pragma once
// UA-TCP framing (OPC 10000-6, 7.1.2): the 8-byte message header, Hello, Acknowledge,
// Error, and buffer-size negotiation. Pure functions on bytes; no I/O.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "ua/encoding/codec.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

inline constexpr std::size_t kMessageHeaderSize = 8;
inline constexpr std::uint32_t kProtocolVersion = 0;
/// Smallest buffer a peer may announce (OPC 10000-6, 7.1.2.3).
inline constexpr std::uint32_t kMinBufferSize = 8192;
inline constexpr std::size_t kMaxEndpointUrlLength = 4096;
/// Longest reason an Error or CloseSecureChannel message may carry (OPC 10000-6, 7.1.2.5).
inline constexpr std::size_t kMaxReasonLength = 4096;
/// SequenceNumber and RequestId, in front of every chunk's body (OPC 10000-6, 6.7.2.4).
inline constexpr std::size_t kSequenceHeaderSize = 8;

enum class MessageType : std::uint8_t {
    Hello,         // "HEL"
    Acknowledge,   // "ACK"
    Error,         // "ERR"
    ReverseHello,  // "RHE"
    Message,       // "MSG"
    OpenChannel,   // "OPN"
    CloseChannel,  // "CLO"
};

enum class ChunkType : std::uint8_t { Final, Intermediate, Abort };  // 'F', 'C', 'A'

struct MessageHeader {
    MessageType type = MessageType::Hello;
    ChunkType chunkType = ChunkType::Final;
    std::uint32_t size = 0;  // the whole frame, header included
};

/// Parses and validates the 8-byte header. BadTcpMessageTypeInvalid for an unknown type or
/// chunk byte, or a chunk type other than 'F' on anything but MSG (OPC 10000-6, 6.7.2.2:
/// IsFinal is "always 'F' for other MessageTypes"); BadTcpMessageTooLarge when size exceeds
/// maxFrameSize; BadDecodingError when size is below the header's own size.
[[nodiscard]] Result<MessageHeader> parseMessageHeader(std::span<const std::uint8_t, 8> bytes,
                                                       std::uint32_t maxFrameSize);
/// Writes the header (size patched later by finishFrame).
void writeMessageHeader(BinaryWriter& w, MessageType type, ChunkType chunk);
/// Patches the size field of a frame that starts at `frameStart` in w's buffer.
void finishFrame(BinaryWriter& w, std::size_t frameStart);

/// Sizes negotiated by Hello/Acknowledge; 0 for the message size and chunk count limits means
/// "no limit". Each direction has its own limits: what we accept (announced to the peer)
/// and what we may send (bounded by what the peer announced).
struct TransportLimits {
    /// Largest chunk we accept / send.
    std::uint32_t receiveBufferSize = 65535;
    std::uint32_t sendBufferSize = 65535;
    /// Largest message body and most chunks per message we accept.
    std::uint32_t maxMessageSize = 16u * 1024 * 1024;
    std::uint32_t maxChunkCount = 512;
    /// Largest message body and most chunks per message we send: before negotiation our own
    /// cap, after it the stricter of that cap and the peer's announced receive limits.
    std::uint32_t sendMaxMessageSize = 16u * 1024 * 1024;
    std::uint32_t sendMaxChunkCount = 512;
};

struct HelloMessage {
    std::uint32_t protocolVersion = kProtocolVersion;
    std::uint32_t receiveBufferSize = 0;
    std::uint32_t sendBufferSize = 0;
    std::uint32_t maxMessageSize = 0;
    std::uint32_t maxChunkCount = 0;
    String endpointUrl;
    static auto tie(auto& s) {
        return std::tie(s.protocolVersion, s.receiveBufferSize, s.sendBufferSize, s.maxMessageSize,
                        s.maxChunkCount, s.endpointUrl);
    }
};

struct AcknowledgeMessage {
    std::uint32_t protocolVersion = kProtocolVersion;
    std::uint32_t receiveBufferSize = 0;
    std::uint32_t sendBufferSize = 0;
    std::uint32_t maxMessageSize = 0;
    std::uint32_t maxChunkCount = 0;
    static auto tie(auto& s) {
        return std::tie(s.protocolVersion, s.receiveBufferSize, s.sendBufferSize, s.maxMessageSize,
                        s.maxChunkCount);
    }
};

struct ErrorMessage {
    StatusCode error;
    String reason;
    static auto tie(auto& s) { return std::tie(s.error, s.reason); }
};

/// Server side: the limits to use on a connection given our own and the client's Hello, and
/// the Acknowledge to send. Fails (BadConnectionRejected/BadTcpEndpointUrlInvalid/...) for a
/// Hello below the minimum buffer sizes or with an over-long endpoint URL.
struct Negotiated {
    TransportLimits limits;  // from our point of view: what we may send / must accept
    AcknowledgeMessage ack;
};
[[nodiscard]] Result<Negotiated> negotiateAsServer(const TransportLimits& own,
                                                   const HelloMessage& hello);
/// Client side: the limits to use given what we asked for and the server's Acknowledge.
[[nodiscard]] Result<TransportLimits> negotiateAsClient(const TransportLimits& own,
                                                        const AcknowledgeMessage& ack);

/// Decodes a whole HEL/ACK/ERR frame (header included, as read off the connection).
/// BadTcpMessageTypeInvalid for a frame of another type, BadDecodingError when malformed or
/// when the size field does not match the frame. An ERR reason longer than 4096 bytes is
/// dropped (OPC 10000-6, 7.1.2.5: the client ignores it).
[[nodiscard]] Result<HelloMessage> decodeHello(std::span<const std::uint8_t> frame);
[[nodiscard]] Result<AcknowledgeMessage> decodeAcknowledge(std::span<const std::uint8_t> frame);
[[nodiscard]] Result<ErrorMessage> decodeError(std::span<const std::uint8_t> frame);

/// A whole frame (header included) for HEL, ACK or ERR. encodeError truncates the reason to
/// 4096 bytes.
[[nodiscard]] std::vector<std::uint8_t> encodeHello(const HelloMessage& m);
[[nodiscard]] std::vector<std::uint8_t> encodeAcknowledge(const AcknowledgeMessage& m);
[[nodiscard]] std::vector<std::uint8_t> encodeError(StatusCode error, std::string_view reason);

}  // namespace skillcell::ua
