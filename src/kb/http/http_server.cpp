#include "kb/http/http_server.hpp"

#include <algorithm>
#include <array>
#include <exception>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <asio/experimental/as_tuple.hpp>

#include "ua/transport/no_throw.hpp"

namespace skillcell::kb::http {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// Errors as values: a peer going away is normal control flow here, not an exception.
using ua::kNoThrow;

// After an error answer the peer may still be sending (a body we refused); reading it away
// for a moment keeps the kernel from resetting the connection before the answer is read.
constexpr milliseconds kMaxLinger{2000};
constexpr std::size_t kMaxLingerBytes = std::size_t{1024} * 1024;

std::string describe(const asio::ip::tcp::endpoint& endpoint) {
    const auto address = endpoint.address();
    const std::string host =
        address.is_v6() ? "[" + address.to_string() + "]" : address.to_string();
    return host + ":" + std::to_string(endpoint.port());
}

// One accepted socket and its deadline. The watchdog cancels the socket's operations when
// the deadline passes; the connection coroutine then sees timedOut and decides what to say.
struct Connection {
    explicit Connection(asio::ip::tcp::socket s)
        : socket(std::move(s)), timer(socket.get_executor()) {}

    void setDeadline(Clock::time_point t) {
        const bool earlier = t < deadline;
        deadline = t;
        timedOut = false;
        if (earlier) timer.cancel();  // the watchdog re-arms; a later one it finds on waking
    }
    void setTimeout(milliseconds timeout) { setDeadline(Clock::now() + timeout); }
    void close() {
        closed = true;
        asio::error_code ignored;
        socket.close(ignored);
        timer.cancel();
    }

    asio::ip::tcp::socket socket;
    asio::steady_timer timer;
    Clock::time_point deadline = Clock::time_point::max();
    bool timedOut = false;
    bool closed = false;
};

}  // namespace

namespace detail {

struct HttpServerState {
    HttpServerState(asio::io_context& io, asio::ip::tcp::endpoint ep, HttpServer::Handler h,
                    const HttpServerLimits& l)
        : acceptor(io), retryTimer(io), endpoint(std::move(ep)), handler(std::move(h)), limits(l) {}

    asio::ip::tcp::acceptor acceptor;
    asio::steady_timer retryTimer;
    asio::ip::tcp::endpoint endpoint;
    HttpServer::Handler handler;
    HttpServerLimits limits;
    std::unordered_map<std::uint64_t, std::weak_ptr<Connection>> connections;
    std::uint64_t nextId = 1;
    std::uint16_t port = 0;
    bool started = false;
    bool stopped = false;
};

}  // namespace detail

namespace {

using detail::HttpServerState;

asio::awaitable<HttpResponse> callSync(std::shared_ptr<const HttpServer::SyncHandler> handler,
                                       HttpRequest request) {
    co_return (*handler)(request);
}

HttpServer::Handler wrapSync(HttpServer::SyncHandler handler) {
    // Shared, not captured by the coroutine: the frame must not point into a lambda object.
    auto shared = std::make_shared<const HttpServer::SyncHandler>(std::move(handler));
    return [shared](HttpRequest request) { return callSync(shared, std::move(request)); };
}

asio::awaitable<HttpResponse> callHandler(const HttpServer::Handler& handler, HttpRequest request) {
    bool failed = !handler;
    HttpResponse response;
    if (!failed) {
        try {
            auto answering = handler(std::move(request));
            response = co_await std::move(answering);
        } catch (...) {
            failed = true;  // the handler's failure stays on this side of the network
        }
    }
    if (failed) response = makeResponse(500, "internal server error\n");
    co_return response;
}

asio::awaitable<bool> writeAll(Connection& conn, const std::string& bytes, milliseconds timeout) {
    conn.setTimeout(timeout);
    auto writing = asio::async_write(conn.socket, asio::buffer(bytes), kNoThrow);
    auto [ec, n] = co_await std::move(writing);
    co_return !ec;
}

// Sends a final error answer, then half-closes and drains what the peer still sends.
// (`message` by value: the coroutine starts only when awaited, after a temporary is gone.)
asio::awaitable<void> answerAndClose(Connection& conn, const HttpServerLimits& limits, int status,
                                     std::string message) {
    HttpResponse response = makeResponse(status, message + "\n");
    response.headers.set("Connection", "close");
    const std::string wire = serialize(response);
    auto writing = writeAll(conn, wire, limits.writeTimeout);
    if (!co_await std::move(writing)) co_return;
    asio::error_code ignored;
    conn.socket.shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
    conn.setTimeout(std::min(kMaxLinger, limits.readTimeout));
    std::array<char, 4096> sink{};
    std::size_t drained = 0;
    while (drained < kMaxLingerBytes && !conn.timedOut) {
        auto reading = conn.socket.async_read_some(asio::buffer(sink), kNoThrow);
        auto [ec, n] = co_await std::move(reading);
        if (ec) break;
        drained += n;
    }
}

// The request loop of one connection: read a request, answer it, repeat while kept alive.
asio::awaitable<void> serveRequests(HttpServerState& state, Connection& conn) {
    const HttpServerLimits& limits = state.limits;
    RequestParser parser(limits.parser);
    std::vector<char> buffer(kReadChunk);
    const std::string continueLine = "HTTP/1.1 100 Continue\r\n\r\n";
    while (!state.stopped) {
        ParseState parsed = parser.feed(std::span<const char>());  // pipelined leftovers
        bool started = parser.started();
        bool continued = false;
        conn.setTimeout(started ? limits.readTimeout : limits.idleTimeout);
        while (parsed == ParseState::NeedMore) {
            if (parser.expectsContinue() && !continued) {
                continued = true;
                auto writing = writeAll(conn, continueLine, limits.writeTimeout);
                if (!co_await std::move(writing)) co_return;
                conn.setTimeout(limits.readTimeout);
            }
            asio::error_code ec;
            std::size_t n = 0;
            if (conn.timedOut) {
                ec = asio::error::timed_out;  // fired between two reads
            } else {
                auto reading = conn.socket.async_read_some(asio::buffer(buffer), kNoThrow);
                std::tie(ec, n) = co_await std::move(reading);
            }
            if (ec) {
                if (conn.timedOut && parser.started() && !state.stopped) {
                    auto answering = answerAndClose(conn, limits, 408, "request timed out");
                    co_await std::move(answering);
                }
                co_return;  // closed by the peer, idle too long, or stopped
            }
            parsed = parser.feed(std::span<const char>(buffer.data(), n));
            if (!started && parser.started()) {
                started = true;
                conn.setTimeout(limits.readTimeout);  // the request's own clock starts now
            }
        }
        if (parsed == ParseState::Error) {
            auto answering =
                answerAndClose(conn, limits, parser.error().status, parser.error().message);
            co_await std::move(answering);
            co_return;
        }

        HttpRequest request = parser.take();
        const bool head = request.method == "HEAD";
        const int versionMinor = request.versionMinor;
        bool keepAlive = request.keepAlive();
        conn.setDeadline(Clock::time_point::max());  // the handler takes what it takes
        auto calling = callHandler(state.handler, std::move(request));
        HttpResponse response = co_await std::move(calling);
        if (state.stopped || conn.closed) co_return;

        keepAlive = keepAlive && response.keepAlive();
        response.versionMinor = 1;
        if (!keepAlive) {
            response.headers.set("Connection", "close");
        } else if (versionMinor == 0) {
            response.headers.set("Connection", "keep-alive");  // 1.0 closes by default
        }
        const std::string wire = serialize(response, head);
        auto writing = writeAll(conn, wire, limits.writeTimeout);
        if (!co_await std::move(writing) || !keepAlive) co_return;
    }
}

asio::awaitable<void> runConnection(std::shared_ptr<HttpServerState> state,
                                    std::shared_ptr<Connection> conn, std::uint64_t id) {
    asio::error_code ignored;
    conn->socket.set_option(asio::ip::tcp::no_delay(true), ignored);  // request/response
    try {
        auto serving = serveRequests(*state, *conn);
        co_await std::move(serving);
    } catch (...) {
        // Only allocation failures get here; the connection is dropped, the server lives on.
    }
    conn->socket.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    conn->close();
    state->connections.erase(id);
}

// Cancels the connection's pending operations whenever its deadline passes.
asio::awaitable<void> watchdog(std::shared_ptr<Connection> conn) {
    while (!conn->closed) {
        conn->timer.expires_at(conn->deadline);
        auto waiting = conn->timer.async_wait(kNoThrow);
        co_await std::move(waiting);
        if (conn->closed) break;
        if (conn->deadline <= Clock::now()) {
            conn->timedOut = true;
            conn->deadline = Clock::time_point::max();
            asio::error_code ignored;
            conn->socket.cancel(ignored);
        }
    }
}

// Over the connection limit: say so without waiting on the peer, then close.
void refuse(asio::ip::tcp::socket& socket) {
    HttpResponse response = makeResponse(503, "too many connections\n");
    response.headers.set("Connection", "close");
    const std::string wire = serialize(response);
    asio::error_code ignored;
    socket.non_blocking(true, ignored);
    socket.write_some(asio::buffer(wire), ignored);
    socket.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    socket.close(ignored);
}

asio::awaitable<void> acceptLoop(std::shared_ptr<HttpServerState> state) {
    const auto executor = co_await asio::this_coro::executor;
    while (!state->stopped) {
        auto accepting = state->acceptor.async_accept(kNoThrow);
        auto [ec, socket] = co_await std::move(accepting);
        if (state->stopped || ec == asio::error::operation_aborted) co_return;
        if (ec) {
            // Out of descriptors and the like: pause instead of spinning on the error.
            state->retryTimer.expires_after(milliseconds(100));
            auto waiting = state->retryTimer.async_wait(kNoThrow);
            co_await std::move(waiting);
            continue;
        }
        if (state->connections.size() >= state->limits.maxConnections) {
            refuse(socket);
            continue;
        }
        auto conn = std::make_shared<Connection>(std::move(socket));
        const std::uint64_t id = state->nextId++;
        state->connections.emplace(id, conn);
        asio::co_spawn(executor, runConnection(state, conn, id), asio::detached);
        asio::co_spawn(executor, watchdog(conn), asio::detached);
    }
}

}  // namespace

HttpServer::HttpServer(asio::io_context& io, asio::ip::tcp::endpoint endpoint, Handler handler,
                       HttpServerLimits limits)
    : state_(
          std::make_shared<HttpServerState>(io, std::move(endpoint), std::move(handler), limits)) {}

HttpServer::HttpServer(asio::io_context& io, asio::ip::tcp::endpoint endpoint, SyncHandler handler,
                       HttpServerLimits limits)
    : HttpServer(io, std::move(endpoint), wrapSync(std::move(handler)), limits) {}

HttpServer::~HttpServer() {
    stop();
}

Status HttpServer::start() {
    HttpServerState& s = *state_;
    if (s.started) return Error{"http server: already started"};
    asio::error_code ec;
    s.acceptor.open(s.endpoint.protocol(), ec);
    if (!ec) s.acceptor.set_option(asio::ip::tcp::acceptor::reuse_address(true), ec);
    if (!ec) s.acceptor.bind(s.endpoint, ec);
    if (!ec) s.acceptor.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) {
        asio::error_code ignored;
        s.acceptor.close(ignored);
        return Error{"http server: cannot listen on " + describe(s.endpoint) + ": " + ec.message()};
    }
    s.port = s.acceptor.local_endpoint(ec).port();
    s.started = true;
    asio::co_spawn(s.acceptor.get_executor(), acceptLoop(state_), asio::detached);
    return Done{};
}

void HttpServer::stop() {
    HttpServerState& s = *state_;
    if (s.stopped) return;
    s.stopped = true;
    asio::error_code ignored;
    s.acceptor.close(ignored);
    s.retryTimer.cancel();
    for (auto& [id, weak] : s.connections) {
        if (auto conn = weak.lock()) conn->close();
    }
}

std::uint16_t HttpServer::port() const {
    return state_->port;
}

std::size_t HttpServer::connectionCount() const {
    return state_->connections.size();
}

}  // namespace skillcell::kb::http
