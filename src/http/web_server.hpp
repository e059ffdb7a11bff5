#pragma once
// WebServer: an HTTPS server on cpp-httplib for a component (the knowledge base's SPARQL
// endpoint). TLS with the component's own certificate, issued by the cell CA, so that a
// client that trusts the cell trusts the server; every route behind a UserGate, so that a
// handler learns who asks and decides with the user's roles. Plain HTTP exists only for
// --insecure development, and only on a loopback address.
//
// Threading: cpp-httplib runs handlers on its own pool of threads; a handler may block (the
// store answers a query). start() returns once the server listens; stop() and the
// destructor wait for the listening thread.
#include <httplib.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/expected.hpp"
#include "http/user_gate.hpp"
#include "ua/crypto/primitives.hpp"

namespace skillcell::http {

struct ServerTls {
    ua::ByteString certificate;  // DER
    ua::crypto::AsymmetricKey privateKey;
    /// Ask clients for a certificate, to know users by it (UserGate); a client without one
    /// is served all the same and proves its user otherwise.
    bool requestClientCertificates = false;
};

struct WebServerConfig {
    std::string host = "127.0.0.1";
    std::uint16_t port = 0;  // 0: any free port
    /// Empty: plain HTTP, which start() refuses on any address but loopback.
    std::optional<ServerTls> tls;
    /// Who asks; required.
    std::shared_ptr<UserGate> gate;
    /// The WWW-Authenticate of a 401. Basic for API clients (curl, the MES); a page whose
    /// users log in by a form gives a scheme browsers do not answer with a password dialog.
    std::string challenge = R"(Basic realm="skillcell", charset="UTF-8")";
    std::chrono::milliseconds readTimeout{10'000};
    std::chrono::milliseconds writeTimeout{30'000};
    std::size_t maxBodyBytes = std::size_t{64} << 20U;
    /// Requests served at once, each on a thread of the server's pool; a long-lived response
    /// (a page's event stream) holds its thread while it lasts.
    std::size_t threads = 8;
};

class WebServer {
public:
    /// Answers a request of an identified user.
    using Handler =
        std::function<void(const httplib::Request&, httplib::Response&, const ua::UserIdentity&)>;

    explicit WebServer(WebServerConfig config);
    ~WebServer();
    WebServer(const WebServer&) = delete;
    WebServer& operator=(const WebServer&) = delete;

    /// Routes, before start(). `pattern` is a path (or a cpp-httplib regex).
    void get(const std::string& pattern, Handler handler);
    void post(const std::string& pattern, Handler handler);
    void put(const std::string& pattern, Handler handler);
    /// Routes that anyone may use, for what a browser needs before its user logs in (the
    /// page, its script, the login itself). A body is read up to maxBodyBytes.
    void publicGet(const std::string& pattern, httplib::Server::Handler handler);
    void publicPost(const std::string& pattern, httplib::Server::Handler handler);

    /// Binds, listens and serves on a thread of its own; an Error says why not (an address
    /// in use, plain HTTP off loopback, a certificate OpenSSL refuses).
    [[nodiscard]] Status start();
    /// Idempotent.
    void stop();
    /// The bound port; 0 before start().
    [[nodiscard]] std::uint16_t port() const { return port_; }
    [[nodiscard]] bool tls() const { return config_.tls.has_value(); }
    /// The URL of `path` as clients should use it, once started: with TLS a host name the
    /// certificate carries ("localhost" for a loopback address); this host's name for one
    /// that listens on every address.
    [[nodiscard]] std::string url(const std::string& path) const;
    [[nodiscard]] UserGate& gate() { return *config_.gate; }

private:
    /// The request's user, or nothing after answering 401.
    std::optional<ua::UserIdentity> identify(const httplib::Request& req,
                                             httplib::Response& res) const;
    httplib::Server::Handler guarded(Handler handler);
    httplib::Server::HandlerWithContentReader guardedWithBody(Handler handler);

    struct Route {
        std::string method;
        std::string pattern;
        Handler handler;
        httplib::Server::Handler publicHandler;  // set: no user needed
    };
    WebServerConfig config_;
    std::vector<Route> pending_;  // until start()
    std::unique_ptr<httplib::Server> server_;
    std::thread thread_;
    std::uint16_t port_ = 0;
};

/// Whether `host` is a loopback address (127.0.0.0/8, ::1) or "localhost".
[[nodiscard]] bool isLoopback(const std::string& host);

}  // namespace skillcell::http
