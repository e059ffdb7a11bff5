#pragma once
// HttpClient: blocking HTTP/1.1 and HTTPS requests to one server, on cpp-httplib, for
// application threads (the knowledge base's store, the MES reading processes, commands).
//
// Every request is bounded by ClientOptions::timeout. Over https the server's certificate
// is judged by ClientOptions::verifyServer, the same judgement as for an OPC UA server (the
// component's trust list, which holds the cell CA), and its name must match the URL's host;
// there is no way to switch that off. Requests may come from several threads: they take
// turns on one kept-alive connection.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "common/expected.hpp"
#include "http/http_url.hpp"
#include "ua/crypto/primitives.hpp"
#include "ua/types/builtin.hpp"

namespace skillcell::http {

/// Name/value pairs of a query string or a form (order does not matter to HTTP forms).
using Params = std::multimap<std::string, std::string>;

struct ClientAuth {
    enum class Kind : std::uint8_t { None, Basic, Digest };
    Kind kind = Kind::None;
    std::string user;
    std::string password;
};

/// Whether to trust a server's certificate (DER); `reason` says why not.
using ServerVerifier = std::function<bool(const ua::ByteString& der, std::string* reason)>;

struct ClientOptions {
    std::chrono::milliseconds timeout{30'000};
    /// https only; required there (a client that trusts every server is not offered).
    ServerVerifier verifyServer;
    ClientAuth auth;
    /// https only: a client certificate (DER) and its key, for servers that know users by
    /// their certificate. Empty: none.
    ua::ByteString certificate;
    ua::crypto::AsymmetricKey privateKey;
};

struct HttpReply {
    int status = 0;
    std::string contentType;
    std::string body;
};

class HttpClient {
public:
    /// No I/O here; the first request connects.
    HttpClient(HttpUrl server, ClientOptions options);
    ~HttpClient();
    HttpClient(const HttpClient&) = delete;
    HttpClient& operator=(const HttpClient&) = delete;

    /// Any status is a reply; an Error (kind Unavailable) means there was none: refused,
    /// timed out, a TLS failure (with the reason the certificate was not trusted).
    [[nodiscard]] Expected<HttpReply> get(const std::string& path, const Params& query,
                                          const std::string& accept);
    /// A form-encoded (application/x-www-form-urlencoded) POST.
    [[nodiscard]] Expected<HttpReply> postForm(const std::string& path, const Params& form,
                                               const std::string& accept);
    [[nodiscard]] Expected<HttpReply> put(const std::string& path, const Params& query,
                                          const std::string& body, const std::string& contentType);
    [[nodiscard]] Expected<HttpReply> post(const std::string& path, const Params& query,
                                           const std::string& body, const std::string& contentType);

    [[nodiscard]] const HttpUrl& server() const { return server_; }

    struct Impl;  // cpp-httplib's client and the TLS state (http_client.cpp)

private:
    HttpUrl server_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace skillcell::http
