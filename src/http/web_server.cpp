#include "http/web_server.hpp"

#include <arpa/inet.h>
#include <spdlog/spdlog.h>
#include <unistd.h>
#include <algorithm>

#include <array>

#include "http/broken_pipe.hpp"
#include "http/http_url.hpp"
#include "ua/pki/certificate.hpp"

namespace skillcell::http {
namespace {

// Client certificates are asked for but not judged here: the user database knows users by
// their certificate's thumbprint (UserGate), and a certificate it does not list identifies
// nobody. The handshake has proven that the client holds the key.
int acceptAnyClientCertificate(int /*preverified*/, X509_STORE_CTX* /*store*/) {
    return 1;
}

ua::ByteString peerCertificate(const httplib::Request& request) {
    if (request.ssl == nullptr) return {};
    X509* cert = SSL_get1_peer_certificate(request.ssl);
    if (cert == nullptr) return {};
    ua::ByteString der = ua::pki::certificateDer(cert);
    X509_free(cert);
    return der;
}

}  // namespace

bool isLoopback(const std::string& host) {
    if (host == "localhost" || host == "::1") return true;
    in_addr a{};
    return inet_pton(AF_INET, host.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 24U) == 127U;
}

WebServer::WebServer(WebServerConfig config) : config_(std::move(config)) {
    ignoreBrokenPipes();
}

WebServer::~WebServer() {
    stop();
}

std::optional<ua::UserIdentity> WebServer::identify(const httplib::Request& req,
                                                    httplib::Response& res) const {
    std::chrono::seconds retryAfter{0};
    auto user = config_.gate->identify(req.get_header_value("Authorization"), peerCertificate(req),
                                       req.get_header_value("Cookie"), &retryAfter);
    if (user) return *user;
    if (user.status() == ua::status::BadTooManyOperations) {
        spdlog::warn("http: {} {} from {}: too many wrong passwords for its user, 429", req.method,
                     req.path, req.remote_addr);
        res.status = 429;
        res.set_header("Retry-After", std::to_string(retryAfter.count()));
        res.set_content("too many wrong passwords for this user: try again later\n", "text/plain");
        return std::nullopt;
    }
    spdlog::info("http: {} {} from {}: no known user, 401", req.method, req.path, req.remote_addr);
    res.status = 401;
    res.set_header("WWW-Authenticate", config_.challenge);
    res.set_content("who are you? give a user of the cell\n", "text/plain");
    return std::nullopt;
}

httplib::Server::Handler WebServer::guarded(Handler handler) {
    return
        [this, handler = std::move(handler)](const httplib::Request& req, httplib::Response& res) {
            if (auto user = identify(req, res)) handler(req, res, *user);
        };
}

// cpp-httplib refuses form bodies above 8 KiB when it reads them itself (a SPARQL update is
// often larger): requests with a body are read here, after the user is known, up to
// maxBodyBytes, and a form body's fields are decoded into params as cpp-httplib would.
httplib::Server::HandlerWithContentReader WebServer::guardedWithBody(Handler handler) {
    return [this, handler = std::move(handler)](const httplib::Request& req, httplib::Response& res,
                                                const httplib::ContentReader& content) {
        auto user = identify(req, res);
        if (!user) return;
        httplib::Request full = req;
        bool tooLarge = false;
        content([&](const char* data, std::size_t size) {
            if (full.body.size() + size > config_.maxBodyBytes) {
                tooLarge = true;
                return false;
            }
            full.body.append(data, size);
            return true;
        });
        if (tooLarge) {
            res.status = 413;
            res.set_content("the body exceeds " + std::to_string(config_.maxBodyBytes) + " bytes\n",
                            "text/plain");
            return;
        }
        if (req.get_header_value("Content-Type").rfind("application/x-www-form-urlencoded", 0) ==
            0) {
            const char* b = full.body.data();
            httplib::detail::split(b, b + full.body.size(), '&', [&](const char* f, const char* e) {
                const std::string field(f, e);
                const auto eq = field.find('=');
                full.params.emplace(httplib::detail::decode_url(field.substr(0, eq), true),
                                    eq == std::string::npos
                                        ? std::string()
                                        : httplib::detail::decode_url(field.substr(eq + 1), true));
            });
        }
        handler(full, res, *user);
    };
}

void WebServer::get(const std::string& pattern, Handler handler) {
    pending_.push_back({"GET", pattern, std::move(handler), {}});
}
void WebServer::post(const std::string& pattern, Handler handler) {
    pending_.push_back({"POST", pattern, std::move(handler), {}});
}
void WebServer::put(const std::string& pattern, Handler handler) {
    pending_.push_back({"PUT", pattern, std::move(handler), {}});
}
void WebServer::publicGet(const std::string& pattern, httplib::Server::Handler handler) {
    pending_.push_back({"GET", pattern, {}, std::move(handler)});
}
void WebServer::publicPost(const std::string& pattern, httplib::Server::Handler handler) {
    pending_.push_back({"POST", pattern, {}, std::move(handler)});
}

Status WebServer::start() {
    if (server_) return Error{"the web server is started already"};
    if (!config_.gate) return Error{"a web server needs a UserGate"};
    const std::string where = config_.host + ":" + std::to_string(config_.port);
    if (config_.tls) {
        auto cert = ua::pki::parseCertificate(config_.tls->certificate);
        if (!cert || !config_.tls->privateKey.valid()) {
            return Error{"HTTPS on " + where + ": no usable certificate and key"};
        }
        auto tls = std::make_unique<httplib::SSLServer>(cert->get(), config_.tls->privateKey.get());
        if (!tls->is_valid()) {
            return Error{"HTTPS on " + where + ": OpenSSL refuses the certificate or its key"};
        }
        SSL_CTX_set_min_proto_version(tls->ssl_context(), TLS1_2_VERSION);
        if (config_.tls->requestClientCertificates) {
            SSL_CTX_set_verify(tls->ssl_context(), SSL_VERIFY_PEER, &acceptAnyClientCertificate);
        }
        server_ = std::move(tls);
    } else {
        if (!isLoopback(config_.host)) {
            return Error{"plain HTTP on " + where +
                         ": only on a loopback address (127.0.0.1); anywhere else the server "
                         "speaks HTTPS"};
        }
        server_ = std::make_unique<httplib::Server>();
    }
    auto& s = *server_;
    // The duration itself: cast to seconds first, a timeout under a second became none.
    s.set_read_timeout(config_.readTimeout);
    s.set_write_timeout(config_.writeTimeout);
    s.set_payload_max_length(config_.maxBodyBytes);
    // cpp-httplib owns the queue it is given (its API takes a raw pointer).
    s.new_task_queue = [threads = std::max<std::size_t>(config_.threads, 1)] {
        return new httplib::ThreadPool(threads);  // NOLINT(cppcoreguidelines-owning-memory)
    };
    s.set_tcp_nodelay(true);  // answers go out as headers, then body (see http_client.cpp)
    s.set_exception_handler(
        [](const httplib::Request& req, httplib::Response& res, const std::exception_ptr& e) {
            std::string what = "unknown exception";
            try {
                std::rethrow_exception(e);
            } catch (const std::exception& x) {
                what = x.what();
            } catch (...) {  // NOLINT(bugprone-empty-catch): described as unknown
            }
            spdlog::error("http: {} {}: {}", req.method, req.path, what);
            res.status = 500;
            res.set_content("internal error: " + what + "\n", "text/plain");
        });
    for (auto& r : pending_) {
        if (r.publicHandler && r.method == "GET") {
            s.Get(r.pattern, std::move(r.publicHandler));
        } else if (r.publicHandler) {
            s.Post(r.pattern, std::move(r.publicHandler));
        } else if (r.method == "GET") {
            s.Get(r.pattern, guarded(std::move(r.handler)));
        } else if (r.method == "POST") {
            s.Post(r.pattern, guardedWithBody(std::move(r.handler)));
        } else {
            s.Put(r.pattern, guardedWithBody(std::move(r.handler)));
        }
    }
    pending_.clear();
    int bound = 0;
    if (config_.port == 0) {
        bound = s.bind_to_any_port(config_.host);
    } else {
        bound = s.bind_to_port(config_.host, config_.port) ? config_.port : -1;
    }
    if (bound <= 0) {
        server_.reset();
        return Error{"cannot listen on " + where + " (in use, or not an address of this host)",
                     ErrorKind::Unavailable};
    }
    port_ = static_cast<std::uint16_t>(bound);
    thread_ = std::thread([&s] { s.listen_after_bind(); });
    // stop() before the loop runs would be lost (cpp-httplib only stops a running loop):
    // start() returns once it runs, which takes microseconds.
    for (int i = 0; i < 1'000'000 && !s.is_running(); ++i) std::this_thread::yield();
    return Done{};
}

std::string WebServer::url(const std::string& path) const {
    std::string host = config_.host;
    if (tls() && isLoopback(host)) host = "localhost";
    if (host == "0.0.0.0") {
        std::array<char, 256> name{};
        host = gethostname(name.data(), name.size() - 1) == 0 ? name.data() : "localhost";
    }
    return HttpUrl{tls(), host, port_, path}.toString();
}

void WebServer::stop() {
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
}

}  // namespace skillcell::http
