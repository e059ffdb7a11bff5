#include "kb/store/http_sparql_store.hpp"

#include "kb/engine/virtuoso_instance.hpp"

namespace skillcell::kb {
namespace {

// The engine's own words for a refusal, shortened: Virtuoso answers a syntax error with a
// plain-text page that starts with the message that matters.
// A 4xx is the request's fault (a syntax error), anything else the engine's; 401 and 403
// say that the store does not take us as the user we are.
Error engineError(const std::string& where, const http::HttpReply& r) {
    std::string body = r.body.substr(0, 2000);
    while (!body.empty() && (body.back() == '\n' || body.back() == '\r')) body.pop_back();
    const std::string text =
        where + ": HTTP " + std::to_string(r.status) + (body.empty() ? "" : ": " + body);
    if (r.status == 401 || r.status == 403) return Error{text, ErrorKind::Refused};
    return Error{text, r.status >= 400 && r.status < 500 ? ErrorKind::BadInput : ErrorKind::Failed};
}

}  // namespace

Expected<HttpSparqlEndpoint> HttpSparqlEndpoint::fromUrl(const std::string& url) {
    auto parsed = http::HttpUrl::parse(url);
    if (!parsed) return badInput("SPARQL endpoint " + parsed.error());
    HttpSparqlEndpoint e;
    e.url = std::move(*parsed);
    return e;
}

HttpSparqlEndpoint HttpSparqlEndpoint::of(const engine::VirtuosoInstance& virtuoso) {
    HttpSparqlEndpoint e;
    if (auto url = http::HttpUrl::parse(virtuoso.sparqlUrl())) e.url = std::move(*url);
    e.graphStorePath = engine::VirtuosoInstance::graphStorePath();
    e.client.auth = {http::ClientAuth::Kind::Digest, engine::VirtuosoInstance::sparqlUser(),
                     virtuoso.sparqlPassword()};
    return e;
}

HttpSparqlStore::HttpSparqlStore(HttpSparqlEndpoint endpoint)
    : endpoint_(std::move(endpoint)),
      client_(std::make_unique<http::HttpClient>(endpoint_.url, endpoint_.client)) {}

Expected<SparqlResponse> HttpSparqlStore::query(const std::string& sparql,
                                                const std::string& accept) {
    auto reply = client_->postForm(endpoint_.url.path, {{"query", sparql}}, accept);
    if (!reply) return Error{"SPARQL endpoint " + reply.error(), ErrorKind::Unavailable};
    if (reply->status != 200) return engineError(endpoint_.urlText(), *reply);
    return SparqlResponse{std::move(reply->contentType), std::move(reply->body)};
}

namespace {

/// Bodies up to this size go to the graph store in one request.
constexpr std::size_t kGraphPiece = std::size_t{256} * 1024;

}  // namespace

Status HttpSparqlStore::sendGraph(bool replace, const std::string& graphIri,
                                  const std::string& nTriples) {
    const http::Params graph{{"graph", graphIri}};
    auto reply = replace
                     ? client_->put(endpoint_.graphStorePath, graph, nTriples, media::kNTriples)
                     : client_->post(endpoint_.graphStorePath, graph, nTriples, media::kNTriples);
    const std::string where = endpoint_.url.withPath(endpoint_.graphStorePath).toString();
    if (!reply) return Error{"graph store " + reply.error(), ErrorKind::Unavailable};
    // 201 Created for a new graph, 200 or 204 for a replaced or merged one.
    if (reply->status < 200 || reply->status > 299) return engineError(where, *reply);
    return Done{};
}

Status HttpSparqlStore::replaceGraph(const std::string& graphIri, const std::string& nTriples) {
    if (!replacesGraphs()) return SparqlStore::replaceGraph(graphIri, nTriples);
    if (nTriples.size() <= kGraphPiece) return sendGraph(true, graphIri, nTriples);
    // A large graph goes in pieces (whole lines) into a staging graph that one update then
    // moves over the graph: a store may answer the first request of an authentication
    // exchange before it has read a large body and hang up (Virtuoso with Digest does), and
    // a reader sees the old graph or the new one, never half of it.
    const std::string staging =
        graphIri + (graphIri.find('#') == std::string::npos ? "#staging" : "-staging");
    bool first = true;
    for (std::size_t begin = 0; begin < nTriples.size(); first = false) {
        std::size_t end = nTriples.size();
        if (begin + kGraphPiece < end) {
            const std::size_t nl = nTriples.find('\n', begin + kGraphPiece);
            end = nl == std::string::npos ? end : nl + 1;
        }
        if (auto st = sendGraph(first, staging, nTriples.substr(begin, end - begin)); !st) {
            (void)update("DROP SILENT GRAPH <" + staging + ">");
            return st;
        }
        begin = end;
    }
    return update("MOVE <" + staging + "> TO <" + graphIri + ">");
}

Status HttpSparqlStore::update(const std::string& sparqlUpdate) {
    auto reply = client_->postForm(endpoint_.url.path, {{"update", sparqlUpdate}}, "");
    if (!reply) return Error{"SPARQL endpoint " + reply.error(), ErrorKind::Unavailable};
    if (reply->status < 200 || reply->status > 299) return engineError(endpoint_.urlText(), *reply);
    return Done{};
}

}  // namespace skillcell::kb
