#pragma once
// A blocking HTTP/1.1 client for application threads (the knowledge base talking to a local
// SPARQL endpoint). Each call runs its own io_context, so it neither needs nor disturbs the
// caller's event loop; one connection per request ("Connection: close").
#include <chrono>
#include <cstdint>
#include <string>

#include "kb/expected.hpp"
#include "kb/http/http_message.hpp"

namespace skillcell::kb::http {

/// Sends `request` to host:port and returns the response, whatever its status. Connecting,
/// sending and receiving together take at most `timeout`; a timeout, a refused connection or
/// a malformed response is an Error naming host:port. The target is built from
/// request.path and request.query when request.target is empty; Host is added if missing.
/// `host` should be a numeric address: name resolution is not bounded by the timeout.
[[nodiscard]] Expected<HttpResponse> httpRequest(const std::string& host, std::uint16_t port,
                                                 HttpRequest request,
                                                 std::chrono::milliseconds timeout,
                                                 const ParserLimits& limits = {});

}  // namespace skillcell::kb::http
