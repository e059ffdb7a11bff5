// The server facing bad input over real sockets: every malformed or out-of-order message
// gets the precise ERR or ServiceFault status, and a well-behaved client connected at the
// same time keeps being served.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <string>
#include <thread>

#include "raw_connection.hpp"
#include "running_server.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/messages/attribute.hpp"
#include "ua/messages/discovery.hpp"
#include "ua/server/service_table.hpp"

namespace server_protocol_test {

using namespace skillcell;
using namespace skillcell::ua;
using test::RawConnection;
using test::RunningServer;

namespace {

const NodeId kValue(1, String("Test.Value"));

void addTestNodes(Server& server) {
    auto& as = server.addressSpace();
    ASSERT_TRUE(as.addVariable(NodeId(ns0::ObjectsFolder), kValue, "Test.Value",
                               NodeId(ns0::Double), Variant(2.5), access_level::kReadWrite));
}

/// A well-behaved client that must keep working while others misbehave.
class Bystander {
public:
    explicit Bystander(const std::string& url) { EXPECT_EQ(client_.connect(url), status::Good); }
    void expectServed() {
        auto v = client_.readValue(kValue);
        ASSERT_TRUE(v) << statusName(v.status());
        EXPECT_EQ(*v->get<double>(), 2.5);
    }

private:
    BlockingClient client_;
};

class ServerProtocol : public ::testing::Test {
protected:
    ServerProtocol() : server_(config(), addTestNodes), bystander_(server_.url()) {}
    static ServerConfig config() {
        auto c = RunningServer::defaultConfig();
        c.limits.transport.maxChunkCount = 4;
        c.limits.transport.maxMessageSize = 64 * 1024;
        return c;
    }
    void TearDown() override { bystander_.expectServed(); }

    RunningServer server_;
    Bystander bystander_;
};

std::vector<std::uint8_t> bytes(std::string_view s) {
    return {s.begin(), s.end()};
}

std::vector<std::uint8_t> readRequestBody(std::uint32_t handle, const NodeId& token = {}) {
    ReadRequest req;
    req.requestHeader.requestHandle = handle;
    req.requestHeader.authenticationToken = token;
    req.nodesToRead.push_back(ReadValueId{kValue, 13, {}, {}});
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, req);
    return body;
}

// Offsets of a MSG chunk's fields: header (8), channel id, token id, sequence number.
constexpr std::size_t kChannelIdOffset = 8;
constexpr std::size_t kTokenIdOffset = 12;
constexpr std::size_t kSequenceNumberOffset = 16;

/// A valid single-chunk Read request frame whose UInt32 at `offset` is replaced by
/// `change(old value)`: how the tests forge one bad field at a time.
template <class Change>
std::vector<std::uint8_t> readFrameWithField(RawConnection& c, std::size_t offset, Change change) {
    auto frames =
        c.channel().encodeMessage(MessageType::Message, c.nextRequestId(), readRequestBody(7));
    if (!frames || frames->size() != 1) return {};
    auto frame = (*frames)[0];
    std::uint32_t value = 0;
    std::memcpy(&value, frame.data() + offset, 4);
    value = change(value);
    std::memcpy(frame.data() + offset, &value, 4);
    return frame;
}

/// The ServiceFault status in a response body, or Good if it is not a ServiceFault.
StatusCode faultStatus(const std::vector<std::uint8_t>& body, std::uint32_t* handle = nullptr) {
    BinaryReader r(body);
    NodeId typeId;
    decode(r, typeId);
    if (typeId != NodeId(ServiceFault::kBinaryEncodingId)) return status::Good;
    ServiceFault fault;
    decode(r, fault);
    if (handle != nullptr) *handle = fault.responseHeader.requestHandle;
    return fault.responseHeader.serviceResult;
}

}  // namespace

TEST_F(ServerProtocol, GarbageInsteadOfHelloIsRejected) {
    RawConnection c(server_.port());
    c.send(bytes("GET / HTTP/1.1\r\nHost: x\r\n\r\n"));
    EXPECT_EQ(c.readError(), status::BadTcpMessageTypeInvalid);
    EXPECT_TRUE(c.closedByPeer());
}

TEST_F(ServerProtocol, MessageBeforeHelloIsRejected) {
    RawConnection c(server_.port());
    // A well-formed MSG header with nothing negotiated yet.
    c.send(std::vector<std::uint8_t>{'M', 'S', 'G', 'F', 16, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    EXPECT_EQ(c.readError(), status::BadTcpMessageTypeInvalid);
    EXPECT_TRUE(c.closedByPeer());
}

TEST_F(ServerProtocol, HelloWithTooSmallBuffersIsRejected) {
    RawConnection c(server_.port());
    HelloMessage h;
    h.receiveBufferSize = 1024;
    h.sendBufferSize = 1024;
    c.send(encodeHello(h));
    EXPECT_EQ(c.readError(), status::BadConnectionRejected);
}

TEST_F(ServerProtocol, TruncatedHelloIsADecodingError) {
    RawConnection c(server_.port());
    auto hello = encodeHello(HelloMessage{0, 65535, 65535, 0, 0, "opc.tcp://x"});
    // Cut the endpoint URL short but keep the header's size consistent with what is sent.
    hello.resize(hello.size() - 4);
    const auto size = static_cast<std::uint32_t>(hello.size());
    std::memcpy(hello.data() + 4, &size, 4);
    c.send(hello);
    EXPECT_EQ(c.readError(), status::BadDecodingError);
}

TEST_F(ServerProtocol, GarbageAfterHelloIsRejected) {
    RawConnection c(server_.port());
    c.hello();
    std::vector<std::uint8_t> garbage{'X', 'Y', 'Z', 'F', 16, 0, 0, 0};
    for (char ch : std::string_view("garbage!")) garbage.push_back(static_cast<std::uint8_t>(ch));
    c.send(garbage);
    EXPECT_EQ(c.readError(), status::BadTcpMessageTypeInvalid);
    EXPECT_TRUE(c.closedByPeer());
}

TEST_F(ServerProtocol, SecondHelloIsRejected) {
    RawConnection c(server_.port());
    c.hello();
    c.send(encodeHello(HelloMessage{0, 65535, 65535, 0, 0, "opc.tcp://x"}));
    EXPECT_EQ(c.readError(), status::BadTcpMessageTypeInvalid);
}

TEST_F(ServerProtocol, ChunkLargerThanTheReceiveBufferIsRejected) {
    RawConnection c(server_.port());
    const auto limits = c.hello();
    std::vector<std::uint8_t> frame{'M', 'S', 'G', 'F', 0, 0, 0, 0};
    const std::uint32_t size = limits.sendBufferSize + 1;
    std::memcpy(frame.data() + 4, &size, 4);
    c.send(frame);
    EXPECT_EQ(c.readError(), status::BadTcpMessageTooLarge);
    EXPECT_TRUE(c.closedByPeer());
}

TEST_F(ServerProtocol, HeaderSizeBelowEightBytesIsADecodingError) {
    RawConnection c(server_.port());
    c.send(std::vector<std::uint8_t>{'H', 'E', 'L', 'F', 4, 0, 0, 0});
    EXPECT_EQ(c.readError(), status::BadDecodingError);
}

TEST_F(ServerProtocol, TruncatedOpenSecureChannelIsADecodingError) {
    RawConnection c(server_.port());
    const auto limits = c.hello();
    SecureChannel channel(SecureChannel::Role::Client, limits,
                          std::make_unique<SecurityPolicyNone>());
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, channel.makeOpenRequest(SecurityTokenRequestType::Issue));
    body.resize(body.size() / 2);  // the request ends in the middle
    auto frames = channel.encodeMessage(MessageType::OpenChannel, 1, body);
    ASSERT_TRUE(frames);
    c.send((*frames)[0]);
    EXPECT_EQ(c.readError(), status::BadDecodingError);
}

TEST_F(ServerProtocol, MessageBeforeOpenSecureChannelIsRejected) {
    RawConnection c(server_.port());
    c.hello();
    std::vector<std::uint8_t> frame{'M', 'S', 'G', 'F', 24, 0, 0, 0, 1, 0, 0, 0,
                                    1,   0,   0,   0,   1,  0, 0, 0, 1, 0, 0, 0};
    c.send(frame);
    EXPECT_EQ(c.readError(), status::BadTcpMessageTypeInvalid);
}

TEST_F(ServerProtocol, BadSequenceNumberClosesTheChannel) {
    RawConnection c(server_.port());
    c.open();
    // The sequence number skips ahead instead of following the OPN's.
    c.send(readFrameWithField(c, kSequenceNumberOffset, [](std::uint32_t seq) { return seq + 5; }));
    EXPECT_EQ(c.readError(), status::BadSequenceNumberInvalid);
    EXPECT_TRUE(c.closedByPeer());
}

TEST_F(ServerProtocol, WrongSecureChannelIdIsRejected) {
    RawConnection c(server_.port());
    c.open();
    c.send(readFrameWithField(c, kChannelIdOffset, [](std::uint32_t id) { return id + 1000; }));
    EXPECT_EQ(c.readError(), status::BadTcpSecureChannelUnknown);
}

TEST_F(ServerProtocol, UnknownTokenIsRejected) {
    RawConnection c(server_.port());
    c.open();
    c.send(readFrameWithField(c, kTokenIdOffset, [](std::uint32_t) { return 999u; }));
    EXPECT_EQ(c.readError(), status::BadSecureChannelTokenUnknown);
}

TEST_F(ServerProtocol, TooManyChunksIsRejected) {
    RawConnection c(server_.port());
    // A client that ignores the server's announced maxChunkCount (4) and sends small chunks.
    c.open([](TransportLimits& l) {
        l.sendBufferSize = 8192;
        l.sendMaxChunkCount = 0;
        l.sendMaxMessageSize = 0;
    });
    WriteRequest req;
    for (int i = 0; i < 3000; ++i) req.nodesToWrite.push_back(WriteValue{kValue, 13, {}, {}});
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, req);
    auto frames = c.channel().encodeMessage(MessageType::Message, c.nextRequestId(), body);
    ASSERT_TRUE(frames);
    ASSERT_GT(frames->size(), 4u);
    for (const auto& f : *frames) c.send(f);
    EXPECT_EQ(c.readError(), status::BadTcpMessageTooLarge);
}

TEST_F(ServerProtocol, UnknownServiceGetsServiceFaultAndChannelStaysUsable) {
    RawConnection c(server_.port());
    c.open();
    RequestHeader header;
    header.requestHandle = 4242;
    std::vector<std::uint8_t> body;
    BinaryWriter w(body);
    encode(w, NodeId(99999u));
    encode(w, header);
    auto reply = c.exchange(body);
    ASSERT_TRUE(reply);
    std::uint32_t handle = 0;
    EXPECT_EQ(faultStatus(*reply, &handle), status::BadServiceUnsupported);
    EXPECT_EQ(handle, 4242u);

    // The same channel still answers a real service.
    GetEndpointsRequest endpoints;
    endpoints.requestHeader.requestHandle = 5;
    std::vector<std::uint8_t> body2;
    encodeServiceMessage(body2, endpoints);
    auto reply2 = c.exchange(body2);
    ASSERT_TRUE(reply2);
    EXPECT_EQ(faultStatus(*reply2), status::Good);
}

TEST_F(ServerProtocol, UndecodableRequestGetsServiceFault) {
    RawConnection c(server_.port());
    c.open();
    GetEndpointsRequest req;  // a service that needs no session: decoding is what fails
    req.requestHeader.requestHandle = 77;
    req.localeIds = {"en", "de"};
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, req);
    body.resize(body.size() - 3);  // the last locale id is cut short
    auto reply = c.exchange(body);
    ASSERT_TRUE(reply);
    std::uint32_t handle = 0;
    EXPECT_EQ(faultStatus(*reply, &handle), status::BadDecodingError);
    EXPECT_EQ(handle, 77u);
}

TEST_F(ServerProtocol, ServicesNeedAnActivatedSession) {
    RawConnection c(server_.port());
    c.open();
    auto reply = c.exchange(readRequestBody(1));
    ASSERT_TRUE(reply);
    EXPECT_EQ(faultStatus(*reply), status::BadSessionIdInvalid);

    CreateSessionRequest create;
    create.requestedSessionTimeout = 60000;
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, create);
    auto created = c.exchange(body);
    ASSERT_TRUE(created);
    BinaryReader r(*created);
    NodeId typeId;
    decode(r, typeId);
    CreateSessionResponse response;
    decode(r, response);
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(typeId, NodeId(CreateSessionResponse::kBinaryEncodingId));

    // Created but not activated.
    auto early = c.exchange(readRequestBody(2, response.authenticationToken));
    ASSERT_TRUE(early);
    EXPECT_EQ(faultStatus(*early), status::BadSessionNotActivated);
}

// Nothing polls the sessions once a second any more: the server wakes at the first one's
// timeout. A session nobody uses is closed then, and one in use is kept.
TEST_F(ServerProtocol, ASessionNobodyUsesIsClosedAtItsTimeout) {
    RawConnection c(server_.port());
    c.open();
    CreateSessionRequest create;
    create.requestedSessionTimeout = 1000;  // the server's least
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, create);
    auto count = [this] { return server_.inServer([](Server& s) { return s.sessionCount(); }); };
    const std::size_t before = count();  // the bystander's, in use (TearDown reads through it)
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(c.exchange(body));
    EXPECT_EQ(count(), before + 1);
    // Bounded wait (10 s) for the reaper; it should act about a second after the creation.
    std::size_t now = before + 1;
    for (int i = 0; i < 1000 && now > before; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));  // polls, bounded in count
        now = count();
    }
    EXPECT_EQ(now, before);
    EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(1000));
}

TEST(ServerLimits, ConnectionsBeyondTheLimitGetAnError) {
    auto config = RunningServer::defaultConfig();
    config.limits.maxChannels = 2;
    RunningServer server(config);
    RawConnection a(server.port());
    a.hello();
    RawConnection b(server.port());
    b.hello();
    RawConnection c(server.port());
    EXPECT_EQ(c.readError(), status::BadTcpNotEnoughResources);
}

TEST(ServerLimits, SilentConnectionIsClosedAfterTheHelloTimeout) {
    auto config = RunningServer::defaultConfig();
    config.limits.helloTimeoutMs = 100;
    RunningServer server(config);
    RawConnection c(server.port(), std::chrono::seconds(5));
    EXPECT_EQ(c.readError(), status::BadTimeout);
    EXPECT_TRUE(c.closedByPeer());
}

}  // namespace server_protocol_test
