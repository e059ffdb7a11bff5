// Client unit tests: URL parsing, connect failures and timeouts, and the request machinery
// against fake servers on loopback (hand-built frames, or our SecureChannel in the server
// role with scripted answers). Tests against real servers live in tests/interop.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <asio/bind_cancellation_slot.hpp>
#include <asio/cancellation_signal.hpp>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/read.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <asio/write.hpp>

#include "ua/client/blocking_client.hpp"
#include "ua/client/client.hpp"
#include "ua/transport/secure_channel.hpp"

namespace skillcell::ua::client_test {
namespace {

using asio::ip::tcp;
using namespace std::chrono_literals;
constexpr auto kNoThrow = asio::experimental::as_tuple(asio::use_awaitable);

// ---- URL parsing ----

TEST(ClientUrl, ParsesGoodUrls) {
    auto a = parseEndpointUrl("opc.tcp://localhost:4841");
    ASSERT_TRUE(a);
    EXPECT_EQ(a->host, "localhost");
    EXPECT_EQ(a->port, 4841);
    EXPECT_EQ(a->path, "");

    auto b = parseEndpointUrl("OPC.TCP://127.0.0.1:48010/UA/Server");
    ASSERT_TRUE(b);
    EXPECT_EQ(b->host, "127.0.0.1");
    EXPECT_EQ(b->port, 48010);
    EXPECT_EQ(b->path, "/UA/Server");

    auto c = parseEndpointUrl("opc.tcp://[::1]:65535/x");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->host, "::1");
    EXPECT_EQ(c->port, 65535);

    auto d = parseEndpointUrl("opc.tcp://plc-7.example.com");
    ASSERT_TRUE(d);
    EXPECT_EQ(d->host, "plc-7.example.com");
    EXPECT_EQ(d->port, 4840);  // the registered OPC UA port
}

TEST(ClientUrl, RejectsMalformedUrls) {
    for (const char* url :
         {"", "opc.tcp://", "http://host:4840", "opc.tcp:/host:4840", "opc.tcp://:4840",
          "opc.tcp://host:", "opc.tcp://host:0", "opc.tcp://host:65536", "opc.tcp://host:12a",
          "opc.tcp://host:4840:1", "opc.tcp://ho st:4840", "opc.tcp://::1:4840", "opc.tcp://[::1",
          "opc.tcp://[::1]x", "opc.tcp://[]:4840", "opc.tcp://host:123456", "opc.tcp://h\tst:1"}) {
        auto r = parseEndpointUrl(url);
        EXPECT_FALSE(r) << url;
        EXPECT_EQ(r.status(), status::BadTcpEndpointUrlInvalid) << url;
    }
}

// ---- helpers ----

/// Runs the io_context until `done` or a safety deadline, so a hang fails instead of
/// blocking the test run.
void runUntil(asio::io_context& io, const bool& done, std::chrono::seconds limit = 10s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done && std::chrono::steady_clock::now() < deadline) {
        io.run_for(20ms);
        if (io.stopped()) io.restart();
    }
    ASSERT_TRUE(done) << "test did not finish in time";
}

std::string urlFor(const tcp::acceptor& a) {
    return "opc.tcp://127.0.0.1:" + std::to_string(a.local_endpoint().port());
}

/// Runs a Client's connect() to the fake server behind `acceptor` and returns its status
/// (std::nullopt if it never finished within runUntil's bound).
std::optional<StatusCode> connectTo(asio::io_context& io, Client& client, tcp::acceptor& acceptor) {
    std::optional<StatusCode> result;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            result = co_await client.connect(urlFor(acceptor), {});
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    return result;
}

asio::awaitable<std::vector<std::uint8_t>> readRawFrame(tcp::socket& s) {
    std::vector<std::uint8_t> frame(kMessageHeaderSize);
    auto [ec, n] = co_await asio::async_read(s, asio::buffer(frame), kNoThrow);
    if (ec) co_return std::vector<std::uint8_t>{};
    std::uint32_t size = 0;
    std::memcpy(&size, frame.data() + 4, 4);
    if (size < kMessageHeaderSize) co_return std::vector<std::uint8_t>{};
    frame.resize(size);
    auto [ec2, n2] = co_await asio::async_read(
        s, asio::buffer(frame.data() + kMessageHeaderSize, size - kMessageHeaderSize), kNoThrow);
    if (ec2) co_return std::vector<std::uint8_t>{};
    co_return frame;
}

/// A UA-TCP frame built by hand, independent of the transport's encoders.
std::vector<std::uint8_t> handFrame(const char (&type)[4], const std::vector<std::uint8_t>& body) {
    std::vector<std::uint8_t> f{static_cast<std::uint8_t>(type[0]),
                                static_cast<std::uint8_t>(type[1]),
                                static_cast<std::uint8_t>(type[2]), 'F'};
    const auto size = static_cast<std::uint32_t>(kMessageHeaderSize + body.size());
    for (int i = 0; i < 4; ++i) f.push_back(static_cast<std::uint8_t>(size >> (8 * i)));
    f.insert(f.end(), body.begin(), body.end());
    return f;
}

void putU32(std::vector<std::uint8_t>& v, std::uint32_t x) {
    for (int i = 0; i < 4; ++i) v.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
}

std::vector<std::uint8_t> handAck() {
    std::vector<std::uint8_t> body;
    putU32(body, 0);        // protocol version
    putU32(body, 65535);    // receive buffer
    putU32(body, 65535);    // send buffer
    putU32(body, 1 << 24);  // max message size
    putU32(body, 0);        // max chunk count: no limit
    return handFrame("ACK", body);
}

std::vector<std::uint8_t> handError(StatusCode s) {
    std::vector<std::uint8_t> body;
    putU32(body, s.code);
    const std::string reason = "go away";
    putU32(body, static_cast<std::uint32_t>(reason.size()));
    body.insert(body.end(), reason.begin(), reason.end());
    return handFrame("ERR", body);
}

// ---- connect failures ----

TEST(ClientConnect, TimesOutWhenHelloIsNeverAnswered) {
    asio::io_context io;
    // Listening but never accepting: the kernel completes the TCP handshake, nobody answers.
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
    Client client(io.get_executor());
    ClientConfig config;
    config.connectTimeout = 300ms;
    std::optional<StatusCode> result;
    bool done = false;
    const auto start = std::chrono::steady_clock::now();
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            result = co_await client.connect(urlFor(acceptor), config);
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    const auto elapsed = std::chrono::steady_clock::now() - start;
    EXPECT_EQ(result, status::BadTimeout);
    EXPECT_GE(elapsed, 250ms);
    EXPECT_LT(elapsed, 1500ms);
    EXPECT_FALSE(client.isConnected());
}

TEST(ClientConnect, ClosedPortIsConnectionRejected) {
    asio::io_context io;
    std::string url;
    {
        tcp::acceptor probe(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
        url = urlFor(probe);
    }  // closed again: connecting to it is refused
    Client client(io.get_executor());
    std::optional<StatusCode> result;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            result = co_await client.connect(url, {});
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(result, status::BadConnectionRejected);
}

TEST(ClientConnect, MalformedUrlFailsWithoutNetwork) {
    asio::io_context io;
    Client client(io.get_executor());
    std::optional<StatusCode> result;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            result = co_await client.connect("opc.tcp://no port:x", {});
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(result, status::BadTcpEndpointUrlInvalid);
}

TEST(ClientConnect, ErrInsteadOfAckIsReported) {
    asio::io_context io;
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            auto [ec, s] = co_await acceptor.async_accept(kNoThrow);
            if (ec) co_return;
            co_await readRawFrame(s);
            co_await asio::async_write(s, asio::buffer(handError(status::BadTcpServerTooBusy)),
                                       kNoThrow);
            co_await readRawFrame(s);  // until the client hangs up
        },
        asio::detached);
    Client client(io.get_executor());
    const std::optional<StatusCode> result = connectTo(io, client, acceptor);
    EXPECT_EQ(result, status::BadTcpServerTooBusy);
}

TEST(ClientConnect, ErrAfterAckIsReported) {
    asio::io_context io;
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
    bool sawOpn = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            auto [ec, s] = co_await acceptor.async_accept(kNoThrow);
            if (ec) co_return;
            const auto hello = co_await readRawFrame(s);
            if (hello.size() < 4 || hello[0] != 'H') co_return;
            co_await asio::async_write(s, asio::buffer(handAck()), kNoThrow);
            const auto opn = co_await readRawFrame(s);
            sawOpn = opn.size() > 4 && opn[0] == 'O' && opn[1] == 'P' && opn[2] == 'N';
            co_await asio::async_write(s, asio::buffer(handError(status::BadSecurityChecksFailed)),
                                       kNoThrow);
            co_await readRawFrame(s);
        },
        asio::detached);
    Client client(io.get_executor());
    const std::optional<StatusCode> result = connectTo(io, client, acceptor);
    EXPECT_TRUE(sawOpn);
    EXPECT_EQ(result, status::BadSecurityChecksFailed);
    EXPECT_FALSE(client.isConnected());
}

TEST(ClientRequests, FailWhenNotConnected) {
    asio::io_context io;
    Client client(io.get_executor());
    std::optional<StatusCode> result;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            auto v = co_await client.readValue(NodeId(2258));
            result = v.status();
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(result, status::BadServerNotConnected);
}

// ---- a scripted server on our SecureChannel ----

/// One accepted connection: Hello/Acknowledge, OPN answered by SecureChannel::openOrRenew,
/// CreateSession/ActivateSession/CloseSession answered here, every other request handed to
/// `onRequest`, which answers through `reply` (now, later, or never).
class FakeServer {
public:
    struct Request {
        std::uint32_t requestId = 0;
        NodeId type;
        std::vector<std::uint8_t> body;  // the whole message body, type NodeId included
    };
    using OnRequest = std::function<void(FakeServer&, Request)>;

    FakeServer(asio::io_context& io, OnRequest onRequest)
        : io_(io),
          acceptor_(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0)),
          socket_(io),
          onRequest_(std::move(onRequest)) {
        asio::co_spawn(io, serve(), asio::detached);
    }

    [[nodiscard]] std::string url() const { return urlFor(acceptor_); }

    template <EncodableStructure Resp>
    void reply(std::uint32_t requestId, Resp response) {
        auto body = client_detail::encodeBody(response);
        send(MessageType::Message, requestId, *body);
    }
    void fault(std::uint32_t requestId, StatusCode s) {
        ServiceFault f;
        f.responseHeader.serviceResult = s;
        reply(requestId, f);
    }
    void drop() {
        std::error_code ignored;
        socket_.close(ignored);
    }

    std::string anonymousPolicyIdSeen;
    NodeId authenticationTokenSeen;
    int closeSessionCount = 0;
    int closeChannelCount = 0;

private:
    void send(MessageType type, std::uint32_t requestId, std::span<const std::uint8_t> body) {
        auto frames = channel_->encodeMessage(type, requestId, body);
        ASSERT_TRUE(frames);
        for (auto& f : *frames) {
            out_.push_back(std::move(f));
        }
        if (!writing_) {
            writing_ = true;
            asio::co_spawn(io_, writeAll(), asio::detached);
        }
    }

    asio::awaitable<void> writeAll() {
        while (!out_.empty()) {
            auto f = std::move(out_.front());
            out_.erase(out_.begin());
            auto [ec, n] = co_await asio::async_write(socket_, asio::buffer(f), kNoThrow);
            if (ec) break;
        }
        writing_ = false;
    }

    asio::awaitable<void> serve() {
        auto [ec] = co_await acceptor_.async_accept(socket_, kNoThrow);
        if (ec) co_return;
        auto hello = decodeHello(co_await readRawFrame(socket_));
        if (!hello) co_return;
        auto negotiated = negotiateAsServer(TransportLimits{}, *hello);
        if (!negotiated) co_return;
        const auto ack = encodeAcknowledge(negotiated->ack);
        co_await asio::async_write(socket_, asio::buffer(ack), kNoThrow);
        channel_.emplace(SecureChannel::Role::Server, negotiated->limits,
                         std::make_unique<SecurityPolicyNone>());
        for (;;) {
            auto frame = co_await readRawFrame(socket_);
            if (frame.empty()) co_return;
            auto message = channel_->receiveFrame(frame, std::chrono::steady_clock::now());
            if (!message || !message->has_value()) continue;
            auto& m = **message;
            BinaryReader r(m.body);
            NodeId type;
            decode(r, type);
            if (m.type == MessageType::CloseChannel) {
                ++closeChannelCount;
                continue;
            }
            if (m.type == MessageType::OpenChannel) {
                OpenSecureChannelRequest req;
                decode(r, req);
                auto resp = channel_->openOrRenew(req, 42, std::chrono::steady_clock::now());
                if (!resp) co_return;
                auto body = client_detail::encodeBody(*resp);
                send(MessageType::OpenChannel, m.requestId, *body);
                continue;
            }
            if (type == NodeId(CreateSessionRequest::kBinaryEncodingId)) {
                CreateSessionResponse resp;
                resp.sessionId = NodeId(1, "session");
                resp.authenticationToken = NodeId(1, "secret-token");
                resp.revisedSessionTimeout = 60000;
                EndpointDescription ep;
                ep.securityPolicyUri = String(kSecurityPolicyNoneUri);
                ep.securityMode = MessageSecurityMode::None;
                ep.userIdentityTokens.push_back(
                    UserTokenPolicy{"user", UserTokenType::UserName, {}, {}, {}});
                ep.userIdentityTokens.push_back(
                    UserTokenPolicy{"anon-policy", UserTokenType::Anonymous, {}, {}, {}});
                resp.serverEndpoints.push_back(ep);
                reply(m.requestId, resp);
            } else if (type == NodeId(ActivateSessionRequest::kBinaryEncodingId)) {
                ActivateSessionRequest req;
                decode(r, req);
                authenticationTokenSeen = req.requestHeader.authenticationToken;
                AnonymousIdentityToken token;
                if (fromExtensionObject(req.userIdentityToken, token).isGood()) {
                    anonymousPolicyIdSeen = token.policyId;
                }
                reply(m.requestId, ActivateSessionResponse{});
            } else if (type == NodeId(CloseSessionRequest::kBinaryEncodingId)) {
                ++closeSessionCount;
                reply(m.requestId, CloseSessionResponse{});
            } else {
                onRequest_(*this, Request{m.requestId, type, std::move(m.body)});
            }
        }
    }

    asio::io_context& io_;
    tcp::acceptor acceptor_;
    tcp::socket socket_;
    OnRequest onRequest_;
    std::optional<SecureChannel> channel_;
    std::vector<std::vector<std::uint8_t>> out_;
    bool writing_ = false;
};

ReadResponse readResponseWith(Variant v) {
    ReadResponse resp;
    DataValue dv;
    dv.value = std::move(v);
    resp.results.push_back(std::move(dv));
    return resp;
}

/// Reads the NodeId of the single ReadValueId in a ReadRequest body.
NodeId readTarget(const FakeServer::Request& req) {
    BinaryReader r(req.body);
    NodeId type;
    decode(r, type);
    ReadRequest read;
    decode(r, read);
    return read.nodesToRead.empty() ? NodeId() : read.nodesToRead[0].nodeId;
}

TEST(ClientSession, ConnectsWithAnonymousPolicyFromServerEndpoints) {
    asio::io_context io;
    FakeServer server(io, [](FakeServer& s, FakeServer::Request r) {
        s.reply(r.requestId, readResponseWith(Variant(readTarget(r).numeric() * 2.0)));
    });
    Client client(io.get_executor());
    std::optional<StatusCode> connected;
    std::optional<Result<Variant>> value;
    std::optional<StatusCode> disconnected;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            connected = co_await client.connect(server.url(), {});
            value = co_await client.readValue(NodeId(21));
            disconnected = co_await client.disconnect();
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    ASSERT_EQ(connected, status::Good);
    EXPECT_EQ(server.anonymousPolicyIdSeen, "anon-policy");
    EXPECT_EQ(server.authenticationTokenSeen, NodeId(1, "secret-token"));
    ASSERT_TRUE(value && *value);
    ASSERT_NE((*value)->get<double>(), nullptr);
    EXPECT_EQ(*(*value)->get<double>(), 42.0);
    EXPECT_EQ(disconnected, status::Good);
    EXPECT_EQ(server.closeSessionCount, 1);
    // CLO was written before the client hung up; let the server read it.
    bool drained = false;
    asio::steady_timer t(io, 100ms);
    t.async_wait([&](auto) { drained = true; });
    runUntil(io, drained);
    EXPECT_EQ(server.closeChannelCount, 1);
    EXPECT_FALSE(client.isConnected());
}

TEST(ClientRequests, ResponsesOutOfOrderReachTheirRequests) {
    asio::io_context io;
    std::vector<FakeServer::Request> held;
    FakeServer server(io, [&held](FakeServer& s, FakeServer::Request r) {
        held.push_back(std::move(r));
        if (held.size() < 3) return;
        // Answer the three reads last-first.
        for (auto it = held.rbegin(); it != held.rend(); ++it) {
            s.reply(
                it->requestId,
                readResponseWith(Variant(static_cast<std::int32_t>(readTarget(*it).numeric()))));
        }
    });
    Client client(io.get_executor());
    std::map<int, std::optional<Result<Variant>>> values;
    int finished = 0;
    bool connected = false;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            connected = (co_await client.connect(server.url(), {})).isGood();
            for (int id : {101, 102, 103}) {
                asio::co_spawn(
                    io,
                    [&, id]() -> asio::awaitable<void> {
                        values[id] =
                            co_await client.readValue(NodeId(static_cast<std::uint32_t>(id)));
                        if (++finished == 3) done = true;
                    },
                    asio::detached);
            }
        },
        asio::detached);
    runUntil(io, done);
    ASSERT_TRUE(connected);
    for (int id : {101, 102, 103}) {
        ASSERT_TRUE(values[id] && *values[id]) << id;
        ASSERT_NE((*values[id])->get<std::int32_t>(), nullptr);
        EXPECT_EQ(*(*values[id])->get<std::int32_t>(), id);
    }
}

TEST(ClientRequests, ServiceFaultBecomesItsStatus) {
    asio::io_context io;
    FakeServer server(io, [](FakeServer& s, FakeServer::Request r) {
        s.fault(r.requestId, status::BadNodeIdUnknown);
    });
    Client client(io.get_executor());
    std::optional<StatusCode> result;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if ((co_await client.connect(server.url(), {})).isGood()) {
                result = (co_await client.readValue(NodeId(5))).status();
            }
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(result, status::BadNodeIdUnknown);
}

TEST(ClientRequests, UnansweredRequestTimesOutAndLaterOnesStillWork) {
    asio::io_context io;
    FakeServer server(io, [](FakeServer& s, FakeServer::Request r) {
        if (readTarget(r) == NodeId(1)) return;  // never answered
        s.reply(r.requestId, readResponseWith(Variant(true)));
    });
    Client client(io.get_executor());
    ClientConfig config;
    config.requestTimeout = 200ms;
    std::optional<StatusCode> first;
    std::optional<StatusCode> second;
    std::chrono::steady_clock::duration waited{};
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if ((co_await client.connect(server.url(), config)).isGood()) {
                const auto start = std::chrono::steady_clock::now();
                first = (co_await client.readValue(NodeId(1))).status();
                waited = std::chrono::steady_clock::now() - start;
                second = (co_await client.readValue(NodeId(2))).status();
            }
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(first, status::BadTimeout);
    EXPECT_GE(waited, 150ms);
    EXPECT_LT(waited, 2s);
    EXPECT_EQ(second, status::Good);
}

TEST(ClientRequests, CancelledRequestEndsWithBadRequestCancelledByClient) {
    asio::io_context io;
    asio::cancellation_signal cancel;
    FakeServer server(io, [&cancel](FakeServer& s, FakeServer::Request r) {
        if (readTarget(r) == NodeId(1)) {
            // The request has reached the server: cancel its wait, then answer it anyway
            // (that late reply must be dropped).
            cancel.emit(asio::cancellation_type::terminal);
            s.reply(r.requestId, readResponseWith(Variant(false)));
            return;
        }
        s.reply(r.requestId, readResponseWith(Variant(true)));
    });
    Client client(io.get_executor());
    std::optional<StatusCode> cancelled;
    std::optional<StatusCode> later;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if (!(co_await client.connect(server.url(), {})).isGood()) {
                done = true;
                co_return;
            }
            // Its own coroutine, so that only this request sees the cancellation.
            asio::co_spawn(
                io,
                [&]() -> asio::awaitable<void> {
                    cancelled = (co_await client.readValue(NodeId(1))).status();
                    asio::co_spawn(
                        io,
                        [&]() -> asio::awaitable<void> {
                            later = (co_await client.readValue(NodeId(2))).status();
                            done = true;
                        },
                        asio::detached);
                },
                asio::bind_cancellation_slot(cancel.slot(), asio::detached));
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(cancelled, status::BadRequestCancelledByClient);
    EXPECT_EQ(later, status::Good);
}

TEST(ClientRequests, ShortDeadlineExpiresWhileALongerOneWaits) {
    // One timer serves all requests: an earlier deadline than the armed one must re-arm it.
    asio::io_context io;
    FakeServer server(io, [](FakeServer&, FakeServer::Request) {});  // never answers
    Client client(io.get_executor());
    std::optional<StatusCode> shortOne;
    std::chrono::steady_clock::duration waited{};
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if (!(co_await client.connect(server.url(), {})).isGood()) {
                done = true;
                co_return;
            }
            asio::co_spawn(  // waits for the default 10 s
                io, [&]() -> asio::awaitable<void> { (void)co_await client.readValue(NodeId(1)); },
                asio::detached);
            ReadRequest req;
            ReadValueId id;
            id.nodeId = NodeId(2);
            req.nodesToRead.push_back(id);
            const auto start = std::chrono::steady_clock::now();
            shortOne =
                (co_await client.requestWithin<ReadRequest, ReadResponse>(std::move(req), 200ms))
                    .status();
            waited = std::chrono::steady_clock::now() - start;
            client.abort();
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    EXPECT_EQ(shortOne, status::BadTimeout);
    EXPECT_GE(waited, 150ms);
    EXPECT_LT(waited, 2s);
}

TEST(ClientRequests, LargeMultiChunkResponseArrivesWhole) {
    // Larger than the client's read buffer and than one chunk: frames arrive in pieces
    // and several at a time.
    asio::io_context io;
    ByteString big;
    big.bytes.resize(300'000);
    for (std::size_t i = 0; i < big.bytes.size(); ++i) {
        big.bytes[i] = static_cast<std::uint8_t>(i * 7);
    }
    FakeServer server(io, [&big](FakeServer& s, FakeServer::Request r) {
        s.reply(r.requestId, readResponseWith(Variant(big)));
    });
    Client client(io.get_executor());
    std::optional<Result<Variant>> got;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if ((co_await client.connect(server.url(), {})).isGood()) {
                got = co_await client.readValue(NodeId(1));
            }
            done = true;
        },
        asio::detached);
    runUntil(io, done);
    ASSERT_TRUE(got && *got) << (got ? statusName(got->status()) : "no result");
    const auto* bytes = (*got)->get<ByteString>();
    ASSERT_NE(bytes, nullptr);
    EXPECT_EQ(bytes->bytes, big.bytes);
}

TEST(ClientRequests, DroppedConnectionFailsPendingRequests) {
    asio::io_context io;
    int seen = 0;
    FakeServer server(io, [&seen](FakeServer& s, FakeServer::Request) {
        if (++seen == 2) s.drop();  // two requests in flight, then the line goes dead
    });
    Client client(io.get_executor());
    std::vector<StatusCode> results;
    std::optional<StatusCode> after;
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if (!(co_await client.connect(server.url(), {})).isGood()) {
                done = true;
                co_return;
            }
            for (std::uint32_t id : {1u, 2u}) {
                asio::co_spawn(
                    io,
                    [&, id]() -> asio::awaitable<void> {
                        results.push_back((co_await client.readValue(NodeId(id))).status());
                        if (results.size() == 2) {
                            after = (co_await client.readValue(NodeId(3))).status();
                            done = true;
                        }
                    },
                    asio::detached);
            }
        },
        asio::detached);
    runUntil(io, done);
    ASSERT_EQ(results.size(), 2u);
    EXPECT_EQ(results[0], status::BadConnectionClosed);
    EXPECT_EQ(results[1], status::BadConnectionClosed);
    EXPECT_TRUE(after && after->isBad());
    EXPECT_FALSE(client.isConnected());
}

TEST(ClientRequests, AnEventLoopThatEndsWithARequestInFlightLeavesNothingBehind) {
    // A coroutine with a client of its own (as a ServerWatcher describes a server) waits for
    // a reply that never comes, and the loop ends: a process stopping meanwhile. The waiting
    // request holds the coroutine and the coroutine its connection; the loop's end must
    // destroy them (under AddressSanitizer the rest would be a leak report at exit).
    std::weak_ptr<int> frameAlive;
    bool requested = false;
    {
        asio::io_context io;
        FakeServer server(io, [&requested](FakeServer&, FakeServer::Request) {
            requested = true;  // and never answered
        });
        asio::co_spawn(
            io,
            [&]() -> asio::awaitable<void> {
                auto alive = std::make_shared<int>(0);
                frameAlive = alive;
                Client client(io.get_executor());
                ClientConfig config;
                config.requestTimeout = 60s;
                if ((co_await client.connect(server.url(), config)).isGood()) {
                    (void)co_await client.readValue(NodeId(1));
                }
            },
            asio::detached);
        runUntil(io, requested);
        ASSERT_TRUE(requested);
        EXPECT_FALSE(frameAlive.expired());  // the coroutine waits for its reply
    }
    EXPECT_TRUE(frameAlive.expired());
}

TEST(BlockingClient, ConnectsReadsAndShutsDown) {
    asio::io_context serverIo;
    FakeServer server(serverIo, [](FakeServer& s, FakeServer::Request r) {
        s.reply(r.requestId, readResponseWith(Variant(String("hello"))));
    });
    std::jthread serverThread([&serverIo] { serverIo.run_for(10s); });

    std::optional<Result<Variant>> value;
    {
        BlockingClient client;
        ASSERT_EQ(client.connect(server.url()), status::Good);
        EXPECT_TRUE(client.isConnected());
        value = client.readValue(NodeId(7));
        EXPECT_EQ(client.readAttribute(NodeId(7), AttributeId::Value).status(), status::Good);
    }  // the destructor closes session and channel and joins its thread
    ASSERT_TRUE(value && *value);
    ASSERT_NE((*value)->get<String>(), nullptr);
    EXPECT_EQ(*(*value)->get<String>(), "hello");
    serverIo.stop();
}

TEST(BlockingClient, DestructsCleanlyWithoutConnecting) {
    BlockingClient client;
    EXPECT_FALSE(client.isConnected());
    EXPECT_EQ(client.readValue(NodeId(1)).status(), status::BadServerNotConnected);
}

}  // namespace
}  // namespace skillcell::ua::client_test
