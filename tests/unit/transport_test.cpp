// UA-TCP framing and UA Secure Conversation: byte-exact frames, negotiation rules, and a
// client and a server SecureChannel talking to each other in memory with a fake clock.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "service_codec.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/transport/secure_channel.hpp"
#include "ua/transport/tcp_framing.hpp"

namespace transport_test {

using namespace skillcell::ua;
using Bytes = std::vector<std::uint8_t>;
using skillcell::test::decodeService;
using skillcell::test::encodeService;
using std::chrono::milliseconds;

namespace {

std::span<const std::uint8_t, 8> head(const Bytes& b) {
    return std::span(b).first<8>();
}

void putU32(Bytes& b, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
std::uint32_t getU32(const Bytes& b, std::size_t at) {
    return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
           static_cast<std::uint32_t>(b[at + 2]) << 16 |
           static_cast<std::uint32_t>(b[at + 3]) << 24;
}
void putString(Bytes& b, std::string_view s) {
    putU32(b, static_cast<std::uint32_t>(s.size()));
    b.insert(b.end(), s.begin(), s.end());
}
void patchSize(Bytes& b) {
    const auto n = static_cast<std::uint32_t>(b.size());
    for (int i = 0; i < 4; ++i) b[4 + i] = static_cast<std::uint8_t>(n >> (8 * i));
}

/// A hand-made symmetric frame (MSG/CLO): header, channel id, token id, sequence header, body.
Bytes symFrame(std::string_view typeAndChunk, std::uint32_t channelId, std::uint32_t tokenId,
               std::uint32_t seq, std::uint32_t requestId, const Bytes& body) {
    Bytes b(typeAndChunk.begin(), typeAndChunk.end());
    putU32(b, 0);
    putU32(b, channelId);
    putU32(b, tokenId);
    putU32(b, seq);
    putU32(b, requestId);
    b.insert(b.end(), body.begin(), body.end());
    patchSize(b);
    return b;
}

/// A hand-made OPN frame with the asymmetric header of `policyUri` (no certificates).
Bytes opnFrame(std::uint32_t channelId, std::uint32_t seq, std::uint32_t requestId,
               const Bytes& body, std::string_view policyUri = kSecurityPolicyNoneUri) {
    Bytes b{'O', 'P', 'N', 'F'};
    putU32(b, 0);
    putU32(b, channelId);
    putString(b, policyUri);
    putU32(b, 0xFFFFFFFF);  // SenderCertificate: null
    putU32(b, 0xFFFFFFFF);  // ReceiverCertificateThumbprint: null
    putU32(b, seq);
    putU32(b, requestId);
    b.insert(b.end(), body.begin(), body.end());
    patchSize(b);
    return b;
}

Bytes pattern(std::size_t n) {
    Bytes b(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(i * 31 + 7);
    return b;
}

TransportLimits smallLimits() {
    TransportLimits l;
    l.receiveBufferSize = kMinBufferSize;
    l.sendBufferSize = kMinBufferSize;
    return l;
}

constexpr std::uint32_t kChannelId = 7;
constexpr std::size_t kSymOverhead = 24;  // header 8 + channel 4 + token 4 + sequence 8

/// A test policy that signs with a 4-byte checksum: it shows that a policy which takes bytes
/// off each chunk plugs into the channel without the channel changing.
class ChecksumPolicy final : public SecurityPolicy {
public:
    static constexpr std::string_view kUri = "urn:skillcell:test:checksum";
    [[nodiscard]] std::string_view uri() const override { return kUri; }
    [[nodiscard]] std::size_t maxBodySize(std::size_t chunkSize, std::size_t headerSize,
                                          bool /*asymmetric*/) const override {
        return chunkSize > headerSize + 4 ? chunkSize - headerSize - 4 : 0;
    }
    [[nodiscard]] StatusCode protect(std::vector<std::uint8_t>& chunk, std::size_t headerSize,
                                     const SymmetricKeys* /*keys*/) override {
        putU32(chunk, sum(chunk, headerSize, chunk.size()));
        return status::Good;
    }
    [[nodiscard]] StatusCode unprotect(std::vector<std::uint8_t>& chunk, std::size_t headerSize,
                                       const SymmetricKeys* /*keys*/) override {
        if (chunk.size() < headerSize + 4) return status::BadSecurityChecksFailed;
        const auto end = chunk.size() - 4;
        if (getU32(chunk, end) != sum(chunk, headerSize, end)) {
            return status::BadSecurityChecksFailed;
        }
        chunk.resize(end);
        return status::Good;
    }

private:
    static std::uint32_t sum(const Bytes& b, std::size_t from, std::size_t to) {
        std::uint32_t s = 0x5A5A;
        for (std::size_t i = from; i < to; ++i) s = s * 33 + b[i];
        return s;
    }
};

/// A client and a server channel wired back to back; `t0` is the fake clock's origin.
struct ChannelPair {
    SecureChannel client;
    SecureChannel server;
    SteadyTime t0{std::chrono::hours(1)};

    explicit ChannelPair(TransportLimits clientLimits = {}, TransportLimits serverLimits = {},
                         SecureChannelConfig clientConfig = {},
                         SecureChannelConfig serverConfig = {})
        : client(SecureChannel::Role::Client, clientLimits, std::make_unique<SecurityPolicyNone>(),
                 clientConfig),
          server(SecureChannel::Role::Server, serverLimits, std::make_unique<SecurityPolicyNone>(),
                 serverConfig) {}

    ChannelPair(std::unique_ptr<SecurityPolicy> clientPolicy,
                std::unique_ptr<SecurityPolicy> serverPolicy, SecureChannelConfig config)
        : client(SecureChannel::Role::Client, {}, std::move(clientPolicy), config),
          server(SecureChannel::Role::Server, {}, std::move(serverPolicy), config) {}

    /// Delivers every frame to `to`; returns the message from the last one.
    static ChannelMessage deliver(SecureChannel& to, const std::vector<Bytes>& frames,
                                  SteadyTime now) {
        std::optional<ChannelMessage> got;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            auto r = to.receiveFrame(frames[i], now);
            EXPECT_TRUE(r.ok()) << statusName(r.status());
            if (!r.ok()) return {};
            EXPECT_EQ(r->has_value(), i + 1 == frames.size());
            got = std::move(*r);
        }
        return got ? std::move(*got) : ChannelMessage{};
    }

    /// One OpenSecureChannel round trip (Issue or Renew) at `now`; the client accepts.
    OpenSecureChannelResponse handshake(SecurityTokenRequestType type, SteadyTime now,
                                        std::uint32_t requestId = 1) {
        auto response = serverSide(type, now, requestId);
        EXPECT_EQ(client.acceptOpenResponse(response, now), status::Good);
        return response;
    }

    /// The request goes to the server, the response comes back, not yet accepted.
    OpenSecureChannelResponse serverSide(SecurityTokenRequestType type, SteadyTime now,
                                         std::uint32_t requestId = 1) {
        auto frames = client.encodeMessage(MessageType::OpenChannel, requestId,
                                           encodeService(client.makeOpenRequest(type)));
        EXPECT_TRUE(frames.ok());
        auto request = deliver(server, *frames, now);
        EXPECT_EQ(request.type, MessageType::OpenChannel);
        EXPECT_EQ(request.requestId, requestId);
        auto decoded = decodeService<OpenSecureChannelRequest>(request.body);
        auto response = server.openOrRenew(decoded, kChannelId, now);
        EXPECT_TRUE(response.ok()) << statusName(response.status());
        auto back =
            server.encodeMessage(MessageType::OpenChannel, requestId, encodeService(*response));
        EXPECT_TRUE(back.ok());
        auto reply = deliver(client, *back, now);
        EXPECT_EQ(reply.type, MessageType::OpenChannel);
        return decodeService<OpenSecureChannelResponse>(reply.body);
    }

    void open() { handshake(SecurityTokenRequestType::Issue, t0); }

    /// Sends `body` from `from` to `to` and checks it arrives whole.
    static void roundTrip(SecureChannel& from, SecureChannel& to, const Bytes& body, SteadyTime now,
                          std::uint32_t requestId = 5) {
        auto frames = from.encodeMessage(MessageType::Message, requestId, body);
        ASSERT_TRUE(frames.ok()) << statusName(frames.status());
        auto m = deliver(to, *frames, now);
        EXPECT_EQ(m.type, MessageType::Message);
        EXPECT_EQ(m.requestId, requestId);
        EXPECT_EQ(m.body, body);
    }
};

}  // namespace

// =======================================================================================
// Message header

TEST(TcpFraming, ParsesEveryMessageType) {
    const std::pair<const char*, MessageType> cases[] = {
        {"HELF", MessageType::Hello},        {"ACKF", MessageType::Acknowledge},
        {"ERRF", MessageType::Error},        {"RHEF", MessageType::ReverseHello},
        {"MSGF", MessageType::Message},      {"OPNF", MessageType::OpenChannel},
        {"CLOF", MessageType::CloseChannel},
    };
    for (const auto& [ascii, type] : cases) {
        Bytes b(ascii, ascii + 4);
        putU32(b, 0x1234);
        auto h = parseMessageHeader(head(b), 0x10000);
        ASSERT_TRUE(h.ok()) << ascii;
        EXPECT_EQ(h->type, type);
        EXPECT_EQ(h->chunkType, ChunkType::Final);
        EXPECT_EQ(h->size, 0x1234u);
    }
}

TEST(TcpFraming, ChunkTypes) {
    auto parse = [](const char* ascii) {
        Bytes b(ascii, ascii + 4);
        putU32(b, 100);
        return parseMessageHeader(head(b), 1000);
    };
    EXPECT_EQ(parse("MSGC")->chunkType, ChunkType::Intermediate);
    EXPECT_EQ(parse("MSGA")->chunkType, ChunkType::Abort);
    // Only MSG may be chunked or aborted (OPC 10000-6, 6.7.2.2 and 7.1.2.2).
    for (const char* bad : {"HELC", "ACKA", "ERRC", "RHEA", "OPNC", "OPNA", "CLOC", "CLOA", "MSGX",
                            "MSG\0", "MSGf"}) {
        EXPECT_EQ(parse(bad).status(), status::BadTcpMessageTypeInvalid) << bad;
    }
}

TEST(TcpFraming, RejectsUnknownTypeBytes) {
    for (const char* bad : {"XYZF", "helF", "MSFF", "OPMF", "\0\0\0F", "HE F"}) {
        Bytes b(bad, bad + 4);
        putU32(b, 100);
        EXPECT_EQ(parseMessageHeader(head(b), 1000).status(), status::BadTcpMessageTypeInvalid)
            << bad;
    }
}

TEST(TcpFraming, SizeBounds) {
    auto parse = [](std::uint32_t size, std::uint32_t max) {
        Bytes b{'M', 'S', 'G', 'F'};
        putU32(b, size);
        return parseMessageHeader(head(b), max);
    };
    EXPECT_EQ(parse(0, 1000).status(), status::BadDecodingError);
    EXPECT_EQ(parse(7, 1000).status(), status::BadDecodingError);
    EXPECT_EQ(parse(8, 1000)->size, 8u);
    EXPECT_EQ(parse(1000, 1000)->size, 1000u);
    EXPECT_EQ(parse(1001, 1000).status(), status::BadTcpMessageTooLarge);
    // A 4 GB claim is refused from the header alone, before anything is allocated.
    EXPECT_EQ(parse(0xFFFFFFFF, 65535).status(), status::BadTcpMessageTooLarge);
}

TEST(TcpFraming, WritesHeaderAndPatchesSize) {
    Bytes out{0xEE};  // a frame need not start at offset 0
    BinaryWriter w(out);
    writeMessageHeader(w, MessageType::Message, ChunkType::Intermediate);
    w.write(std::uint16_t{0xBEEF});
    finishFrame(w, 1);
    EXPECT_EQ(out, (Bytes{0xEE, 'M', 'S', 'G', 'C', 10, 0, 0, 0, 0xEF, 0xBE}));

    Bytes clo;
    BinaryWriter w2(clo);
    writeMessageHeader(w2, MessageType::CloseChannel, ChunkType::Final);
    finishFrame(w2, 0);
    EXPECT_EQ(clo, (Bytes{'C', 'L', 'O', 'F', 8, 0, 0, 0}));
    Bytes abort;
    BinaryWriter w3(abort);
    writeMessageHeader(w3, MessageType::Message, ChunkType::Abort);
    finishFrame(w3, 0);
    EXPECT_EQ(abort, (Bytes{'M', 'S', 'G', 'A', 8, 0, 0, 0}));
}

// =======================================================================================
// Hello / Acknowledge / Error

TEST(TcpFraming, EncodesHelloByteExact) {
    HelloMessage h;
    h.protocolVersion = 0;
    h.receiveBufferSize = 0x00010000;
    h.sendBufferSize = 0x00002000;
    h.maxMessageSize = 0x01000000;
    h.maxChunkCount = 0;
    h.endpointUrl = "opc.tcp://h:1";
    const Bytes expected{'H',  'E',  'L',  'F',  45,  0,   0,   0,  // header, size 45
                         0,    0,    0,    0,                       // ProtocolVersion
                         0x00, 0x00, 0x01, 0x00,                    // ReceiveBufferSize 65536
                         0x00, 0x20, 0x00, 0x00,                    // SendBufferSize 8192
                         0x00, 0x00, 0x00, 0x01,                    // MaxMessageSize 16 MiB
                         0,    0,    0,    0,                       // MaxChunkCount: no limit
                         13,   0,    0,    0,    'o', 'p', 'c', '.', 't',
                         'c',  'p',  ':',  '/',  '/', 'h', ':', '1'};
    EXPECT_EQ(encodeHello(h), expected);

    auto decoded = decodeHello(expected);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(decoded->receiveBufferSize, 0x10000u);
    EXPECT_EQ(decoded->sendBufferSize, 0x2000u);
    EXPECT_EQ(decoded->maxMessageSize, 0x1000000u);
    EXPECT_EQ(decoded->maxChunkCount, 0u);
    EXPECT_EQ(decoded->endpointUrl, "opc.tcp://h:1");
}

TEST(TcpFraming, EncodesAcknowledgeByteExact) {
    AcknowledgeMessage a{0, 8192, 65535, 0, 512};
    const Bytes expected{'A',  'C',  'K', 'F', 28,   0,    0, 0,  // header, size 28
                         0,    0,    0,   0,   0x00, 0x20, 0, 0,  // version, receive 8192
                         0xFF, 0xFF, 0,   0,   0,    0,    0, 0,  // send 65535, max size 0
                         0x00, 0x02, 0,   0};                     // chunk count 512
    EXPECT_EQ(encodeAcknowledge(a), expected);
    auto decoded = decodeAcknowledge(expected);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(decoded->receiveBufferSize, 8192u);
    EXPECT_EQ(decoded->sendBufferSize, 65535u);
    EXPECT_EQ(decoded->maxChunkCount, 512u);
}

TEST(TcpFraming, EncodesErrorByteExact) {
    const Bytes expected{'E',  'R',  'R',  'F',  19,  0,   0,  0,  // header, size 19
                         0x00, 0x00, 0x80, 0x80,                   // BadTcpMessageTooLarge
                         3,    0,    0,    0,    'b', 'i', 'g'};
    EXPECT_EQ(encodeError(status::BadTcpMessageTooLarge, "big"), expected);
    auto decoded = decodeError(expected);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(decoded->error, status::BadTcpMessageTooLarge);
    EXPECT_EQ(decoded->reason, "big");

    // The reason is capped at 4096 bytes when sent and ignored beyond that when received.
    const auto longFrame = encodeError(status::BadTimeout, std::string(5000, 'x'));
    EXPECT_EQ(longFrame.size(), 8u + 4 + 4 + 4096);
    EXPECT_EQ(decodeError(longFrame)->reason.size(), 4096u);
    Bytes tooLong{'E', 'R', 'R', 'F', 0, 0, 0, 0};
    putU32(tooLong, status::BadTimeout.code);
    putString(tooLong, std::string(4097, 'y'));
    patchSize(tooLong);
    auto ignored = decodeError(tooLong);
    ASSERT_TRUE(ignored.ok());
    EXPECT_EQ(ignored->error, status::BadTimeout);
    EXPECT_TRUE(ignored->reason.empty());
}

TEST(TcpFraming, DecodeRejectsMalformedFrames) {
    const auto hello = encodeHello(HelloMessage{0, 8192, 8192, 0, 0, "opc.tcp://x"});
    EXPECT_EQ(decodeAcknowledge(hello).status(), status::BadTcpMessageTypeInvalid);
    EXPECT_EQ(decodeHello(Bytes(hello.begin(), hello.begin() + 5)).status(),
              status::BadDecodingError);
    // Truncated: the size field claims more than there is.
    EXPECT_EQ(decodeHello(Bytes(hello.begin(), hello.end() - 1)).status(),
              status::BadDecodingError);
    // Trailing bytes inside the frame.
    Bytes trailing = hello;
    trailing.push_back(0);
    patchSize(trailing);
    EXPECT_EQ(decodeHello(trailing).status(), status::BadDecodingError);
    // A string length beyond the frame.
    Bytes badUrl = hello;
    badUrl[28] = 0xFF;
    badUrl[29] = 0x00;
    EXPECT_EQ(decodeHello(badUrl).status(), status::BadDecodingError);
    // Too short a body.
    Bytes ack{'A', 'C', 'K', 'F', 12, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(decodeAcknowledge(ack).status(), status::BadDecodingError);
}

// =======================================================================================
// Negotiation

TEST(Negotiation, ServerTakesTheSmallerBuffers) {
    TransportLimits own;
    own.receiveBufferSize = 65536;
    own.sendBufferSize = 32768;
    own.maxMessageSize = 1'000'000;
    own.maxChunkCount = 100;
    own.sendMaxMessageSize = 2'000'000;
    own.sendMaxChunkCount = 0;
    HelloMessage hello{0, 16384, 20000, 500'000, 50, "opc.tcp://x:4840"};

    auto n = negotiateAsServer(own, hello);
    ASSERT_TRUE(n.ok());
    // What we accept is bounded by what the client sends, and what we send by what it accepts.
    EXPECT_EQ(n->limits.receiveBufferSize, 20000u);
    EXPECT_EQ(n->limits.sendBufferSize, 16384u);
    // Receive limits stay ours; send limits are the stricter of ours and the client's.
    EXPECT_EQ(n->limits.maxMessageSize, 1'000'000u);
    EXPECT_EQ(n->limits.maxChunkCount, 100u);
    EXPECT_EQ(n->limits.sendMaxMessageSize, 500'000u);
    EXPECT_EQ(n->limits.sendMaxChunkCount, 50u);
    EXPECT_EQ(n->ack.protocolVersion, 0u);
    EXPECT_EQ(n->ack.receiveBufferSize, 20000u);
    EXPECT_EQ(n->ack.sendBufferSize, 16384u);
    EXPECT_EQ(n->ack.maxMessageSize, 1'000'000u);
    EXPECT_EQ(n->ack.maxChunkCount, 100u);
}

TEST(Negotiation, ZeroMeansNoLimit) {
    TransportLimits own;
    own.sendMaxMessageSize = 0;
    own.sendMaxChunkCount = 300;
    HelloMessage hello{0, 65535, 65535, 0, 0, ""};
    auto n = negotiateAsServer(own, hello);
    ASSERT_TRUE(n.ok());
    EXPECT_EQ(n->limits.sendMaxMessageSize, 0u);  // neither side limits it
    EXPECT_EQ(n->limits.sendMaxChunkCount, 300u);
    hello.maxMessageSize = 70'000;
    EXPECT_EQ(negotiateAsServer(own, hello)->limits.sendMaxMessageSize, 70'000u);
}

TEST(Negotiation, ServerAnswersWithItsOwnVersion) {
    HelloMessage hello{7, 65535, 65535, 0, 0, "opc.tcp://x"};
    auto n = negotiateAsServer({}, hello);
    ASSERT_TRUE(n.ok());
    EXPECT_EQ(n->ack.protocolVersion, kProtocolVersion);
}

TEST(Negotiation, ServerRejectsSmallBuffersAndLongUrls) {
    TransportLimits own;
    HelloMessage hello{0, 8191, 65535, 0, 0, "opc.tcp://x"};
    EXPECT_EQ(negotiateAsServer(own, hello).status(), status::BadConnectionRejected);
    hello = HelloMessage{0, 65535, 8191, 0, 0, "opc.tcp://x"};
    EXPECT_EQ(negotiateAsServer(own, hello).status(), status::BadConnectionRejected);
    hello = HelloMessage{0, 8192, 8192, 0, 0, "opc.tcp://x"};
    EXPECT_TRUE(negotiateAsServer(own, hello).ok());
    // Our own configuration below the minimum is refused rather than announced.
    TransportLimits tiny;
    tiny.receiveBufferSize = 4096;
    EXPECT_EQ(negotiateAsServer(tiny, hello).status(), status::BadConnectionRejected);

    hello.endpointUrl = std::string(4096, 'u');
    EXPECT_TRUE(negotiateAsServer(own, hello).ok());
    hello.endpointUrl = std::string(4097, 'u');
    EXPECT_EQ(negotiateAsServer(own, hello).status(), status::BadTcpEndpointUrlInvalid);
}

TEST(Negotiation, ClientSide) {
    TransportLimits own;
    own.receiveBufferSize = 65536;
    own.sendBufferSize = 65536;
    own.maxMessageSize = 4'000'000;
    own.maxChunkCount = 0;
    own.sendMaxMessageSize = 0;
    own.sendMaxChunkCount = 64;
    AcknowledgeMessage ack{0, 16384, 32768, 1'000'000, 0};
    auto l = negotiateAsClient(own, ack);
    ASSERT_TRUE(l.ok());
    EXPECT_EQ(l->receiveBufferSize, 32768u);  // the server sends at most 32768
    EXPECT_EQ(l->sendBufferSize, 16384u);     // the server receives at most 16384
    EXPECT_EQ(l->maxMessageSize, 4'000'000u);
    EXPECT_EQ(l->maxChunkCount, 0u);
    EXPECT_EQ(l->sendMaxMessageSize, 1'000'000u);
    EXPECT_EQ(l->sendMaxChunkCount, 64u);

    // A server may not exceed what the Hello asked for; we hold it to our buffers anyway.
    ack = AcknowledgeMessage{0, 1'000'000, 1'000'000, 0, 0};
    EXPECT_EQ(negotiateAsClient(own, ack)->sendBufferSize, 65536u);
    EXPECT_EQ(negotiateAsClient(own, ack)->receiveBufferSize, 65536u);

    ack = AcknowledgeMessage{1, 16384, 16384, 0, 0};
    EXPECT_EQ(negotiateAsClient(own, ack).status(), status::BadProtocolVersionUnsupported);
    ack = AcknowledgeMessage{0, 8191, 16384, 0, 0};
    EXPECT_EQ(negotiateAsClient(own, ack).status(), status::BadConnectionRejected);
    ack = AcknowledgeMessage{0, 16384, 100, 0, 0};
    EXPECT_EQ(negotiateAsClient(own, ack).status(), status::BadConnectionRejected);
}

TEST(Negotiation, HelloAckRoundTripFeedsBothChannels) {
    TransportLimits clientOwn = smallLimits();
    clientOwn.maxMessageSize = 50'000;
    HelloMessage hello{0,
                       clientOwn.receiveBufferSize,
                       clientOwn.sendBufferSize,
                       clientOwn.maxMessageSize,
                       clientOwn.maxChunkCount,
                       "opc.tcp://x"};
    auto server = negotiateAsServer({}, *decodeHello(encodeHello(hello)));
    ASSERT_TRUE(server.ok());
    auto client = negotiateAsClient(clientOwn, *decodeAcknowledge(encodeAcknowledge(server->ack)));
    ASSERT_TRUE(client.ok());
    EXPECT_EQ(server->limits.sendBufferSize, client->receiveBufferSize);
    EXPECT_EQ(server->limits.receiveBufferSize, client->sendBufferSize);
    EXPECT_EQ(server->limits.sendMaxMessageSize, 50'000u);
    EXPECT_EQ(client->sendMaxMessageSize, server->limits.maxMessageSize);
}

// =======================================================================================
// SecureChannel: opening

TEST(SecureChannel, OpensInMemory) {
    ChannelPair p;
    EXPECT_FALSE(p.client.isOpen());
    EXPECT_FALSE(p.server.isOpen());
    const auto response = p.handshake(SecurityTokenRequestType::Issue, p.t0);
    EXPECT_TRUE(p.client.isOpen());
    EXPECT_TRUE(p.server.isOpen());
    EXPECT_EQ(p.client.channelId(), kChannelId);
    EXPECT_EQ(p.server.channelId(), kChannelId);
    EXPECT_EQ(response.securityToken.channelId, kChannelId);
    EXPECT_EQ(response.securityToken.tokenId, 1u);
    EXPECT_EQ(response.securityToken.revisedLifetime, 600'000u);
    EXPECT_EQ(response.serverProtocolVersion, 0u);
    EXPECT_EQ(p.client.currentToken()->tokenId, 1u);
    EXPECT_EQ(p.server.currentToken()->tokenId, 1u);
}

TEST(SecureChannel, OpenRequestFrameLayout) {
    SecureChannel client(SecureChannel::Role::Client, {}, std::make_unique<SecurityPolicyNone>());
    const Bytes body{0xAB, 0xCD};
    auto frames = client.encodeMessage(MessageType::OpenChannel, 9, body);
    ASSERT_TRUE(frames.ok());
    ASSERT_EQ(frames->size(), 1u);
    const Bytes expected = opnFrame(0, 1, 9, body);
    EXPECT_EQ(frames->front(), expected);
    EXPECT_EQ(expected.size(), 8u + 4 + 4 + 47 + 4 + 4 + 8 + 2);
}

TEST(SecureChannel, MessageFrameLayoutAndSequenceNumbers) {
    ChannelPair p;
    p.open();  // the client's OPN used sequence number 1, the server's response too
    auto frames = p.client.encodeMessage(MessageType::Message, 5, Bytes{0xAA});
    ASSERT_TRUE(frames.ok());
    ASSERT_EQ(frames->size(), 1u);
    EXPECT_EQ(frames->front(), (Bytes{'M', 'S', 'G', 'F', 25, 0, 0, 0,  // header
                                      7,   0,   0,   0,                 // SecureChannelId
                                      1,   0,   0,   0,                 // TokenId
                                      2,   0,   0,   0,                 // SequenceNumber
                                      5,   0,   0,   0,                 // RequestId
                                      0xAA}));
    auto next = p.client.encodeMessage(MessageType::CloseChannel, 6, {});
    ASSERT_TRUE(next.ok());
    EXPECT_EQ(next->front(), symFrame("CLOF", 7, 1, 3, 6, {}));
}

TEST(SecureChannel, OneByteMessageBothWays) {
    ChannelPair p;
    p.open();
    ChannelPair::roundTrip(p.client, p.server, {0x42}, p.t0);
    ChannelPair::roundTrip(p.server, p.client, {0x43}, p.t0);
    ChannelPair::roundTrip(p.client, p.server, {}, p.t0);  // an empty body is one chunk
}

TEST(SecureChannel, ExactlyOneChunk) {
    ChannelPair p(smallLimits(), smallLimits());
    p.open();
    const auto fits = kMinBufferSize - kSymOverhead;
    auto one = p.client.encodeMessage(MessageType::Message, 5, pattern(fits));
    ASSERT_TRUE(one.ok());
    ASSERT_EQ(one->size(), 1u);
    EXPECT_EQ(one->front().size(), kMinBufferSize);
    EXPECT_EQ(ChannelPair::deliver(p.server, *one, p.t0).body, pattern(fits));

    auto two = p.client.encodeMessage(MessageType::Message, 6, pattern(fits + 1));
    ASSERT_TRUE(two.ok());
    ASSERT_EQ(two->size(), 2u);
    EXPECT_EQ((*two)[0][3], 'C');
    EXPECT_EQ((*two)[1][3], 'F');
    EXPECT_EQ((*two)[1].size(), kSymOverhead + 1);
    EXPECT_EQ(ChannelPair::deliver(p.server, *two, p.t0).body, pattern(fits + 1));
}

TEST(SecureChannel, ManyChunks) {
    ChannelPair p(smallLimits(), smallLimits());
    p.open();
    const Bytes body = pattern(100'000);
    auto frames = p.client.encodeMessage(MessageType::Message, 77, body);
    ASSERT_TRUE(frames.ok());
    const std::size_t perChunk = kMinBufferSize - kSymOverhead;
    ASSERT_EQ(frames->size(), (body.size() + perChunk - 1) / perChunk);
    for (std::size_t i = 0; i < frames->size(); ++i) {
        const auto& f = (*frames)[i];
        EXPECT_LE(f.size(), kMinBufferSize);
        EXPECT_EQ(f[3], i + 1 == frames->size() ? 'F' : 'C');
        EXPECT_EQ(getU32(f, 16), 2 + i) << "one sequence number per chunk";
        EXPECT_EQ(getU32(f, 20), 77u);
    }
    EXPECT_EQ(ChannelPair::deliver(p.server, *frames, p.t0).body, body);
    // And the other way, with the server's own sequence numbers.
    ChannelPair::roundTrip(p.server, p.client, pattern(30'000), p.t0);
}

// =======================================================================================
// SecureChannel: limits

TEST(SecureChannel, ReceiveMessageSizeLimit) {
    TransportLimits server = smallLimits();
    server.maxMessageSize = 20'000;
    TransportLimits client = smallLimits();
    client.sendMaxMessageSize = 0;  // lets the client send past the server's limit
    ChannelPair p(client, server);
    p.open();
    ChannelPair::roundTrip(p.client, p.server, pattern(20'000), p.t0);

    auto over = p.client.encodeMessage(MessageType::Message, 9, pattern(20'001));
    ASSERT_TRUE(over.ok());
    ASSERT_EQ(over->size(), 3u);
    EXPECT_TRUE(p.server.receiveFrame((*over)[0], p.t0).ok());
    EXPECT_TRUE(p.server.receiveFrame((*over)[1], p.t0).ok());
    EXPECT_EQ(p.server.receiveFrame((*over)[2], p.t0).status(), status::BadTcpMessageTooLarge);
}

TEST(SecureChannel, ReceiveChunkCountLimit) {
    TransportLimits server = smallLimits();
    server.maxChunkCount = 3;
    TransportLimits client = smallLimits();
    client.sendMaxChunkCount = 0;
    ChannelPair p(client, server);
    p.open();
    const std::size_t perChunk = kMinBufferSize - kSymOverhead;
    ChannelPair::roundTrip(p.client, p.server, pattern(3 * perChunk), p.t0);

    auto over = p.client.encodeMessage(MessageType::Message, 9, pattern(3 * perChunk + 1));
    ASSERT_TRUE(over.ok());
    ASSERT_EQ(over->size(), 4u);
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(p.server.receiveFrame((*over)[i], p.t0).ok());
    EXPECT_EQ(p.server.receiveFrame((*over)[3], p.t0).status(), status::BadTcpMessageTooLarge);
}

TEST(SecureChannel, FrameLargerThanReceiveBuffer) {
    TransportLimits client;
    client.sendBufferSize = 16384;
    ChannelPair p(client, smallLimits());
    p.open();
    auto frames = p.client.encodeMessage(MessageType::Message, 9, pattern(10'000));
    ASSERT_TRUE(frames.ok());
    ASSERT_EQ(frames->size(), 1u);
    EXPECT_EQ(p.server.receiveFrame(frames->front(), p.t0).status(), status::BadTcpMessageTooLarge);
}

TEST(SecureChannel, SendLimitsRefuseBeforeSpendingSequenceNumbers) {
    TransportLimits client = smallLimits();
    client.sendMaxMessageSize = 20'000;
    client.sendMaxChunkCount = 2;
    TransportLimits server = smallLimits();
    server.sendMaxMessageSize = 100;
    ChannelPair p(client, server);
    p.open();
    const std::size_t perChunk = kMinBufferSize - kSymOverhead;

    EXPECT_EQ(p.client.encodeMessage(MessageType::Message, 9, pattern(20'001)).status(),
              status::BadRequestTooLarge);
    EXPECT_EQ(p.client.encodeMessage(MessageType::Message, 9, pattern(2 * perChunk + 1)).status(),
              status::BadRequestTooLarge);
    EXPECT_EQ(p.server.encodeMessage(MessageType::Message, 9, pattern(101)).status(),
              status::BadResponseTooLarge);
    // OPN and CLO are never chunked.
    EXPECT_EQ(p.client.encodeMessage(MessageType::CloseChannel, 9, pattern(perChunk + 1)).status(),
              status::BadRequestTooLarge);
    EXPECT_EQ(p.client.encodeMessage(MessageType::Hello, 9, {}).status(),
              status::BadInvalidArgument);

    // Nothing was spent: the next messages arrive in sequence.
    ChannelPair::roundTrip(p.client, p.server, pattern(2 * perChunk), p.t0);
    ChannelPair::roundTrip(p.server, p.client, pattern(100), p.t0);
}

TEST(SecureChannel, SendBeforeOpen) {
    SecureChannel client(SecureChannel::Role::Client, {}, std::make_unique<SecurityPolicyNone>());
    EXPECT_EQ(client.encodeMessage(MessageType::Message, 1, Bytes{1}).status(),
              status::BadInvalidState);
    EXPECT_EQ(client.encodeAbort(1, status::BadTimeout, "x").status(), status::BadInvalidState);
}

// =======================================================================================
// SecureChannel: errors on receive

TEST(SecureChannel, BadSequenceNumber) {
    ChannelPair p;
    p.open();
    // The server's last received sequence number is 1 (the client's OPN).
    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGF", 7, 1, 3, 2, {1}), p.t0).status(),
              status::BadSequenceNumberInvalid);
    ChannelPair q;
    q.open();
    EXPECT_EQ(q.server.receiveFrame(symFrame("MSGF", 7, 1, 1, 2, {1}), q.t0).status(),
              status::BadSequenceNumberInvalid)
        << "a replayed sequence number";
    ChannelPair r;
    r.open();
    EXPECT_TRUE(r.server.receiveFrame(symFrame("MSGF", 7, 1, 2, 2, {1}), r.t0).ok());
}

TEST(SecureChannel, SequenceNumberWrapAround) {
    auto openAt = [](SecureChannel& server, std::uint32_t firstSeq) {
        const auto body = encodeService(OpenSecureChannelRequest{});
        auto m = server.receiveFrame(opnFrame(0, firstSeq, 1, body), SteadyTime{});
        ASSERT_TRUE(m.ok());
        auto req = decodeService<OpenSecureChannelRequest>((*m)->body);
        ASSERT_TRUE(server.openOrRenew(req, kChannelId, SteadyTime{}).ok());
    };
    {
        // The first sequence number is accepted as is; past UInt32Max-1024 the sender may
        // wrap to anything below 1024.
        SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
        openAt(s, 4'294'966'272u);
        EXPECT_TRUE(s.receiveFrame(symFrame("MSGF", 7, 1, 4'294'966'273u, 2, {}), {}).ok());
        EXPECT_TRUE(s.receiveFrame(symFrame("MSGF", 7, 1, 1023, 3, {}), {}).ok());
        EXPECT_TRUE(s.receiveFrame(symFrame("MSGF", 7, 1, 1024, 4, {}), {}).ok());
    }
    {
        SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
        openAt(s, 4'294'966'272u);
        EXPECT_EQ(s.receiveFrame(symFrame("MSGF", 7, 1, 1024, 2, {}), {}).status(),
                  status::BadSequenceNumberInvalid);
    }
    {
        // Not yet past the threshold: no wrap allowed.
        SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
        openAt(s, 4'294'966'271u);
        EXPECT_EQ(s.receiveFrame(symFrame("MSGF", 7, 1, 0, 2, {}), {}).status(),
                  status::BadSequenceNumberInvalid);
    }
    {
        // UInt32Max + 1 wraps to 0.
        SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
        openAt(s, 0xFFFFFFFFu);
        EXPECT_TRUE(s.receiveFrame(symFrame("MSGF", 7, 1, 0, 2, {}), {}).ok());
        EXPECT_TRUE(s.receiveFrame(symFrame("MSGF", 7, 1, 1, 3, {}), {}).ok());
    }
}

TEST(SecureChannel, WrongChannelId) {
    ChannelPair p;
    p.open();
    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGF", 8, 1, 2, 2, {1}), p.t0).status(),
              status::BadTcpSecureChannelUnknown);
    ChannelPair q;
    q.open();
    EXPECT_EQ(q.client.receiveFrame(symFrame("MSGF", 0, 1, 2, 2, {1}), q.t0).status(),
              status::BadTcpSecureChannelUnknown);
    // An OPN for a channel the server does not have.
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
    EXPECT_EQ(s.receiveFrame(opnFrame(42, 1, 1, {}), {}).status(),
              status::BadTcpSecureChannelUnknown);
    ChannelPair r;
    r.open();
    EXPECT_EQ(r.server.receiveFrame(opnFrame(42, 2, 1, {}), r.t0).status(),
              status::BadTcpSecureChannelUnknown);
}

TEST(SecureChannel, UnknownToken) {
    ChannelPair p;
    p.open();
    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGF", 7, 99, 2, 2, {1}), p.t0).status(),
              status::BadSecureChannelTokenUnknown);
    ChannelPair q;
    q.open();
    EXPECT_EQ(q.client.receiveFrame(symFrame("MSGF", 7, 0, 2, 2, {1}), q.t0).status(),
              status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, MessageBeforeOpen) {
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
    EXPECT_EQ(s.receiveFrame(symFrame("MSGF", 0, 0, 1, 1, {}), {}).status(),
              status::BadTcpMessageTypeInvalid);
    EXPECT_EQ(s.receiveFrame(symFrame("CLOF", 0, 0, 1, 1, {}), {}).status(),
              status::BadTcpMessageTypeInvalid);
    SecureChannel c(SecureChannel::Role::Client, {}, std::make_unique<SecurityPolicyNone>());
    EXPECT_EQ(c.receiveFrame(symFrame("MSGF", 7, 1, 1, 1, {}), {}).status(),
              status::BadTcpMessageTypeInvalid);
}

TEST(SecureChannel, NonSecureConversationFrames) {
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
    EXPECT_EQ(s.receiveFrame(encodeHello(HelloMessage{0, 8192, 8192, 0, 0, "x"}), {}).status(),
              status::BadTcpMessageTypeInvalid);
    EXPECT_EQ(s.receiveFrame(encodeError(status::BadTimeout, ""), {}).status(),
              status::BadTcpMessageTypeInvalid);
}

TEST(SecureChannel, PolicyUriMismatch) {
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
    const auto frame = opnFrame(0, 1, 1, encodeService(OpenSecureChannelRequest{}),
                                "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256");
    EXPECT_EQ(s.receiveFrame(frame, {}).status(), status::BadSecurityPolicyRejected);
}

TEST(SecureChannel, TruncatedAndMalformedFrames) {
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
    const auto good = opnFrame(0, 1, 1, encodeService(OpenSecureChannelRequest{}));
    EXPECT_EQ(s.receiveFrame(Bytes(good.begin(), good.begin() + 4), {}).status(),
              status::BadDecodingError);
    // The size field no longer matches what was handed over.
    EXPECT_EQ(s.receiveFrame(Bytes(good.begin(), good.end() - 1), {}).status(),
              status::BadDecodingError);
    // Consistent sizes, but the headers stop early.
    for (std::size_t cut : {8u, 12u, 20u, 59u, 70u, 78u}) {
        Bytes b(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut));
        patchSize(b);
        EXPECT_EQ(s.receiveFrame(b, {}).status(), status::BadDecodingError) << cut;
    }
    // A policy URI length beyond the frame.
    Bytes badLength = good;
    badLength[12] = 0xFF;
    badLength[13] = 0xFF;
    EXPECT_EQ(s.receiveFrame(badLength, {}).status(), status::BadDecodingError);
    // A 4 GB size claim.
    Bytes huge = good;
    huge[4] = huge[5] = huge[6] = huge[7] = 0xFF;
    EXPECT_EQ(s.receiveFrame(huge, {}).status(), status::BadTcpMessageTooLarge);

    ChannelPair p;
    p.open();
    for (std::size_t cut : {12u, 16u, 20u}) {
        Bytes b = symFrame("MSGF", 7, 1, 2, 2, {});
        b.resize(cut);
        patchSize(b);
        EXPECT_EQ(p.server.receiveFrame(b, p.t0).status(), status::BadDecodingError) << cut;
    }
}

// =======================================================================================
// SecureChannel: reassembly, aborts

TEST(SecureChannel, AbortDropsThePartialMessage) {
    ChannelPair p;
    p.open();
    // Hand-made chunks: a sender that aborts never spent a sequence number on a final chunk.
    EXPECT_FALSE(
        p.server.receiveFrame(symFrame("MSGC", 7, 1, 2, 11, pattern(100)), p.t0)->has_value());
    EXPECT_FALSE(
        p.server.receiveFrame(symFrame("MSGC", 7, 1, 3, 11, pattern(100)), p.t0)->has_value());
    const Bytes abortBody{0x00, 0x00, 0x08, 0x80, 8,   0,   0,   0,
                          't',  'o',  'o',  ' ',  'd', 'e', 'e', 'p'};
    auto r = p.server.receiveFrame(symFrame("MSGA", 7, 1, 4, 11, abortBody), p.t0);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->has_value());
    ASSERT_TRUE(p.server.lastAbort().has_value());
    EXPECT_EQ(p.server.lastAbort()->requestId, 11u);
    EXPECT_EQ(p.server.lastAbort()->error, status::BadEncodingLimitsExceeded);
    EXPECT_EQ(p.server.lastAbort()->reason, "too deep");
    // The channel goes on: the next message holds only its own bytes, and the abort report
    // is gone.
    auto next = p.server.receiveFrame(symFrame("MSGF", 7, 1, 5, 12, {9}), p.t0);
    ASSERT_TRUE(next.ok());
    ASSERT_TRUE(next->has_value());
    EXPECT_EQ((*next)->requestId, 12u);
    EXPECT_EQ((*next)->body, Bytes{9});
    EXPECT_FALSE(p.server.lastAbort().has_value());

    // encodeAbort builds exactly that kind of chunk, with the sender's next sequence number.
    auto abort = p.client.encodeAbort(11, status::BadEncodingLimitsExceeded, "too deep");
    ASSERT_TRUE(abort.ok());
    EXPECT_EQ(*abort, symFrame("MSGA", 7, 1, 2, 11, abortBody));
}

TEST(SecureChannel, AbortWithoutPartialAndMalformedAbort) {
    ChannelPair p;
    p.open();
    auto abort = p.server.encodeAbort(3, status::BadResponseTooLarge, std::string(5000, 'r'));
    ASSERT_TRUE(abort.ok());
    auto r = p.client.receiveFrame(*abort, p.t0);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->has_value());
    EXPECT_EQ(p.client.lastAbort()->error, status::BadResponseTooLarge);
    EXPECT_EQ(p.client.lastAbort()->reason.size(), 4096u);

    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGA", 7, 1, 2, 3, {1, 2}), p.t0).status(),
              status::BadDecodingError);
}

TEST(SecureChannel, InterleavedRequestIds) {
    ChannelPair p;
    p.open();
    ASSERT_TRUE(p.server.receiveFrame(symFrame("MSGC", 7, 1, 2, 1, {1}), p.t0).ok());
    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGF", 7, 1, 3, 2, {2}), p.t0).status(),
              status::BadSecurityChecksFailed);

    ChannelPair q;
    q.open();
    ASSERT_TRUE(q.server.receiveFrame(symFrame("MSGC", 7, 1, 2, 1, {1}), q.t0).ok());
    EXPECT_EQ(q.server.receiveFrame(symFrame("CLOF", 7, 1, 3, 1, {}), q.t0).status(),
              status::BadSecurityChecksFailed);

    ChannelPair a;
    a.open();
    ASSERT_TRUE(a.server.receiveFrame(symFrame("MSGC", 7, 1, 2, 1, {1}), a.t0).ok());
    EXPECT_EQ(a.server.receiveFrame(symFrame("MSGA", 7, 1, 3, 2, {0, 0, 0, 0x80, 0, 0, 0, 0}), a.t0)
                  .status(),
              status::BadSecurityChecksFailed);
}

TEST(SecureChannel, CloseMessage) {
    ChannelPair p;
    p.open();
    auto frames = p.client.encodeMessage(MessageType::CloseChannel, 4,
                                         encodeService(CloseSecureChannelRequest{}));
    ASSERT_TRUE(frames.ok());
    auto m = ChannelPair::deliver(p.server, *frames, p.t0);
    EXPECT_EQ(m.type, MessageType::CloseChannel);
    EXPECT_EQ(m.requestId, 4u);
    decodeService<CloseSecureChannelRequest>(m.body);
}

// =======================================================================================
// SecureChannel: tokens

TEST(SecureChannel, OpenRequestFields) {
    SecureChannelConfig config;
    config.tokenLifetimeMs = 30'000;
    SecureChannel client(SecureChannel::Role::Client, {}, std::make_unique<SecurityPolicyNone>(),
                         config);
    const auto r = client.makeOpenRequest(SecurityTokenRequestType::Renew);
    EXPECT_EQ(r.requestType, SecurityTokenRequestType::Renew);
    EXPECT_EQ(r.securityMode, MessageSecurityMode::None);
    EXPECT_EQ(r.requestedLifetime, 30'000u);
    EXPECT_EQ(r.clientProtocolVersion, 0u);
}

TEST(SecureChannel, LifetimeIsClamped) {
    SecureChannelConfig config;
    config.tokenLifetimeMs = 60'000;
    config.minTokenLifetimeMs = 10'000;
    auto revised = [&](std::uint32_t requested) {
        SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>(),
                        config);
        OpenSecureChannelRequest r;
        r.requestedLifetime = requested;
        r.requestHeader.requestHandle = 17;
        auto response = s.openOrRenew(r, kChannelId, {});
        EXPECT_TRUE(response.ok());
        EXPECT_EQ(response->responseHeader.requestHandle, 17u);
        EXPECT_EQ(response->responseHeader.serviceResult, status::Good);
        return response->securityToken.revisedLifetime;
    };
    EXPECT_EQ(revised(0), 60'000u);
    EXPECT_EQ(revised(1), 10'000u);
    EXPECT_EQ(revised(30'000), 30'000u);
    EXPECT_EQ(revised(0xFFFFFFFF), 60'000u);
}

TEST(SecureChannel, RequestTypeAndModeChecks) {
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<SecurityPolicyNone>());
    OpenSecureChannelRequest r;
    r.requestType = SecurityTokenRequestType::Renew;
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadRequestTypeInvalid);
    r.requestType = static_cast<SecurityTokenRequestType>(5);
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadRequestTypeInvalid);
    r.requestType = SecurityTokenRequestType::Issue;
    r.securityMode = MessageSecurityMode::Sign;
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadSecurityModeRejected);
    r.securityMode = MessageSecurityMode::Invalid;
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadSecurityModeRejected);
    r.securityMode = MessageSecurityMode::None;
    EXPECT_EQ(s.openOrRenew(r, 0, {}).status(), status::BadInvalidArgument);
    ASSERT_TRUE(s.openOrRenew(r, kChannelId, {}).ok());
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadRequestTypeInvalid)
        << "Issue twice";
    r.requestType = SecurityTokenRequestType::Renew;
    auto renewed = s.openOrRenew(r, 999, {});
    ASSERT_TRUE(renewed.ok());
    EXPECT_EQ(renewed->securityToken.channelId, kChannelId) << "Renew keeps the channel id";
    EXPECT_EQ(renewed->securityToken.tokenId, 2u);

    SecureChannel c(SecureChannel::Role::Client, {}, std::make_unique<SecurityPolicyNone>());
    EXPECT_EQ(c.openOrRenew(r, kChannelId, {}).status(), status::BadInvalidState);
    EXPECT_EQ(s.acceptOpenResponse(OpenSecureChannelResponse{}, {}), status::BadInvalidState);
}

TEST(SecureChannel, TokenExpiresAfterLifetimePlusTolerance) {
    SecureChannelConfig config;
    config.tokenLifetimeMs = 10'000;
    ChannelPair p({}, {}, config, config);
    p.open();
    EXPECT_EQ(p.server.currentToken()->revisedLifetime, 10'000u);
    // Accepted up to lifetime * 1.25, not one millisecond later, on both sides.
    const auto edge = p.t0 + milliseconds(12'500);
    ChannelPair::roundTrip(p.client, p.server, {1}, edge);
    ChannelPair::roundTrip(p.server, p.client, {2}, edge);
    auto late = p.client.encodeMessage(MessageType::Message, 9, Bytes{3});
    EXPECT_EQ(p.server.receiveFrame(late->front(), edge + milliseconds(1)).status(),
              status::BadSecureChannelTokenUnknown);
    auto lateBack = p.server.encodeMessage(MessageType::Message, 9, Bytes{3});
    EXPECT_EQ(p.client.receiveFrame(lateBack->front(), edge + milliseconds(1)).status(),
              status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, RenewalDueAtThreeQuarters) {
    SecureChannelConfig config;
    config.tokenLifetimeMs = 20'000;
    ChannelPair p({}, {}, config, config);
    EXPECT_FALSE(p.client.renewalDue(p.t0));
    p.open();
    EXPECT_FALSE(p.client.renewalDue(p.t0 + milliseconds(14'999)));
    EXPECT_TRUE(p.client.renewalDue(p.t0 + milliseconds(15'000)));
}

TEST(SecureChannel, RenewalKeepsOldTokenUntilNewOneIsUsed) {
    SecureChannelConfig config;
    config.tokenLifetimeMs = 20'000;
    ChannelPair p({}, {}, config, config);
    p.open();
    const auto t1 = p.t0 + milliseconds(15'000);
    ASSERT_TRUE(p.client.renewalDue(t1));

    // The server has renewed; the client has not seen the response yet.
    const auto response = p.serverSide(SecurityTokenRequestType::Renew, t1, 2);
    EXPECT_EQ(response.securityToken.tokenId, 2u);
    EXPECT_EQ(response.securityToken.channelId, kChannelId);
    auto oldToken = p.client.encodeMessage(MessageType::Message, 3, Bytes{1});
    EXPECT_EQ(getU32(oldToken->front(), 12), 1u);
    EXPECT_TRUE(p.server.receiveFrame(oldToken->front(), t1).ok()) << "old token still valid";
    // Until the client uses the new token, the server keeps securing with the old one.
    auto serverOld = p.server.encodeMessage(MessageType::Message, 3, Bytes{2});
    EXPECT_EQ(getU32(serverOld->front(), 12), 1u);

    ASSERT_EQ(p.client.acceptOpenResponse(response, t1), status::Good);
    EXPECT_FALSE(p.client.renewalDue(t1));
    EXPECT_EQ(p.client.currentToken()->tokenId, 2u);
    // The client still accepts the server's message secured with the old token.
    EXPECT_TRUE(p.client.receiveFrame(serverOld->front(), t1).ok());
    auto newToken = p.client.encodeMessage(MessageType::Message, 4, Bytes{3});
    EXPECT_EQ(getU32(newToken->front(), 12), 2u);
    EXPECT_TRUE(p.server.receiveFrame(newToken->front(), t1).ok());

    // The server has switched; the old token is now refused by both.
    auto serverNew = p.server.encodeMessage(MessageType::Message, 4, Bytes{4});
    EXPECT_EQ(getU32(serverNew->front(), 12), 2u);
    EXPECT_TRUE(p.client.receiveFrame(serverNew->front(), t1).ok());
    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGF", 7, 1, 5, 5, {}), t1).status(),
              status::BadSecureChannelTokenUnknown);
    EXPECT_EQ(p.client.receiveFrame(symFrame("MSGF", 7, 1, 5, 5, {}), t1).status(),
              status::BadSecureChannelTokenUnknown);
}

TEST(SecureChannel, OldTokenExpiresEvenIfNewOneIsUnused) {
    SecureChannelConfig config;
    config.tokenLifetimeMs = 20'000;
    ChannelPair p({}, {}, config, config);
    p.open();
    const auto t1 = p.t0 + milliseconds(15'000);
    p.handshake(SecurityTokenRequestType::Renew, t1, 2);
    // The old token was created at t0: acceptable until t0 + 25 s.
    auto stale = symFrame("MSGF", 7, 1, 3, 9, {});
    EXPECT_TRUE(p.server.receiveFrame(stale, p.t0 + milliseconds(25'000)).ok());
    EXPECT_EQ(p.server.receiveFrame(symFrame("MSGF", 7, 1, 4, 9, {}), p.t0 + milliseconds(25'001))
                  .status(),
              status::BadSecureChannelTokenUnknown);
    // The new token (created at t1) is fine then, and the server sends with it.
    EXPECT_TRUE(
        p.server.receiveFrame(symFrame("MSGF", 7, 2, 4, 9, {}), p.t0 + milliseconds(25'001)).ok());
}

TEST(SecureChannel, AcceptOpenResponseChecks) {
    ChannelPair p;
    OpenSecureChannelResponse bad;
    bad.responseHeader.serviceResult = status::BadSecurityModeRejected;
    EXPECT_EQ(p.client.acceptOpenResponse(bad, p.t0), status::BadSecurityModeRejected);
    OpenSecureChannelResponse zero;
    zero.securityToken.tokenId = 1;
    EXPECT_EQ(p.client.acceptOpenResponse(zero, p.t0), status::BadSecureChannelIdInvalid);

    p.open();
    auto renewed = p.serverSide(SecurityTokenRequestType::Renew, p.t0, 2);
    auto moved = renewed;
    moved.securityToken.channelId = kChannelId + 1;
    EXPECT_EQ(p.client.acceptOpenResponse(moved, p.t0), status::BadSecureChannelIdInvalid);
    EXPECT_EQ(p.client.acceptOpenResponse(renewed, p.t0), status::Good);

    // The token's channel id must match the OPN header it came in.
    SecureChannel c(SecureChannel::Role::Client, {}, std::make_unique<SecurityPolicyNone>());
    ASSERT_TRUE(c.receiveFrame(opnFrame(5, 1, 1, {}), {}).ok());
    OpenSecureChannelResponse other;
    other.securityToken.channelId = 6;
    other.securityToken.tokenId = 1;
    other.securityToken.revisedLifetime = 10'000;
    EXPECT_EQ(c.acceptOpenResponse(other, {}), status::BadSecureChannelIdInvalid);
    other.securityToken.channelId = 5;
    EXPECT_EQ(c.acceptOpenResponse(other, {}), status::Good);
    EXPECT_EQ(c.channelId(), 5u);
}

// =======================================================================================
// SecureChannel: a policy that signs

TEST(SecureChannel, PolicyThatSignsPlugsIn) {
    SecureChannelConfig config;
    config.securityMode = MessageSecurityMode::Sign;
    ChannelPair p(std::make_unique<ChecksumPolicy>(), std::make_unique<ChecksumPolicy>(), config);
    p.open();
    EXPECT_TRUE(p.client.isOpen());
    // Chunks carry 4 bytes fewer; frames still never exceed the peer's buffer.
    auto frames = p.client.encodeMessage(MessageType::Message, 5, pattern(65535 - kSymOverhead));
    ASSERT_TRUE(frames.ok());
    ASSERT_EQ(frames->size(), 2u);
    EXPECT_EQ((*frames)[0].size(), 65535u);
    EXPECT_EQ(getU32((*frames)[0], 4), 65535u) << "size patched after protect";
    EXPECT_EQ(ChannelPair::deliver(p.server, *frames, p.t0).body, pattern(65535 - kSymOverhead));

    // A flipped byte fails the check, whatever the channel state.
    auto tampered = p.client.encodeMessage(MessageType::Message, 6, Bytes{1, 2, 3});
    (*tampered)[0][25] ^= 1;
    EXPECT_EQ(p.server.receiveFrame((*tampered)[0], p.t0).status(),
              status::BadSecurityChecksFailed);
}

TEST(SecureChannel, SecuredPolicyRequiresSecuredMode) {
    // The server's endpoints decide which modes go with a policy; this one offers
    // SignAndEncrypt only.
    SecureChannelConfig config;
    config.acceptsMode = [](std::string_view uri, MessageSecurityMode mode) {
        return uri == ChecksumPolicy::kUri && mode == MessageSecurityMode::SignAndEncrypt;
    };
    SecureChannel s(SecureChannel::Role::Server, {}, std::make_unique<ChecksumPolicy>(), config);
    OpenSecureChannelRequest r;
    r.securityMode = MessageSecurityMode::None;
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadSecurityModeRejected);
    r.securityMode = MessageSecurityMode::Sign;
    EXPECT_EQ(s.openOrRenew(r, kChannelId, {}).status(), status::BadSecurityModeRejected);
    r.securityMode = MessageSecurityMode::SignAndEncrypt;
    EXPECT_TRUE(s.openOrRenew(r, kChannelId, {}).ok());
}

}  // namespace transport_test
