#include "ua/client/client.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <deque>
#include <exception>
#include <new>
#include <optional>
#include <random>
#include <unordered_map>
#include <utility>

#include <asio/co_spawn.hpp>
#include <asio/connect.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/read.hpp>
#include <asio/steady_timer.hpp>
#include <asio/this_coro.hpp>
#include <asio/use_awaitable.hpp>
#include <asio/write.hpp>

#include "ua/transport/secure_channel.hpp"
#include "ua/transport/security_policy.hpp"

namespace skillcell::ua {

namespace {

using asio::ip::tcp;
// Completion token that yields (error_code, ...) instead of throwing.
constexpr auto kNoThrow = asio::experimental::as_tuple(asio::use_awaitable);

SteadyTime steadyNow() {
    return std::chrono::steady_clock::now();
}

/// Network errors as status codes (documented in README.md).
StatusCode statusFromError(const std::error_code& ec) {
    if (ec == asio::error::connection_refused) return status::BadConnectionRejected;
    if (ec == asio::error::timed_out) return status::BadTimeout;
    if (ec == asio::error::eof || ec == asio::error::connection_reset ||
        ec == asio::error::connection_aborted || ec == asio::error::broken_pipe ||
        ec == asio::error::not_connected || ec == asio::error::shut_down) {
        return status::BadConnectionClosed;
    }
    if (ec == asio::error::host_not_found || ec == asio::error::host_not_found_try_again ||
        ec == asio::error::no_data || ec == asio::error::service_not_found ||
        ec == asio::error::network_unreachable || ec == asio::error::host_unreachable ||
        ec == asio::error::network_down || ec == std::errc::address_not_available) {
        return status::BadConnectionRejected;
    }
    return status::BadCommunicationError;
}

StatusCode statusFromException(std::exception_ptr e) {
    try {
        std::rethrow_exception(std::move(e));
    } catch (const std::bad_alloc&) {
        return status::BadOutOfMemory;
    } catch (const std::system_error& err) {
        // Thrown by Asio when an operation starts after its coroutine was cancelled.
        if (err.code() == asio::error::operation_aborted) {
            return status::BadRequestCancelledByClient;
        }
        return statusFromError(err.code());
    } catch (...) {
        return status::BadInternalError;
    }
}

bool isHostChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '.' || c == '_';
}

std::string toLower(std::string_view s) {
    std::string out(s);
    for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

ByteString randomNonce(std::size_t n) {
    std::random_device rd;
    ByteString nonce;
    nonce.bytes.resize(n);
    for (auto& b : nonce.bytes) b = static_cast<std::uint8_t>(rd());
    return nonce;
}

/// The policyId of an anonymous token the server offers, preferring SecurityPolicy None
/// endpoints. node-opcua and others reject an Anonymous token with a policyId they do not
/// know, so guessing is the last resort.
String anonymousPolicyId(const std::vector<EndpointDescription>& endpoints) {
    const String* fallback = nullptr;
    for (const auto& ep : endpoints) {
        for (const auto& token : ep.userIdentityTokens) {
            if (token.tokenType != UserTokenType::Anonymous) continue;
            if (ep.securityPolicyUri == kSecurityPolicyNoneUri) return token.policyId;
            if (fallback == nullptr) fallback = &token.policyId;
        }
    }
    return fallback != nullptr ? *fallback : String("anonymous");
}

struct Frame {
    MessageHeader header;
    std::vector<std::uint8_t> bytes;  // header included
};

}  // namespace

Result<EndpointAddress> parseEndpointUrl(std::string_view url) {
    constexpr std::string_view kScheme = "opc.tcp://";
    const StatusCode bad = status::BadTcpEndpointUrlInvalid;
    if (url.size() <= kScheme.size() || url.size() > kMaxEndpointUrlLength) return bad;
    if (toLower(url.substr(0, kScheme.size())) != kScheme) return bad;
    for (char c : url) {
        if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7F) return bad;
    }
    const auto rest = url.substr(kScheme.size());
    const auto slash = rest.find('/');
    const auto authority = rest.substr(0, slash);

    EndpointAddress out;
    if (slash != std::string_view::npos) out.path = std::string(rest.substr(slash));
    std::string_view host;
    std::string_view afterHost;
    if (!authority.empty() && authority.front() == '[') {
        const auto close = authority.find(']');
        if (close == std::string_view::npos) return bad;
        host = authority.substr(1, close - 1);
        afterHost = authority.substr(close + 1);
        const bool ipv6Chars = std::all_of(host.begin(), host.end(), [](char c) {
            return std::isxdigit(static_cast<unsigned char>(c)) != 0 || c == ':' || c == '.';
        });
        if (!ipv6Chars || host.find(':') == std::string_view::npos) return bad;
    } else {
        const auto colon = authority.find(':');
        host = authority.substr(0, colon);
        afterHost = colon == std::string_view::npos ? std::string_view{} : authority.substr(colon);
        if (!std::all_of(host.begin(), host.end(), isHostChar)) return bad;
    }
    if (host.empty()) return bad;
    out.host = std::string(host);
    if (!afterHost.empty()) {
        if (afterHost.front() != ':') return bad;
        const auto digits = afterHost.substr(1);
        if (digits.empty() || digits.size() > 5) return bad;
        std::uint32_t port = 0;
        for (char c : digits) {
            if (c < '0' || c > '9') return bad;
            port = port * 10 + static_cast<std::uint32_t>(c - '0');
        }
        if (port == 0 || port > 65535) return bad;
        out.port = static_cast<std::uint16_t>(port);
    }
    return out;
}

// Everything tied to one socket. Coroutines that outlive a call (reader, writer, token
// renewal) hold it by shared_ptr and never touch the Client, which may be gone by then.
struct client_detail::Connection {
    struct Pending {
        explicit Pending(const asio::any_io_executor& ex) : timer(ex) {}
        // Doubles as the wake-up: the reader cancels it once `reply` is set, and its expiry
        // is the request's deadline.
        asio::steady_timer timer;
        std::optional<Result<std::vector<std::uint8_t>>> reply;
    };

    Connection(const asio::any_io_executor& ex, const ClientConfig& config)
        : socket(ex),
          resolver(ex),
          watchdog(ex),
          renewTimer(ex),
          drained(ex),
          requestTimeout(config.requestTimeout) {}

    tcp::socket socket;
    tcp::resolver resolver;
    asio::steady_timer watchdog;    // connect timeout
    asio::steady_timer renewTimer;  // next token renewal
    asio::steady_timer drained;     // cancelled whenever the write queue runs empty
    std::optional<SecureChannel> channel;
    std::unordered_map<std::uint32_t, std::shared_ptr<Pending>> pending;
    std::deque<std::vector<std::uint8_t>> writeQueue;
    std::chrono::milliseconds requestTimeout;
    SteadyTime tokenAcceptedAt{};
    StatusCode closeReason = status::BadConnectionClosed;
    std::uint32_t nextRequestId = 1;
    std::uint32_t nextRequestHandle = 1;
    bool writing = false;
    bool closed = false;
    bool timedOut = false;  // the connect watchdog fired

    /// Ends the connection once: every pending request fails with `reason`.
    void close(StatusCode reason) {
        if (closed) return;
        closed = true;
        closeReason = reason;
        std::error_code ignored;
        socket.close(ignored);
        resolver.cancel();
        watchdog.cancel();
        renewTimer.cancel();
        drained.cancel();
        for (auto& [id, p] : pending) {
            p->reply.emplace(reason);
            p->timer.cancel();
        }
        pending.clear();
        writeQueue.clear();
    }
};

namespace {

using client_detail::Connection;

asio::awaitable<Result<Frame>> readFrame(Connection& conn, std::uint32_t maxFrameSize) {
    Frame frame;
    frame.bytes.resize(kMessageHeaderSize);
    auto [ec, n] = co_await asio::async_read(conn.socket, asio::buffer(frame.bytes), kNoThrow);
    if (ec) co_return conn.closed ? conn.closeReason : statusFromError(ec);
    auto header = parseMessageHeader(
        std::span<const std::uint8_t, kMessageHeaderSize>(frame.bytes.data(), kMessageHeaderSize),
        maxFrameSize);
    if (!header) co_return header.status();
    frame.header = *header;
    frame.bytes.resize(frame.header.size);
    auto [ec2, n2] = co_await asio::async_read(conn.socket,
                                               asio::buffer(frame.bytes.data() + kMessageHeaderSize,
                                                            frame.header.size - kMessageHeaderSize),
                                               kNoThrow);
    if (ec2) co_return conn.closed ? conn.closeReason : statusFromError(ec2);
    co_return frame;
}

/// The status an ERR frame carries (BadCommunicationError if it carries none).
StatusCode errorFrameStatus(const Frame& frame) {
    auto err = decodeError(frame.bytes);
    if (!err || !err->error.isBad()) return status::BadCommunicationError;
    return err->error;
}

asio::awaitable<void> writeLoop(std::shared_ptr<Connection> conn) {
    while (!conn->closed && !conn->writeQueue.empty()) {
        // Owned here, not by the queue: close() clears the queue while a write may still
        // be using the buffer.
        auto frame = std::move(conn->writeQueue.front());
        conn->writeQueue.pop_front();
        auto [ec, n] = co_await asio::async_write(conn->socket, asio::buffer(frame), kNoThrow);
        if (ec) conn->close(conn->closed ? conn->closeReason : statusFromError(ec));
    }
    conn->writing = false;
    conn->drained.cancel();
}

/// Queues frames in sequence-number order; one writer coroutine drains the queue so that
/// concurrent requests never interleave their chunks.
void enqueue(const std::shared_ptr<Connection>& conn,
             std::vector<std::vector<std::uint8_t>> frames) {
    for (auto& f : frames) conn->writeQueue.push_back(std::move(f));
    if (conn->writing) return;
    conn->writing = true;
    asio::co_spawn(conn->socket.get_executor(), writeLoop(conn), asio::detached);
}

/// Completes the request waiting for `requestId`, if it still waits (it may have timed out).
void complete(Connection& conn, std::uint32_t requestId, Result<std::vector<std::uint8_t>> reply) {
    auto it = conn.pending.find(requestId);
    if (it == conn.pending.end()) return;
    it->second->reply.emplace(std::move(reply));
    it->second->timer.cancel();
    conn.pending.erase(it);
}

asio::awaitable<void> readLoop(std::shared_ptr<Connection> conn) {
    try {
        while (!conn->closed) {
            auto frame = co_await readFrame(*conn, conn->channel->limits().receiveBufferSize);
            if (conn->closed) co_return;
            if (!frame) {
                conn->close(frame.status());
                co_return;
            }
            switch (frame->header.type) {
                case MessageType::Error:
                    conn->close(errorFrameStatus(*frame));
                    co_return;
                case MessageType::OpenChannel:
                case MessageType::Message:
                case MessageType::CloseChannel: {
                    auto message = conn->channel->receiveFrame(frame->bytes, steadyNow());
                    if (!message) {
                        conn->close(message.status());
                        co_return;
                    }
                    if (message->has_value()) {
                        auto& m = **message;
                        if (m.type == MessageType::CloseChannel) {
                            conn->close(status::BadSecureChannelClosed);
                            co_return;
                        }
                        complete(*conn, m.requestId, std::move(m.body));
                    } else if (const auto& abort = conn->channel->lastAbort()) {
                        // The server gave up on a response it had started to send.
                        complete(
                            *conn, abort->requestId,
                            abort->error.isBad() ? abort->error : status::BadCommunicationError);
                    }
                    break;
                }
                default:
                    conn->close(status::BadTcpMessageTypeInvalid);
                    co_return;
            }
        }
    } catch (...) {
        conn->close(statusFromException(std::current_exception()));
    }
}

asio::awaitable<Result<std::vector<std::uint8_t>>> exchangeOn(std::shared_ptr<Connection> conn,
                                                              MessageType type,
                                                              std::vector<std::uint8_t> body,
                                                              std::chrono::milliseconds timeout) {
    if (conn->closed) co_return conn->closeReason;
    const auto requestId = conn->nextRequestId++;
    auto frames = conn->channel->encodeMessage(type, requestId, body);
    if (!frames) co_return frames.status();
    auto pending = std::make_shared<Connection::Pending>(conn->socket.get_executor());
    pending->timer.expires_after(timeout);
    conn->pending.emplace(requestId, pending);
    enqueue(conn, std::move(*frames));
    while (!pending->reply) {
        auto [ec] = co_await pending->timer.async_wait(kNoThrow);
        if (pending->reply) break;
        if (!ec) {
            conn->pending.erase(requestId);
            co_return status::BadTimeout;
        }
        auto cancelled = (co_await asio::this_coro::cancellation_state).cancelled();
        if (cancelled != asio::cancellation_type::none) {
            conn->pending.erase(requestId);
            co_return status::BadRequestCancelledByClient;
        }
    }
    co_return std::move(*pending->reply);
}

/// Opens (Issue) or renews the channel. Touches only `conn`, so that the renewal coroutine
/// can run it after the Client is gone.
asio::awaitable<StatusCode> openChannel(std::shared_ptr<Connection> conn,
                                        SecurityTokenRequestType type) {
    auto req = conn->channel->makeOpenRequest(type);
    req.requestHeader.timestamp = DateTime::now();
    req.requestHeader.requestHandle = conn->nextRequestHandle++;
    req.requestHeader.timeoutHint = static_cast<std::uint32_t>(conn->requestTimeout.count());
    auto body = client_detail::encodeBody(req);
    if (!body) co_return body.status();
    auto reply =
        co_await exchangeOn(conn, MessageType::OpenChannel, std::move(*body), conn->requestTimeout);
    if (!reply) co_return reply.status();
    auto response = client_detail::decodeBody<OpenSecureChannelResponse>(*reply);
    if (!response) co_return response.status();
    if (conn->closed) co_return conn->closeReason;
    const auto now = steadyNow();
    const StatusCode accepted = conn->channel->acceptOpenResponse(*response, now);
    if (accepted.isGood()) conn->tokenAcceptedAt = now;
    co_return accepted;
}

asio::awaitable<void> renewLoop(std::shared_ptr<Connection> conn) {
    try {
        while (!conn->closed) {
            const auto& token = conn->channel->currentToken();
            if (!token || token->revisedLifetime == 0) co_return;
            // renewalDue() turns true at 75% of the lifetime; wake a little after that.
            const auto lifetime = std::chrono::milliseconds(token->revisedLifetime);
            conn->renewTimer.expires_at(conn->tokenAcceptedAt + lifetime * 3 / 4 +
                                        std::chrono::milliseconds(10));
            auto [ec] = co_await conn->renewTimer.async_wait(kNoThrow);
            if (conn->closed) co_return;
            if (ec || !conn->channel->renewalDue(steadyNow())) continue;
            const StatusCode s = co_await openChannel(conn, SecurityTokenRequestType::Renew);
            if (conn->closed) co_return;
            if (s.isBad()) conn->close(s);
        }
    } catch (...) {
        conn->close(statusFromException(std::current_exception()));
    }
}

/// TCP connect and Hello/Acknowledge, all within config.connectTimeout; on success the
/// connection has its SecureChannel (not yet open).
asio::awaitable<StatusCode> handshake(std::shared_ptr<Connection> conn,
                                      const EndpointAddress& address,
                                      const std::string& endpointUrl, const ClientConfig& config) {
    // The watchdog closes the socket when the deadline passes; the step in progress then
    // fails and `timedOut` tells why.
    conn->watchdog.expires_after(config.connectTimeout);
    conn->watchdog.async_wait([weak = std::weak_ptr(conn)](const std::error_code& ec) {
        if (ec) return;
        if (auto c = weak.lock()) {
            c->timedOut = true;
            c->resolver.cancel();
            std::error_code ignored;
            c->socket.close(ignored);
        }
    });
    const auto failed = [&conn](const std::error_code& ec) {
        return conn->timedOut ? status::BadTimeout : statusFromError(ec);
    };

    auto [rec, endpoints] =
        co_await conn->resolver.async_resolve(address.host, std::to_string(address.port), kNoThrow);
    if (rec) co_return failed(rec);
    auto [cec, ep] = co_await asio::async_connect(conn->socket, endpoints, kNoThrow);
    if (cec) co_return failed(cec);
    std::error_code ignored;
    conn->socket.set_option(tcp::no_delay(true), ignored);

    HelloMessage hello;
    hello.receiveBufferSize = config.limits.receiveBufferSize;
    hello.sendBufferSize = config.limits.sendBufferSize;
    hello.maxMessageSize = config.limits.maxMessageSize;
    hello.maxChunkCount = config.limits.maxChunkCount;
    hello.endpointUrl = endpointUrl;
    const auto helloFrame = encodeHello(hello);
    auto [wec, wn] = co_await asio::async_write(conn->socket, asio::buffer(helloFrame), kNoThrow);
    if (wec) co_return failed(wec);

    auto ackFrame =
        co_await readFrame(*conn, std::max(config.limits.receiveBufferSize, kMinBufferSize));
    conn->watchdog.cancel();
    if (conn->timedOut) co_return status::BadTimeout;
    if (!ackFrame) co_return ackFrame.status();
    if (ackFrame->header.type == MessageType::Error) co_return errorFrameStatus(*ackFrame);
    if (ackFrame->header.type != MessageType::Acknowledge) {
        co_return status::BadTcpMessageTypeInvalid;
    }
    auto ack = decodeAcknowledge(ackFrame->bytes);
    if (!ack) co_return ack.status();
    auto limits = negotiateAsClient(config.limits, *ack);
    if (!limits) co_return limits.status();
    conn->channel.emplace(SecureChannel::Role::Client, *limits,
                          std::make_unique<SecurityPolicyNone>(),
                          SecureChannelConfig{.tokenLifetimeMs = config.tokenLifetimeMs});
    co_return status::Good;
}

}  // namespace

Client::Client(asio::any_io_executor executor) : executor_(std::move(executor)) {}

Client::~Client() {
    abort();
}

void Client::abort() {
    // Subscriptions end quietly: the caller chose to drop the connection.
    endSubscriptions(status::BadConnectionClosed);
    if (conn_) conn_->close(status::BadConnectionClosed);
    conn_.reset();
    resetSession();
}

bool Client::isConnected() const {
    return conn_ && !conn_->closed && conn_->channel && conn_->channel->isOpen();
}

void Client::resetSession() {
    authenticationToken_ = NodeId();
    sessionId_ = NodeId();
}

void Client::fillRequestHeader(RequestHeader& header) {
    fillRequestHeader(header, config_.requestTimeout);
}

void Client::fillRequestHeader(RequestHeader& header, std::chrono::milliseconds timeout) {
    header.authenticationToken = authenticationToken_;
    header.timestamp = DateTime::now();
    header.requestHandle = conn_ ? conn_->nextRequestHandle++ : 0;
    header.timeoutHint = static_cast<std::uint32_t>(timeout.count());
}

asio::awaitable<Result<std::vector<std::uint8_t>>> Client::exchange(
    MessageType type, std::vector<std::uint8_t> body, std::chrono::milliseconds timeout) {
    if (!conn_ || !conn_->channel) co_return status::BadServerNotConnected;
    try {
        co_return co_await exchangeOn(conn_, type, std::move(body), timeout);
    } catch (...) {
        co_return statusFromException(std::current_exception());
    }
}

asio::awaitable<StatusCode> Client::connect(std::string endpointUrl, ClientConfig config) {
    if (conn_ && !conn_->closed) co_return status::BadInvalidState;
    auto address = parseEndpointUrl(endpointUrl);
    if (!address) co_return address.status();
    abort();
    config_ = std::move(config);
    endpointUrl_ = std::move(endpointUrl);
    serverEndpoints_.clear();
    auto conn = std::make_shared<Connection>(executor_, config_);
    conn_ = conn;

    StatusCode result = status::Good;
    try {
        result = co_await handshake(conn, *address, endpointUrl_, config_);
        if (result.isGood()) {
            asio::co_spawn(executor_, readLoop(conn), asio::detached);
            result = co_await openChannel(conn, SecurityTokenRequestType::Issue);
        }
        if (result.isGood()) {
            asio::co_spawn(executor_, renewLoop(conn), asio::detached);
            if (config_.createSession) result = co_await createAndActivateSession();
        }
    } catch (...) {
        result = statusFromException(std::current_exception());
    }
    if (result.isBad()) {
        conn->close(result);
        if (conn_ == conn) abort();
    }
    co_return result;
}

asio::awaitable<StatusCode> Client::createAndActivateSession() {
    CreateSessionRequest create;
    create.clientDescription.applicationUri = config_.applicationUri;
    create.clientDescription.productUri = config_.productUri;
    create.clientDescription.applicationName.text = config_.applicationName;
    create.clientDescription.applicationType = ApplicationType::Client;
    create.endpointUrl = endpointUrl_;
    create.sessionName = config_.sessionName;
    // Some servers insist on a nonce of at least 32 bytes even without security.
    create.clientNonce = randomNonce(32);
    create.requestedSessionTimeout = config_.sessionTimeoutMs;
    create.maxResponseMessageSize = conn_->channel->limits().maxMessageSize;
    auto created = co_await request<CreateSessionRequest, CreateSessionResponse>(std::move(create));
    if (!created) co_return created.status();
    authenticationToken_ = created->authenticationToken;
    sessionId_ = created->sessionId;
    serverEndpoints_ = std::move(created->serverEndpoints);

    ActivateSessionRequest activate;
    activate.userIdentityToken =
        toExtensionObject(AnonymousIdentityToken{anonymousPolicyId(serverEndpoints_)});
    auto activated =
        co_await request<ActivateSessionRequest, ActivateSessionResponse>(std::move(activate));
    if (!activated) {
        resetSession();
        co_return activated.status();
    }
    co_return status::Good;
}

asio::awaitable<StatusCode> Client::disconnect() {
    // Before CloseSession, so that the Publish requests it fails are not reported as a
    // lost session: the caller ends the session on purpose.
    endSubscriptions(status::BadSessionClosed);
    if (!conn_) co_return status::Good;
    auto conn = conn_;
    StatusCode result = status::Good;
    try {
        if (!conn->closed && hasSession()) {
            CloseSessionRequest req;  // named: see ClientConfig on braced temporaries
            auto closed =
                co_await request<CloseSessionRequest, CloseSessionResponse>(std::move(req));
            result = closed.status();
        }
        resetSession();
        if (!conn->closed && conn->channel && conn->channel->isOpen()) {
            CloseSecureChannelRequest req;
            fillRequestHeader(req.requestHeader);
            auto body = client_detail::encodeBody(req);
            auto frames = body ? conn->channel->encodeMessage(MessageType::CloseChannel,
                                                              conn->nextRequestId++, *body)
                               : Result<std::vector<std::vector<std::uint8_t>>>(body.status());
            if (frames) {
                enqueue(conn, std::move(*frames));
                // No response to CLO: wait (briefly) until it is on the wire, then hang up.
                conn->drained.expires_after(std::chrono::seconds(1));
                while (conn->writing && !conn->closed) {
                    auto [ec] = co_await conn->drained.async_wait(kNoThrow);
                    if (!ec) break;
                }
            }
        }
    } catch (...) {
        result = statusFromException(std::current_exception());
    }
    conn->close(status::BadConnectionClosed);
    if (conn_ == conn) abort();
    co_return result;
}

// ---- services ----

asio::awaitable<Result<std::vector<EndpointDescription>>> Client::getEndpoints(
    std::string endpointUrl) {
    GetEndpointsRequest req;
    req.endpointUrl = endpointUrl.empty() ? endpointUrl_ : std::move(endpointUrl);
    auto resp = co_await request<GetEndpointsRequest, GetEndpointsResponse>(std::move(req));
    if (!resp) co_return resp.status();
    co_return std::move(resp->endpoints);
}

asio::awaitable<Result<std::vector<ApplicationDescription>>> Client::findServers(
    std::string endpointUrl) {
    FindServersRequest req;
    req.endpointUrl = endpointUrl.empty() ? endpointUrl_ : std::move(endpointUrl);
    auto resp = co_await request<FindServersRequest, FindServersResponse>(std::move(req));
    if (!resp) co_return resp.status();
    co_return std::move(resp->servers);
}

asio::awaitable<Result<BrowseResponse>> Client::browse(BrowseRequest req) {
    co_return co_await request<BrowseRequest, BrowseResponse>(std::move(req));
}

asio::awaitable<Result<BrowseResult>> Client::browse(NodeId nodeId, BrowseDirection direction,
                                                     NodeId referenceTypeId, bool includeSubtypes,
                                                     std::uint32_t nodeClassMask) {
    BrowseRequest req;
    BrowseDescription d;
    d.nodeId = std::move(nodeId);
    d.browseDirection = direction;
    d.referenceTypeId = std::move(referenceTypeId);
    d.includeSubtypes = includeSubtypes;
    d.nodeClassMask = nodeClassMask;
    req.nodesToBrowse.push_back(std::move(d));
    auto resp = co_await browse(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    if (resp->results[0].statusCode.isBad()) co_return resp->results[0].statusCode;
    co_return std::move(resp->results[0]);
}

asio::awaitable<Result<BrowseNextResponse>> Client::browseNext(BrowseNextRequest req) {
    co_return co_await request<BrowseNextRequest, BrowseNextResponse>(std::move(req));
}

asio::awaitable<Result<BrowseResult>> Client::browseNext(ByteString continuationPoint,
                                                         bool releaseContinuationPoint) {
    BrowseNextRequest req;
    req.releaseContinuationPoints = releaseContinuationPoint;
    req.continuationPoints.push_back(std::move(continuationPoint));
    auto resp = co_await browseNext(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    if (resp->results[0].statusCode.isBad()) co_return resp->results[0].statusCode;
    co_return std::move(resp->results[0]);
}

asio::awaitable<Result<TranslateBrowsePathsToNodeIdsResponse>> Client::translateBrowsePaths(
    TranslateBrowsePathsToNodeIdsRequest req) {
    co_return co_await request<TranslateBrowsePathsToNodeIdsRequest,
                               TranslateBrowsePathsToNodeIdsResponse>(std::move(req));
}

asio::awaitable<Result<NodeId>> Client::translateBrowsePath(NodeId start,
                                                            std::vector<QualifiedName> path) {
    constexpr std::uint32_t kHierarchicalReferences = 33;
    BrowsePath bp;
    bp.startingNode = std::move(start);
    for (auto& name : path) {
        RelativePathElement e;
        e.referenceTypeId = NodeId(kHierarchicalReferences);
        e.targetName = std::move(name);
        bp.relativePath.elements.push_back(std::move(e));
    }
    TranslateBrowsePathsToNodeIdsRequest req;
    req.browsePaths.push_back(std::move(bp));
    auto resp = co_await translateBrowsePaths(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    const auto& r = resp->results[0];
    if (r.statusCode.isBad()) co_return r.statusCode;
    if (r.targets.empty()) co_return status::BadNoMatch;
    // A target in another server has no local NodeId to give back.
    if (r.targets[0].targetId.serverIndex != 0) co_return status::BadNodeIdUnknown;
    co_return r.targets[0].targetId.nodeId;
}

asio::awaitable<Result<std::vector<NodeId>>> Client::registerNodes(std::vector<NodeId> nodes) {
    const auto count = nodes.size();
    RegisterNodesRequest req;
    req.nodesToRegister = std::move(nodes);
    auto resp = co_await request<RegisterNodesRequest, RegisterNodesResponse>(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->registeredNodeIds.size() != count) co_return status::BadUnknownResponse;
    co_return std::move(resp->registeredNodeIds);
}

asio::awaitable<StatusCode> Client::unregisterNodes(std::vector<NodeId> nodes) {
    UnregisterNodesRequest req;
    req.nodesToUnregister = std::move(nodes);
    auto resp = co_await request<UnregisterNodesRequest, UnregisterNodesResponse>(std::move(req));
    co_return resp.status();
}

asio::awaitable<Result<ReadResponse>> Client::read(ReadRequest req) {
    co_return co_await request<ReadRequest, ReadResponse>(std::move(req));
}

asio::awaitable<Result<DataValue>> Client::readAttribute(NodeId nodeId, AttributeId attribute) {
    ReadRequest req;
    ReadValueId id;
    id.nodeId = std::move(nodeId);
    id.attributeId = static_cast<std::uint32_t>(attribute);
    req.nodesToRead.push_back(std::move(id));
    auto resp = co_await read(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    if (resp->results[0].statusOrGood().isBad()) co_return resp->results[0].statusOrGood();
    co_return std::move(resp->results[0]);
}

asio::awaitable<Result<Variant>> Client::readValue(NodeId nodeId) {
    auto dv = co_await readAttribute(std::move(nodeId), AttributeId::Value);
    if (!dv) co_return dv.status();
    co_return dv->value.value_or(Variant());
}

asio::awaitable<Result<WriteResponse>> Client::write(WriteRequest req) {
    co_return co_await request<WriteRequest, WriteResponse>(std::move(req));
}

asio::awaitable<StatusCode> Client::writeAttribute(NodeId nodeId, AttributeId attribute,
                                                   DataValue value) {
    WriteRequest req;
    WriteValue wv;
    wv.nodeId = std::move(nodeId);
    wv.attributeId = static_cast<std::uint32_t>(attribute);
    wv.value = std::move(value);
    req.nodesToWrite.push_back(std::move(wv));
    auto resp = co_await write(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    co_return resp->results[0];
}

asio::awaitable<StatusCode> Client::writeValue(NodeId nodeId, Variant value) {
    DataValue dv;
    dv.value = std::move(value);
    co_return co_await writeAttribute(std::move(nodeId), AttributeId::Value, std::move(dv));
}

asio::awaitable<Result<CallResponse>> Client::call(CallRequest req) {
    co_return co_await request<CallRequest, CallResponse>(std::move(req));
}

asio::awaitable<Result<std::vector<Variant>>> Client::call(NodeId objectId, NodeId methodId,
                                                           std::vector<Variant> inputs) {
    CallRequest req;
    req.methodsToCall.push_back(
        CallMethodRequest{std::move(objectId), std::move(methodId), std::move(inputs)});
    auto resp = co_await call(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return status::BadUnknownResponse;
    auto& r = resp->results[0];
    if (r.statusCode.isBad()) co_return r.statusCode;
    co_return std::move(r.outputArguments);
}

}  // namespace skillcell::ua
