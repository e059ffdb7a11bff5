#include "kb/store/http_sparql_store.hpp"

#include <charconv>

#include "kb/http/http_client.hpp"
#include "kb/http/http_message.hpp"

namespace skillcell::kb {
namespace {

// The engine's own words for a refusal, shortened: Virtuoso answers a syntax error with a
// plain-text page that starts with the message that matters.
// A 4xx is the request's fault (a syntax error), anything else the engine's.
Error engineError(const http::HttpResponse& r) {
    std::string body = r.body.substr(0, 2000);
    while (!body.empty() && (body.back() == '\n' || body.back() == '\r')) body.pop_back();
    return Error{"HTTP " + std::to_string(r.status) + (body.empty() ? "" : ": " + body),
                 r.status >= 400 && r.status < 500 ? ErrorKind::BadInput : ErrorKind::Failed};
}

Expected<http::HttpResponse> post(const HttpSparqlEndpoint& e, const http::Params& form,
                                  const std::string& accept) {
    http::HttpRequest request;
    request.method = "POST";
    request.path = e.path;
    request.headers.add("Content-Type", "application/x-www-form-urlencoded");
    if (!accept.empty()) request.headers.add("Accept", accept);
    request.body = http::formUrlEncode(form);
    auto response = http::httpRequest(e.host, e.port, std::move(request), e.timeout);
    if (!response) {
        return Error{"SPARQL endpoint " + e.url() + ": " + response.error(),
                     ErrorKind::Unavailable};
    }
    return response;
}

}  // namespace

Expected<HttpSparqlEndpoint> HttpSparqlEndpoint::fromUrl(const std::string& url) {
    constexpr std::string_view kScheme = "http://";
    if (url.rfind(kScheme, 0) != 0) {
        return Error{"SPARQL endpoint '" + url + "': only http:// URLs are supported"};
    }
    const std::string rest = url.substr(kScheme.size());
    const auto slash = rest.find('/');
    const std::string authority = rest.substr(0, slash);
    HttpSparqlEndpoint e;
    e.path = slash == std::string::npos ? "/" : rest.substr(slash);
    const auto colon = authority.rfind(':');
    if (colon == std::string::npos) {
        e.host = authority;
        e.port = 80;
    } else {
        e.host = authority.substr(0, colon);
        const std::string portText = authority.substr(colon + 1);
        unsigned port = 0;
        auto [end, ec] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
        if (ec != std::errc{} || end != portText.data() + portText.size() || port == 0 ||
            port > 65535) {
            return Error{"SPARQL endpoint '" + url + "': bad port '" + portText + "'"};
        }
        e.port = static_cast<std::uint16_t>(port);
    }
    if (e.host.empty()) return Error{"SPARQL endpoint '" + url + "': no host"};
    return e;
}

std::string HttpSparqlEndpoint::url() const {
    return "http://" + host + ":" + std::to_string(port) + path;
}

Expected<SparqlResponse> HttpSparqlStore::query(const std::string& sparql,
                                                const std::string& accept) {
    auto response = post(endpoint_, {{"query", sparql}}, accept);
    if (!response) return response.failure();
    if (response->status != 200) return engineError(*response);
    SparqlResponse out;
    out.contentType = std::string(response->headers.get("Content-Type").value_or(""));
    out.body = std::move(response->body);
    return out;
}

Status HttpSparqlStore::replaceGraph(const std::string& graphIri, const std::string& nTriples) {
    if (!replacesGraphs()) return SparqlStore::replaceGraph(graphIri, nTriples);
    http::HttpRequest request;
    request.method = "PUT";
    request.path = endpoint_.graphStorePath;
    request.query = {{"graph", graphIri}};
    request.headers.add("Content-Type", media::kNTriples);
    request.body = nTriples;
    auto response =
        http::httpRequest(endpoint_.host, endpoint_.port, std::move(request), endpoint_.timeout);
    if (!response) {
        HttpSparqlEndpoint graphStore = endpoint_;
        graphStore.path = endpoint_.graphStorePath;
        return Error{"graph store " + graphStore.url() + ": " + response.error(),
                     ErrorKind::Unavailable};
    }
    // 201 Created for a new graph, 200 or 204 for a replaced one.
    if (response->status < 200 || response->status > 299) return engineError(*response);
    return Done{};
}

Status HttpSparqlStore::update(const std::string& sparqlUpdate) {
    auto response = post(endpoint_, {{"update", sparqlUpdate}}, "");
    if (!response) return response.failure();
    if (response->status < 200 || response->status > 299) return engineError(*response);
    return Done{};
}

}  // namespace skillcell::kb
