#include "kb/http/http_client.hpp"

#include <algorithm>
#include <exception>
#include <optional>
#include <span>
#include <vector>

#include <asio.hpp>
#include <asio/experimental/as_tuple.hpp>

#include "ua/transport/no_throw.hpp"

namespace skillcell::kb::http {
namespace {

// Errors as values: refusals and resets are answers here, not exceptional.
using ua::kNoThrow;

// One request's state. It outlives the io_context that runs the exchange, so a timed-out
// coroutine destroyed with the io_context never points at freed memory.
struct Exchange {
    std::string host;
    std::uint16_t port = 0;
    std::string wire;
    bool head = false;
    ParserLimits limits;
    const char* stage = "resolving the address";
    std::optional<Expected<HttpResponse>> result;

    [[nodiscard]] std::string where() const {
        const bool ipv6 = host.find(':') != std::string::npos;
        return (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
    }
    void fail(const std::string& what) { result = Error{"http " + where() + ": " + what}; }
};

asio::awaitable<void> runExchange(Exchange& ex) {
    const auto executor = co_await asio::this_coro::executor;
    asio::ip::tcp::resolver resolver(executor);
    const std::string service = std::to_string(ex.port);
    auto resolving = resolver.async_resolve(ex.host, service,
                                            asio::ip::tcp::resolver::numeric_service, kNoThrow);
    auto [resolveError, endpoints] = co_await std::move(resolving);
    if (resolveError) {
        ex.fail("cannot resolve the host: " + resolveError.message());
        co_return;
    }

    ex.stage = "connecting";
    asio::ip::tcp::socket socket(executor);
    auto connecting = asio::async_connect(socket, endpoints, kNoThrow);
    auto [connectError, endpoint] = co_await std::move(connecting);
    if (connectError) {
        ex.fail("cannot connect: " + connectError.message());
        co_return;
    }
    asio::error_code ignored;
    socket.set_option(asio::ip::tcp::no_delay(true), ignored);

    ex.stage = "sending the request";
    auto writing = asio::async_write(socket, asio::buffer(ex.wire), kNoThrow);
    auto [writeError, written] = co_await std::move(writing);
    // A server may answer early (413) and close while we still send: read its answer anyway.

    ex.stage = "waiting for the response";
    ResponseParser parser(ex.limits);
    parser.setHeadRequest(ex.head);
    std::vector<char> buffer(kReadChunk);
    ParseState state = ParseState::NeedMore;
    while (state == ParseState::NeedMore) {
        auto reading = socket.async_read_some(asio::buffer(buffer), kNoThrow);
        auto [readError, n] = co_await std::move(reading);
        if (readError == asio::error::eof) {
            state = parser.finish();
        } else if (readError) {
            ex.fail(writeError ? "cannot send the request: " + writeError.message()
                               : "cannot receive the response: " + readError.message());
            co_return;
        } else {
            state = parser.feed(std::span<const char>(buffer.data(), n));
        }
    }
    if (state == ParseState::Error) {
        ex.fail(writeError && !parser.error().message.empty()
                    ? "cannot send the request: " + writeError.message()
                    : "malformed response: " + parser.error().message);
        co_return;
    }
    socket.close(ignored);
    ex.result = parser.take();
}

bool validMethod(std::string_view method) {
    return !method.empty() && std::all_of(method.begin(), method.end(), [](char c) {
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
               c == '-' || c == '_' || c == '.';
    });
}

bool validTarget(std::string_view target) {
    return !target.empty() && std::all_of(target.begin(), target.end(), [](char c) {
        const auto u = static_cast<unsigned char>(c);
        return u > 0x20 && u < 0x7f;
    });
}

}  // namespace

Expected<HttpResponse> httpRequest(const std::string& host, std::uint16_t port, HttpRequest request,
                                   std::chrono::milliseconds timeout, const ParserLimits& limits) {
    Exchange ex;
    ex.host = host;
    ex.port = port;
    ex.limits = limits;
    if (request.target.empty()) request.target = makeTarget(request.path, request.query);
    if (!validMethod(request.method)) return Error{"http " + ex.where() + ": invalid method"};
    if (!validTarget(request.target)) {
        return Error{"http " + ex.where() + ": invalid request target"};
    }
    if (!request.headers.contains("Host")) request.headers.add("Host", ex.where());
    request.headers.set("Connection", "close");
    ex.wire = serialize(request);
    ex.head = request.method == "HEAD";

    try {
        asio::io_context io(1);
        auto onDone = [&ex](const std::exception_ptr& e) {
            if (e && !ex.result) ex.fail(std::string("internal error ") + ex.stage);
        };
        asio::co_spawn(io, runExchange(ex), onDone);
        io.run_for(timeout);
        // Leaving the scope destroys a still-pending exchange together with its socket.
    } catch (const std::exception& e) {
        return Error{"http " + ex.where() + ": " + e.what()};
    }
    if (!ex.result) {
        return Error{"http " + ex.where() + ": timed out after " + std::to_string(timeout.count()) +
                     " ms " + ex.stage};
    }
    return std::move(*ex.result);
}

}  // namespace skillcell::kb::http
