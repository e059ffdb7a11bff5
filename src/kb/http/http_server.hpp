#pragma once
// HttpServer: HTTP/1.1 over Asio for the knowledge base's SPARQL 1.1 Protocol endpoint. An
// accept loop and one coroutine per connection (plus a watchdog for its deadlines); parsing,
// framing and size limits are RequestParser's, so this file only moves bytes and keeps time.
//
// Threading: like ua::Server, everything runs on the io_context's thread. Call start(),
// stop() and the destructor on that thread, or while the io_context is not running.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

// After a standard header on purpose: Asio 1.22 decides between aligned_alloc and operator
// new for its coroutine frames from a libstdc++ macro, so a translation unit that includes
// <asio.hpp> first allocates differently from one that does not (an ODR violation that
// AddressSanitizer reports as alloc-dealloc-mismatch).
#include <asio.hpp>

#include "kb/expected.hpp"
#include "kb/http/http_message.hpp"

namespace skillcell::kb::http {

namespace detail {
struct HttpServerState;
}

struct HttpServerLimits {
    /// Connections beyond this are answered 503 and closed.
    std::size_t maxConnections = 64;
    /// A request must be complete this long after its first byte arrived (else 408).
    std::chrono::milliseconds readTimeout{10'000};
    /// A connection without a request in progress is closed after this (silently).
    std::chrono::milliseconds idleTimeout{30'000};
    /// Bound on sending one response to a peer that does not read.
    std::chrono::milliseconds writeTimeout{30'000};
    /// Header and body limits (413, 414, 431).
    ParserLimits parser;
};

class HttpServer {
public:
    /// Answers one request; it may suspend (on a worker, a timer) without blocking the I/O
    /// thread. An exception from it becomes a 500 answer.
    using Handler = std::function<asio::awaitable<HttpResponse>(HttpRequest)>;
    /// A handler that answers at once, on the I/O thread.
    using SyncHandler = std::function<HttpResponse(const HttpRequest&)>;

    /// Nothing is opened until start(). Port 0 in `endpoint` asks for an ephemeral port.
    HttpServer(asio::io_context& io, asio::ip::tcp::endpoint endpoint, Handler handler,
               HttpServerLimits limits = {});
    HttpServer(asio::io_context& io, asio::ip::tcp::endpoint endpoint, SyncHandler handler,
               HttpServerLimits limits = {});
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;
    /// Stops; coroutines still suspended finish on their own without touching this object.
    ~HttpServer();

    /// Binds, listens and starts accepting; an Error names the address that failed.
    [[nodiscard]] Status start();
    /// Closes the acceptor and every connection; a handler still running finishes and its
    /// answer is dropped. Idempotent.
    void stop();
    /// The bound port (the ephemeral one for port 0); 0 before start().
    [[nodiscard]] std::uint16_t port() const;
    /// Connections currently open.
    [[nodiscard]] std::size_t connectionCount() const;

private:
    // Shared with the coroutines, so that they may outlive the server object.
    std::shared_ptr<detail::HttpServerState> state_;
};

}  // namespace skillcell::kb::http
