#include "ua/client/client.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <exception>
#include <mutex>
#include <new>
#include <optional>
#include <random>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include <asio/associated_cancellation_slot.hpp>
#include <asio/associated_executor.hpp>
#include <asio/async_result.hpp>
#include <asio/cancellation_signal.hpp>
#include <asio/co_spawn.hpp>
#include <asio/connect.hpp>
#include <asio/detached.hpp>
#include <asio/dispatch.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/post.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <asio/write.hpp>

#include "ua/crypto/security_policy_profile.hpp"
#include "ua/transport/certificate_security_policy.hpp"
#include "ua/transport/no_throw.hpp"
#include "ua/transport/secure_channel.hpp"
#include "ua/transport/security_policy.hpp"

namespace skillcell::ua {

namespace {

using asio::ip::tcp;
// Completion token that yields (error_code, ...) instead of throwing.

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
    return ByteString(crypto::randomBytes(n));
}

bool isSecured(const ClientConfig& config) {
    return config.security.policyUri != kSecurityPolicyNoneUri;
}

/// The token policy of the given type the server offers, preferring the endpoint we are
/// connected through. node-opcua and others reject a token with a policyId they do not
/// know, so guessing ("anonymous") is the last resort for anonymous tokens only.
std::optional<UserTokenPolicy> findTokenPolicy(const std::vector<EndpointDescription>& endpoints,
                                               const ClientConfig& config, UserTokenType type) {
    std::optional<UserTokenPolicy> fallback;
    for (const auto& ep : endpoints) {
        for (const auto& token : ep.userIdentityTokens) {
            if (token.tokenType != type) continue;
            if (ep.securityPolicyUri == config.security.policyUri &&
                ep.securityMode == config.security.mode) {
                return token;
            }
            if (!fallback) fallback = token;
        }
    }
    if (!fallback && type == UserTokenType::Anonymous) {
        UserTokenPolicy guess;
        guess.policyId = "anonymous";
        guess.tokenType = UserTokenType::Anonymous;
        fallback = guess;
    }
    return fallback;
}

/// The profile that secures a user token: its policy's own, else the channel's.
const crypto::SecurityPolicyProfile* tokenProfile(const UserTokenPolicy& policy,
                                                  const ClientConfig& config) {
    return crypto::findSecurityPolicyProfile(
        policy.securityPolicyUri.empty() ? config.security.policyUri : policy.securityPolicyUri);
}

/// The user identity token for ActivateSession (OPC 10000-4, 7.41), with its signature for
/// X.509 tokens. A password is encrypted for the server with the token policy's algorithm
/// (legacy format: length, password, server nonce).
Result<std::pair<ExtensionObject, SignatureData>> makeIdentityToken(
    const std::vector<EndpointDescription>& endpoints, const ClientConfig& config,
    const ByteString& serverCertificate, const ByteString& serverNonce) {
    using Kind = UserCredentials::Kind;
    const auto& user = config.security.user;
    const UserTokenType type = user.kind == Kind::UserName      ? UserTokenType::UserName
                               : user.kind == Kind::Certificate ? UserTokenType::Certificate
                                                                : UserTokenType::Anonymous;
    const auto policy = findTokenPolicy(endpoints, config, type);
    if (!policy) return status::BadIdentityTokenRejected;  // the server does not take it
    if (type == UserTokenType::Anonymous) {
        return std::pair{toExtensionObject(AnonymousIdentityToken{policy->policyId}),
                         SignatureData{}};
    }
    const auto* profile = tokenProfile(*policy, config);
    if (type == UserTokenType::UserName) {
        UserNameIdentityToken token;
        token.policyId = policy->policyId;
        token.userName = user.userName;
        if (profile == nullptr) {
            // A token without a policy of its own on a None channel: never send a password
            // in clear text.
            if (config.security.mode != MessageSecurityMode::SignAndEncrypt) {
                return status::BadSecurityModeInsufficient;
            }
            token.password =
                ByteString(std::vector<std::uint8_t>(user.password.begin(), user.password.end()));
        } else {
            auto key = crypto::AsymmetricKey::fromCertificate(serverCertificate.bytes);
            if (!key) return key.status();
            const auto length =
                static_cast<std::uint32_t>(user.password.size() + serverNonce.bytes.size());
            std::vector<std::uint8_t> plain{
                static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8),
                static_cast<std::uint8_t>(length >> 16), static_cast<std::uint8_t>(length >> 24)};
            plain.insert(plain.end(), user.password.begin(), user.password.end());
            plain.insert(plain.end(), serverNonce.bytes.begin(), serverNonce.bytes.end());
            auto cipher = crypto::rsaEncrypt(*key, profile->asymmetricEncryption, plain);
            if (!cipher) return cipher.status();
            token.password = ByteString(std::move(*cipher));
            token.encryptionAlgorithm = String(profile->asymmetricEncryptionUri);
        }
        return std::pair{toExtensionObject(token), SignatureData{}};
    }
    if (profile == nullptr) return status::BadSecurityPolicyRejected;
    X509IdentityToken token;
    token.policyId = policy->policyId;
    token.certificateData = user.certificate;
    auto signature = crypto::sign(user.privateKey, profile->asymmetricSignature,
                                  certificateAndNonce(serverCertificate, serverNonce));
    if (!signature) return signature.status();
    SignatureData data;
    data.algorithm = String(profile->asymmetricSignatureUri);
    data.signature = ByteString(std::move(*signature));
    return std::pair{toExtensionObject(token), std::move(data)};
}

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

namespace {

/// A request waiting for its reply holds its coroutine (the Waiter in its Connection's
/// `pending`), and the coroutine holds the Connection: a cycle that a reply, a timeout or
/// close() breaks. An event loop that ends with requests in flight (a process stopping
/// while one of its clients connects) would leave the cycle, and all that the coroutines
/// own, behind. This service of the loop destroys those waiters when the loop shuts down,
/// as Asio's own services destroy the handlers they hold.
class PendingRequests final : public asio::execution_context::service {
public:
    using key_type = PendingRequests;
    // NOLINTNEXTLINE(readability-identifier-naming,cppcoreguidelines-avoid-non-const-global-variables):
    // Asio finds a service by this member
    static inline asio::execution_context::id id;

    explicit PendingRequests(asio::execution_context& context) : service(context) {}

    void add(client_detail::Connection* c) {
        const std::lock_guard lock(mutex_);
        live_.insert(c);
    }
    void remove(client_detail::Connection* c) {
        const std::lock_guard lock(mutex_);
        live_.erase(c);
    }

private:
    void shutdown() override;

    std::mutex mutex_;
    std::unordered_set<client_detail::Connection*> live_;
};

}  // namespace

// Everything tied to one socket. Callbacks and coroutines that outlive a call (reader,
// write completions, timers, token renewal) hold it by shared_ptr and never touch the
// Client, which may be gone by then.
struct client_detail::Connection {
    using Reply = Result<std::vector<std::uint8_t>>;

    /// The completion handler of a request coroutine waiting for its reply, type-erased so
    /// that the pending map can hold any of them. Asio 1.22 has no any_completion_handler.
    class Waiter {
    public:
        Waiter() = default;
        template <class Handler>
        Waiter(Handler handler, const asio::any_io_executor& fallback)
            : impl_(std::make_unique<Impl<Handler>>(std::move(handler), fallback)) {}

        /// Resumes the waiting coroutine inside this call when we run on its executor:
        /// the reader uses it so that the next request is sent before the event loop polls
        /// again (a post would cost one more epoll_wait per request).
        void dispatch(Reply reply) { std::exchange(impl_, {})->complete(std::move(reply), false); }
        /// Resumes it later, from the event loop: for completions that come from places
        /// (timer, cancellation, close) that must not run the caller's code re-entrantly.
        void post(Reply reply) { std::exchange(impl_, {})->complete(std::move(reply), true); }

    private:
        struct Base {
            virtual ~Base() = default;
            virtual void complete(Reply reply, bool deferred) = 0;
        };
        template <class Handler>
        struct Impl final : Base {
            Impl(Handler h, const asio::any_io_executor& fallback)
                : handler(std::move(h)),
                  executor(asio::get_associated_executor(handler, fallback)) {}
            void complete(Reply reply, bool deferred) override {
                auto f = [h = std::move(handler), r = std::move(reply)]() mutable {
                    std::move(h)(std::move(r));
                };
                if (deferred) {
                    asio::post(executor, std::move(f));
                } else {
                    asio::dispatch(executor, std::move(f));
                }
            }
            Handler handler;
            asio::associated_executor_t<Handler, asio::any_io_executor> executor;
        };
        std::unique_ptr<Base> impl_;
    };

    struct Pending {
        SteadyTime deadline;
        Waiter waiter;
        // The awaiting coroutine's cancellation slot (may be unconnected); cleared before
        // the waiter completes so that a later cancellation cannot reach a finished request.
        asio::cancellation_slot cancelSlot;
    };

    Connection(const asio::any_io_executor& ex, const ClientConfig& config)
        : socket(ex),
          resolver(ex),
          watchdog(ex),
          renewTimer(ex),
          requestTimer(ex),
          drained(ex),
          requestTimeout(config.requestTimeout),
          requests(asio::use_service<PendingRequests>(asio::query(ex, asio::execution::context))) {
        requests.add(this);
    }
    ~Connection() { requests.remove(this); }
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    tcp::socket socket;
    tcp::resolver resolver;
    asio::steady_timer watchdog;      // connect timeout
    asio::steady_timer renewTimer;    // next token renewal
    asio::steady_timer requestTimer;  // the earliest request deadline (or earlier)
    asio::steady_timer drained;       // cancelled whenever an async write drains the queue
    std::optional<SecureChannel> channel;
    std::unordered_map<std::uint32_t, Pending> pending;
    // Received bytes not yet cut into frames: [inBegin, inEnd) of `in`.
    std::vector<std::uint8_t> in;
    std::size_t inBegin = 0;
    std::size_t inEnd = 0;
    // Frames waiting for the write in flight to finish, in sequence-number order.
    std::vector<std::vector<std::uint8_t>> writeQueue;
    // The frames of the write in flight; owned here, not by the queue, because close()
    // clears the queue while the kernel may still be reading these buffers. Only the write
    // completion releases them.
    std::vector<std::vector<std::uint8_t>> inFlight;
    std::chrono::milliseconds requestTimeout;
    SteadyTime tokenAcceptedAt{};
    // When the armed requestTimer wait fires; nullopt when no wait is armed.
    std::optional<SteadyTime> requestTimerAt;
    std::uint64_t requestTimerGeneration = 0;  // tells a superseded wait from the armed one
    StatusCode closeReason = status::BadConnectionClosed;
    std::uint32_t nextRequestId = 1;
    std::uint32_t nextRequestHandle = 1;
    std::uint64_t requestsSent = 0;
    bool writing = false;  // an async write is in flight (then frames go to writeQueue)
    bool closed = false;
    bool timedOut = false;      // the connect watchdog fired
    PendingRequests& requests;  // of the event loop, which outlives its sockets

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
        requestTimer.cancel();
        requestTimerAt.reset();
        drained.cancel();
        auto failed = std::exchange(pending, {});
        for (auto& [id, p] : failed) {
            p.cancelSlot.clear();
            p.waiter.post(reason);
        }
        writeQueue.clear();
    }
};

void PendingRequests::shutdown() {
    // Taken under the lock, destroyed after it: destroying a coroutine may end a Connection,
    // whose destructor comes back here.
    std::vector<std::unordered_map<std::uint32_t, client_detail::Connection::Pending>> taken;
    {
        const std::lock_guard lock(mutex_);
        for (auto* c : live_) {
            for (auto& entry : c->pending) entry.second.cancelSlot.clear();
            taken.push_back(std::exchange(c->pending, {}));
        }
    }
    taken.clear();
}

namespace {

using client_detail::Connection;

/// A frame cut out of Connection::in; valid until the next readFrame on that connection.
struct FrameView {
    MessageHeader header;
    std::span<const std::uint8_t> bytes;  // header included
};

/// Room for many small frames per read system call; grows to the frame size for larger ones.
constexpr std::size_t kInitialReadBuffer = std::size_t{64} * 1024;

/// The next frame: cut out of what is buffered, reading more only when it holds no whole
/// frame. Reading into a large buffer takes whatever the socket has in one call, and a
/// read that leaves the buffer partly empty tells Asio the socket is drained, so that the
/// next read waits for readiness instead of trying (and failing) a speculative recv.
asio::awaitable<Result<FrameView>> readFrame(Connection& conn, std::uint32_t maxFrameSize) {
    if (conn.in.empty()) conn.in.resize(kInitialReadBuffer);
    std::optional<MessageHeader> header;
    for (;;) {
        const std::size_t buffered = conn.inEnd - conn.inBegin;
        if (!header && buffered >= kMessageHeaderSize) {
            auto parsed = parseMessageHeader(std::span<const std::uint8_t, kMessageHeaderSize>(
                                                 conn.in.data() + conn.inBegin, kMessageHeaderSize),
                                             maxFrameSize);
            if (!parsed) co_return parsed.status();
            header = *parsed;
        }
        const std::size_t need = header ? header->size : kMessageHeaderSize;
        if (header && buffered >= need) {
            FrameView frame{*header, std::span(conn.in.data() + conn.inBegin, need)};
            conn.inBegin += need;
            co_return frame;
        }
        if (buffered == 0 || conn.in.size() - conn.inBegin < need || conn.inEnd == conn.in.size()) {
            // Move the partial frame to the front (the previous frame's view is dead now).
            std::memmove(conn.in.data(), conn.in.data() + conn.inBegin, buffered);
            conn.inBegin = 0;
            conn.inEnd = buffered;
            if (conn.in.size() < need) conn.in.resize(need);
        }
        auto [ec, n] = co_await conn.socket.async_read_some(
            asio::buffer(conn.in.data() + conn.inEnd, conn.in.size() - conn.inEnd), kNoThrow);
        if (ec) co_return conn.closed ? conn.closeReason : statusFromError(ec);
        conn.inEnd += n;
    }
}

/// The status an ERR frame carries (BadCommunicationError if it carries none).
StatusCode errorFrameStatus(const FrameView& frame) {
    auto err = decodeError(frame.bytes);
    if (!err || !err->error.isBad()) return status::BadCommunicationError;
    return err->error;
}

std::size_t totalSize(const std::vector<std::vector<std::uint8_t>>& frames) {
    std::size_t n = 0;
    for (const auto& f : frames) n += f.size();
    return n;
}

void startWrite(const std::shared_ptr<Connection>& conn, std::size_t skip);

/// Completion of an async write: frees its frames, then writes whatever queued up meanwhile.
void writeDone(const std::shared_ptr<Connection>& conn, const std::error_code& ec) {
    conn->inFlight.clear();
    if (ec) conn->close(conn->closed ? conn->closeReason : statusFromError(ec));
    if (conn->closed || conn->writeQueue.empty()) {
        conn->writing = false;
        conn->drained.cancel();
        return;
    }
    conn->inFlight = std::exchange(conn->writeQueue, {});
    startWrite(conn, 0);
}

/// Writes conn->inFlight, less its first `skip` bytes (already sent), asynchronously.
void startWrite(const std::shared_ptr<Connection>& conn, std::size_t skip) {
    std::vector<asio::const_buffer> buffers;
    buffers.reserve(conn->inFlight.size());
    for (const auto& f : conn->inFlight) {
        if (skip >= f.size()) {
            skip -= f.size();
            continue;
        }
        buffers.emplace_back(f.data() + skip, f.size() - skip);
        skip = 0;
    }
    asio::async_write(conn->socket, buffers,
                      [conn](const std::error_code& ec, std::size_t) { writeDone(conn, ec); });
}

/// Sends frames in sequence-number order without interleaving the chunks of concurrent
/// requests. With no write in flight, the frames go to the kernel right here (the socket is
/// non-blocking): usually all of them, and then nothing is posted and no coroutine wakes.
/// Whatever the kernel does not take goes to an async write; frames arriving while it is
/// in flight queue behind it.
void send(const std::shared_ptr<Connection>& conn, std::vector<std::vector<std::uint8_t>> frames) {
    if (conn->closed || frames.empty()) return;
    if (conn->writing) {
        for (auto& f : frames) conn->writeQueue.push_back(std::move(f));
        return;
    }
    std::error_code ec;
    std::size_t sent = 0;
    if (frames.size() == 1) {
        sent = conn->socket.write_some(asio::buffer(frames.front()), ec);
    } else {
        std::vector<asio::const_buffer> buffers;
        buffers.reserve(frames.size());
        for (const auto& f : frames) buffers.emplace_back(asio::buffer(f));
        sent = conn->socket.write_some(buffers, ec);
    }
    if (ec && ec != asio::error::would_block && ec != asio::error::try_again) {
        conn->close(statusFromError(ec));
        return;
    }
    if (sent == totalSize(frames)) return;
    conn->writing = true;
    conn->inFlight = std::move(frames);
    startWrite(conn, sent);
}

void armRequestTimer(const std::shared_ptr<Connection>& conn, SteadyTime deadline);

/// The request timer fired: fails every request whose deadline passed, then waits for the
/// earliest remaining deadline.
void onRequestTimer(const std::shared_ptr<Connection>& conn, std::uint64_t generation,
                    const std::error_code& ec) {
    // Cancelled (close) or superseded by an earlier deadline: that wait is in charge now.
    if (ec || conn->closed || generation != conn->requestTimerGeneration) return;
    conn->requestTimerAt.reset();
    const auto now = std::chrono::steady_clock::now();
    std::optional<SteadyTime> next;
    for (auto it = conn->pending.begin(); it != conn->pending.end();) {
        if (it->second.deadline <= now) {
            auto p = std::move(it->second);
            it = conn->pending.erase(it);
            p.cancelSlot.clear();
            p.waiter.post(status::BadTimeout);
        } else {
            if (!next || it->second.deadline < *next) next = it->second.deadline;
            ++it;
        }
    }
    if (next) armRequestTimer(conn, *next);
}

/// Makes sure the request timer fires no later than `deadline`. One timer serves all
/// requests, and it is re-armed only when a deadline is earlier than the armed one, so
/// that a request usually costs no timer system call: with equal timeouts, deadlines only
/// grow, and a timer firing before the earliest live deadline (its request was answered)
/// just re-arms for that one.
void armRequestTimer(const std::shared_ptr<Connection>& conn, SteadyTime deadline) {
    if (conn->requestTimerAt && *conn->requestTimerAt <= deadline) return;
    conn->requestTimerAt = deadline;
    const auto generation = ++conn->requestTimerGeneration;
    conn->requestTimer.expires_at(deadline);  // cancels a later wait; its handler returns
    conn->requestTimer.async_wait(
        [conn, generation](const std::error_code& ec) { onRequestTimer(conn, generation, ec); });
}

/// Completes the request waiting for `requestId`, if it still waits (it may have timed
/// out or been cancelled). The waiter runs inside this call.
void complete(Connection& conn, std::uint32_t requestId, Connection::Reply reply) {
    auto it = conn.pending.find(requestId);
    if (it == conn.pending.end()) return;
    auto p = std::move(it->second);
    conn.pending.erase(it);
    p.cancelSlot.clear();
    p.waiter.dispatch(std::move(reply));
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

/// Cancellation of a waiting request (per-operation cancellation of its coroutine).
struct CancelPending {
    std::weak_ptr<Connection> conn;
    std::uint32_t requestId;
    void operator()(asio::cancellation_type type) const {
        if ((type & (asio::cancellation_type::terminal | asio::cancellation_type::partial |
                     asio::cancellation_type::total)) == asio::cancellation_type::none) {
            return;
        }
        auto c = conn.lock();
        if (!c) return;
        auto it = c->pending.find(requestId);
        if (it == c->pending.end()) return;
        // Not clearing the slot: this handler lives in it. It stays harmless there, since
        // it finds no pending request under this id any more.
        auto p = std::move(it->second);
        c->pending.erase(it);
        p.waiter.post(status::BadRequestCancelledByClient);
    }
};

asio::awaitable<Result<std::vector<std::uint8_t>>> exchangeOn(std::shared_ptr<Connection> conn,
                                                              MessageType type,
                                                              std::vector<std::uint8_t> body,
                                                              std::chrono::milliseconds timeout) {
    if (conn->closed) co_return conn->closeReason;
    const auto requestId = conn->nextRequestId++;
    ++conn->requestsSent;
    auto frames = conn->channel->encodeMessage(type, requestId, body);
    if (!frames) co_return frames.status();
    const auto deadline = steadyNow() + timeout;
    // The request waits in `pending` with its completion handler; the reader, the request
    // timer, a cancellation or close() takes it out and completes it exactly once.
    auto initiate = [&conn, &frames, requestId, deadline](auto handler) {
        const auto ex = conn->socket.get_executor();
        if (conn->closed) {
            Connection::Waiter(std::move(handler), ex).post(conn->closeReason);
            return;
        }
        auto slot = asio::get_associated_cancellation_slot(handler);
        Connection::Pending p{deadline, Connection::Waiter(std::move(handler), ex), slot};
        if (slot.is_connected()) slot.assign(CancelPending{conn, requestId});
        conn->pending.emplace(requestId, std::move(p));
        armRequestTimer(conn, deadline);
        send(conn, std::move(*frames));
        // The analyzer loses the Waiter once it is in `pending` (a map in a shared_ptr'd
        // Connection) and calls it a leak; the ASan runs of every test (detect_leaks=1) find none.
    };  // NOLINT(clang-analyzer-cplusplus.NewDeleteLeaks)
    co_return co_await asio::async_initiate<decltype(asio::use_awaitable), void(Connection::Reply)>(
        initiate, asio::use_awaitable);
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
    // Closed (aborted) while the name was resolved, after the resolver had finished: the
    // socket must not be opened again, with no watchdog left to bound it.
    if (conn->closed) co_return conn->closeReason;
    auto [cec, ep] = co_await asio::async_connect(conn->socket, endpoints, kNoThrow);
    if (cec) co_return failed(cec);
    if (conn->closed) co_return conn->closeReason;
    std::error_code ignored;
    conn->socket.set_option(tcp::no_delay(true), ignored);
    // send() writes synchronously first and must not block: what the kernel does not take
    // goes to an async write instead. Async operations are unaffected by this mode.
    std::error_code nbec;
    conn->socket.non_blocking(true, nbec);
    if (nbec) co_return failed(nbec);

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
    SecureChannelConfig channelConfig;
    channelConfig.tokenLifetimeMs = config.tokenLifetimeMs;
    std::unique_ptr<SecurityPolicy> policy = std::make_unique<SecurityPolicyNone>();
    if (isSecured(config)) {
        const auto* profile = crypto::findSecurityPolicyProfile(config.security.policyUri);
        if (profile == nullptr) co_return status::BadSecurityPolicyRejected;
        auto secured = createCertificateSecurityPolicy(
            *profile, config.security.certificate, config.security.privateKey,
            config.serverCertificate, config.security.mode);
        if (!secured) co_return secured.status();
        policy = std::move(*secured);
        channelConfig.securityMode = config.security.mode;
    }
    conn->channel.emplace(SecureChannel::Role::Client, *limits, std::move(policy), channelConfig);
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

std::uint64_t Client::requestsSent() const {
    return conn_ ? conn_->requestsSent : 0;
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
    if (isSecured(config_)) {
        if (const StatusCode s = co_await prepareSecurity(); s.isBad()) co_return s;
    }
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

namespace {

/// Whether we have a certificate and key for `profile`'s kind of key.
bool canUse(const crypto::SecurityPolicyProfile& profile, const ClientSecurity& security) {
    const auto has = [&profile](const ByteString& certificate, const crypto::AsymmetricKey& key) {
        return !certificate.empty() && key.valid() && key.kind() == profile.keyKind;
    };
    const bool own = has(security.certificate, security.privateKey);
    const bool second = has(security.eccCertificate, security.eccPrivateKey);
    // An X.509 user signs with the channel's algorithm: a user certificate of another kind
    // fits only when it is the application's, which useCertificateFor() swaps with it.
    const auto& user = security.user;
    if (user.kind == UserCredentials::Kind::Certificate && user.privateKey.valid() &&
        user.privateKey.kind() != profile.keyKind &&
        !(second && user.certificate == security.certificate)) {
        return false;
    }
    return own || second;
}

/// Makes the certificate of `profile`'s kind the channel's (and the user's, when the user is
/// the application): an ECC channel signs with ECDSA, and so does its X.509 user token.
void useCertificateFor(const crypto::SecurityPolicyProfile& profile, ClientSecurity& security) {
    if (security.privateKey.kind() == profile.keyKind || !security.eccPrivateKey.valid() ||
        security.eccPrivateKey.kind() != profile.keyKind) {
        return;
    }
    auto& user = security.user;
    if (user.kind == UserCredentials::Kind::Certificate &&
        user.certificate == security.certificate) {
        user.certificate = security.eccCertificate;
        user.privateKey = security.eccPrivateKey;
    }
    std::swap(security.certificate, security.eccCertificate);
    std::swap(security.privateKey, security.eccPrivateKey);
}

/// How much an endpoint protects: SignAndEncrypt over Sign, then the server's own ranking
/// (securityLevel), then the stronger policy of ours. 0: not one we can use.
int endpointStrength(const EndpointDescription& ep, const ClientSecurity& security,
                     bool createsSession) {
    // A password or a certificate goes only where the endpoint takes one (a password not
    // over ECC_nistP256, for one).
    const auto userKind = security.user.kind;
    if (createsSession && userKind != UserCredentials::Kind::Anonymous) {
        const UserTokenType wanted = userKind == UserCredentials::Kind::UserName
                                         ? UserTokenType::UserName
                                         : UserTokenType::Certificate;
        if (std::none_of(ep.userIdentityTokens.begin(), ep.userIdentityTokens.end(),
                         [wanted](const UserTokenPolicy& t) { return t.tokenType == wanted; })) {
            return 0;
        }
    }
    if (ep.securityPolicyUri == kSecurityPolicyNoneUri) {
        return security.allowNone && ep.securityMode == MessageSecurityMode::None ? 1 : 0;
    }
    const auto* profile = crypto::findSecurityPolicyProfile(ep.securityPolicyUri);
    // Our certificates' keys decide between the RSA and the ECC policies.
    if (profile == nullptr || !canUse(*profile, security) || ep.serverCertificate.empty()) {
        return 0;
    }
    int modeRank = 0;
    if (ep.securityMode == MessageSecurityMode::SignAndEncrypt) modeRank = 2;
    if (ep.securityMode == MessageSecurityMode::Sign) modeRank = 1;
    if (modeRank == 0) return 0;
    return 2 + modeRank * 1024 + std::min<int>(ep.securityLevel, 1023);
}

}  // namespace

asio::awaitable<StatusCode> Client::prepareSecurity() {
    auto& security = config_.security;
    const bool choose = security.choosesEndpoint();
    if (!choose) {
        const auto* profile = crypto::findSecurityPolicyProfile(security.policyUri);
        if (profile == nullptr) co_return status::BadSecurityPolicyRejected;
        if (security.mode != MessageSecurityMode::Sign &&
            security.mode != MessageSecurityMode::SignAndEncrypt) {
            co_return status::BadSecurityModeRejected;
        }
        if (!canUse(*profile, security)) co_return status::BadConfigurationError;
        useCertificateFor(*profile, security);
    }
    if (choose || config_.serverCertificate.empty()) {
        Result<std::vector<EndpointDescription>> endpoints = config_.endpoints;
        if (config_.endpoints.empty()) {
            Client discovery(executor_);
            ClientConfig discoveryConfig;
            discoveryConfig.createSession = false;
            discoveryConfig.connectTimeout = config_.connectTimeout;
            discoveryConfig.requestTimeout = config_.requestTimeout;
            discoveryConfig.limits = config_.limits;
            const std::string url = endpointUrl_;
            const StatusCode connected = co_await discovery.connect(url, discoveryConfig);
            if (connected.isBad()) co_return connected;
            endpoints = co_await discovery.getEndpoints(url);
            co_await discovery.disconnect();
            if (!endpoints) co_return endpoints.status();
        }
        const EndpointDescription* chosen = nullptr;
        int best = 0;
        for (const auto& ep : *endpoints) {
            if (choose) {
                const int strength = endpointStrength(ep, security, config_.createSession);
                if (strength > best) {
                    best = strength;
                    chosen = &ep;
                }
            } else if (ep.securityPolicyUri == security.policyUri &&
                       ep.securityMode == security.mode && !ep.serverCertificate.empty()) {
                chosen = &ep;
                break;
            }
        }
        if (chosen == nullptr) co_return status::BadSecurityPolicyRejected;
        security.policyUri = chosen->securityPolicyUri;
        security.mode = chosen->securityMode;
        if (!isSecured(config_)) co_return status::Good;  // None, and allowed
        useCertificateFor(*crypto::findSecurityPolicyProfile(security.policyUri), security);
        config_.serverCertificate = chosen->serverCertificate;
    }
    if (security.validateServerCertificate) {
        std::string reason;
        const StatusCode trusted =
            security.validateServerCertificate(config_.serverCertificate, &reason);
        if (trusted.isBad()) co_return trusted;
    }
    co_return status::Good;
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
    const ByteString clientNonce = create.clientNonce;
    if (isSecured(config_)) create.clientCertificate = config_.security.certificate;
    create.requestedSessionTimeout = config_.sessionTimeoutMs;
    create.maxResponseMessageSize = conn_->channel->limits().maxMessageSize;
    auto created = co_await request<CreateSessionRequest, CreateSessionResponse>(std::move(create));
    if (!created) co_return created.status();
    authenticationToken_ = created->authenticationToken;
    sessionId_ = created->sessionId;
    serverEndpoints_ = std::move(created->serverEndpoints);
    // With None the server's certificate is informational; the token encryption of a
    // None endpoint still uses it.
    const ByteString serverCertificate =
        isSecured(config_) ? config_.serverCertificate : created->serverCertificate;

    ActivateSessionRequest activate;
    if (isSecured(config_)) {
        // The server proves it holds its key by signing our certificate and nonce; we prove
        // ours by signing its certificate and nonce (OPC 10000-4, 5.6.2 and 5.6.3).
        const auto* profile = crypto::findSecurityPolicyProfile(config_.security.policyUri);
        // The channel decoded the server's key when it opened, from this certificate.
        const SecurityPolicy* channel = conn_->channel->policy();
        auto serverKey = channel != nullptr
                             ? publicKeyOf(serverCertificate, &channel->remoteCertificate(),
                                           channel->remoteKey())
                             : crypto::AsymmetricKey::fromCertificate(serverCertificate.bytes);
        if (!serverKey ||
            leafCertificate(created->serverCertificate.bytes) !=
                leafCertificate(serverCertificate.bytes) ||
            created->serverSignature.algorithm != profile->asymmetricSignatureUri ||
            crypto::verify(*serverKey, profile->asymmetricSignature,
                           certificateAndNonce(config_.security.certificate, clientNonce),
                           created->serverSignature.signature.bytes)
                .isBad()) {
            resetSession();
            co_return status::BadApplicationSignatureInvalid;
        }
        auto signature = crypto::sign(config_.security.privateKey, profile->asymmetricSignature,
                                      certificateAndNonce(serverCertificate, created->serverNonce));
        if (!signature) co_return signature.status();
        activate.clientSignature.algorithm = String(profile->asymmetricSignatureUri);
        activate.clientSignature.signature = ByteString(std::move(*signature));
    }
    auto token =
        makeIdentityToken(serverEndpoints_, config_, serverCertificate, created->serverNonce);
    if (!token) {
        resetSession();
        co_return token.status();
    }
    activate.userIdentityToken = std::move(token->first);
    activate.userTokenSignature = std::move(token->second);
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
                send(conn, std::move(*frames));
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
