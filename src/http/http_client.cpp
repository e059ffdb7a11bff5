#include "http/http_client.hpp"

#include <httplib.h>

#include "http/broken_pipe.hpp"

#include <mutex>

#include "ua/pki/certificate.hpp"

namespace skillcell::http {

struct HttpClient::Impl {
    std::mutex mutex;  // one request at a time on the kept-alive connection
    ClientOptions options;
    std::unique_ptr<httplib::ClientImpl> client;
    ua::pki::ossl::Cert clientCertificate;
    std::string rejection;  // why verifyServer refused the last server certificate

    // OpenSSL asks this instead of its own chain building: the server's certificate is
    // trusted when the component's trust list trusts it, as for an OPC UA server.
    static int verify(X509_STORE_CTX* store, void* arg) {
        auto* self = static_cast<Impl*>(arg);
        X509* cert = X509_STORE_CTX_get0_cert(store);
        std::string reason = "the server sent no certificate";
        if (cert != nullptr && self->options.verifyServer) {
            if (self->options.verifyServer(ua::pki::certificateDer(cert), &reason)) return 1;
        }
        self->rejection = reason.empty() ? "its certificate is not trusted" : reason;
        X509_STORE_CTX_set_error(store, X509_V_ERR_CERT_REJECTED);
        return 0;
    }
};

namespace {

std::string describe(httplib::Error e) {
    switch (e) {
        case httplib::Error::Connection:
            return "cannot connect";
        case httplib::Error::ConnectionTimeout:
            return "no connection within the timeout";
        case httplib::Error::Read:
            return "no (complete) answer within the timeout";
        case httplib::Error::Write:
            return "cannot send the request";
        case httplib::Error::SSLConnection:
            return "TLS handshake failed";
        default:
            return httplib::to_string(e);
    }
}

template <class Rep, class Period>
void setTimeouts(httplib::ClientImpl& c, std::chrono::duration<Rep, Period> t) {
    const auto us = std::chrono::duration_cast<std::chrono::microseconds>(t).count();
    const auto sec = static_cast<time_t>(us / 1'000'000);
    const auto usec = static_cast<time_t>(us % 1'000'000);
    c.set_connection_timeout(sec, usec);
    c.set_read_timeout(sec, usec);
    c.set_write_timeout(sec, usec);
}

}  // namespace

HttpClient::HttpClient(HttpUrl server, ClientOptions options)
    : server_(std::move(server)), impl_(std::make_unique<Impl>()) {
    ignoreBrokenPipes();
    impl_->options = std::move(options);
    if (server_.tls) {
        std::unique_ptr<httplib::SSLClient> tls;
        auto cert = impl_->options.certificate.empty()
                        ? ua::Result<ua::pki::ossl::Cert>(ua::status::BadCertificateInvalid)
                        : ua::pki::parseCertificate(impl_->options.certificate);
        if (cert && impl_->options.privateKey.valid()) {
            impl_->clientCertificate = std::move(*cert);
            tls = std::make_unique<httplib::SSLClient>(server_.host, server_.port,
                                                       impl_->clientCertificate.get(),
                                                       impl_->options.privateKey.get());
        } else {
            tls = std::make_unique<httplib::SSLClient>(server_.host, server_.port);
        }
        SSL_CTX_set_cert_verify_callback(tls->ssl_context(), &Impl::verify, impl_.get());
        tls->enable_server_certificate_verification(true);  // and the host name check
        impl_->client = std::move(tls);
    } else {
        impl_->client = std::make_unique<httplib::ClientImpl>(server_.host, server_.port);
    }
    auto& c = *impl_->client;
    setTimeouts(c, impl_->options.timeout);
    c.set_keep_alive(true);
    // A request goes out as headers, then body: with Nagle's algorithm the body waits for
    // the server's delayed ACK, 40 ms a request on Linux.
    c.set_tcp_nodelay(true);
    const auto& auth = impl_->options.auth;
    if (auth.kind == ClientAuth::Kind::Basic) c.set_basic_auth(auth.user, auth.password);
    if (auth.kind == ClientAuth::Kind::Digest) c.set_digest_auth(auth.user, auth.password);
}

HttpClient::~HttpClient() = default;

namespace {

Expected<HttpReply> exchange(HttpClient::Impl& impl, const HttpUrl& server,
                             const httplib::Request& request) {
    const std::lock_guard lock(impl.mutex);
    impl.rejection.clear();
    auto result = impl.client->send(request);
    if (!result && result.error() == httplib::Error::Write) {
        // The kept-alive connection was closed by the server as it idled (cpp-httplib's
        // servers close after 5 s), just as the request went out: nothing reached the server,
        // so it is sent once more on a new connection, an update included.
        impl.client->stop();
        result = impl.client->send(request);
    }
    if (!result) {
        std::string why = describe(result.error());
        if (result.error() == httplib::Error::SSLServerVerification) {
            why = "the server's certificate is refused: " +
                  (impl.rejection.empty() ? "it does not name the host " + server.host
                                          : impl.rejection);
        }
        return Error{server.toString() + ": " + why, ErrorKind::Unavailable};
    }
    HttpReply reply;
    reply.status = result->status;
    reply.contentType = result->get_header_value("Content-Type");
    reply.body = std::move(result->body);
    return reply;
}

httplib::Request request(const char* method, const std::string& path, const Params& query) {
    httplib::Request r;
    r.method = method;
    r.path = query.empty() ? path : httplib::append_query_params(path, query);
    return r;
}

}  // namespace

Expected<HttpReply> HttpClient::get(const std::string& path, const Params& query,
                                    const std::string& accept) {
    auto r = request("GET", path, query);
    if (!accept.empty()) r.headers.emplace("Accept", accept);
    return exchange(*impl_, server_, r);
}

Expected<HttpReply> HttpClient::postForm(const std::string& path, const Params& form,
                                         const std::string& accept) {
    auto r = request("POST", path, {});
    if (!accept.empty()) r.headers.emplace("Accept", accept);
    r.headers.emplace("Content-Type", "application/x-www-form-urlencoded");
    // The query-string encoding of the pairs is the form encoding, without the '?'.
    if (!form.empty()) r.body = httplib::append_query_params("", form).substr(1);
    return exchange(*impl_, server_, r);
}

Expected<HttpReply> HttpClient::put(const std::string& path, const Params& query,
                                    const std::string& body, const std::string& contentType) {
    auto r = request("PUT", path, query);
    r.headers.emplace("Content-Type", contentType);
    r.body = body;
    return exchange(*impl_, server_, r);
}

Expected<HttpReply> HttpClient::post(const std::string& path, const Params& query,
                                     const std::string& body, const std::string& contentType) {
    auto r = request("POST", path, query);
    r.headers.emplace("Content-Type", contentType);
    r.body = body;
    return exchange(*impl_, server_, r);
}

}  // namespace skillcell::http
