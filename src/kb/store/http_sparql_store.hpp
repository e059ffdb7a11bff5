#pragma once
// HttpSparqlStore: any SPARQL 1.1 Protocol endpoint by URL (the KB's own Virtuoso, another
// knowledge base, or a remote store for plants that outgrow one machine). Queries and
// updates are sent form-encoded in a POST: Virtuoso can hang on a POST with
// application/sparql-query (INTEROP-NOTES.md), and form encoding is the one form every
// SPARQL 1.1 endpoint must take. HTTPS and users come from the endpoint's ClientOptions.
#include <memory>
#include <string>

#include "http/http_client.hpp"
#include "kb/store/sparql_store.hpp"

namespace skillcell::kb {

namespace engine {
class VirtuosoInstance;
}

struct HttpSparqlEndpoint {
    http::HttpUrl url;
    /// The path of the same server's SPARQL 1.1 Graph Store HTTP Protocol service
    /// (Virtuoso: /sparql-graph-crud-auth); empty when it has none or it is not known.
    std::string graphStorePath;
    /// Time bound, TLS trust and the user the store is used as.
    http::ClientOptions client;

    /// Parses "http[s]://HOST:PORT/PATH"; an Error says what is wrong with it.
    [[nodiscard]] static Expected<HttpSparqlEndpoint> fromUrl(const std::string& url);
    /// A started Virtuoso of the KB's own: its authenticated SPARQL and Graph Store paths,
    /// as its SQL user (Digest).
    [[nodiscard]] static HttpSparqlEndpoint of(const engine::VirtuosoInstance& virtuoso);
    [[nodiscard]] std::string urlText() const { return url.toString(); }
};

class HttpSparqlStore final : public SparqlStore {
public:
    explicit HttpSparqlStore(HttpSparqlEndpoint endpoint);

    [[nodiscard]] Expected<SparqlResponse> query(const std::string& sparql,
                                                 const std::string& accept) override;
    [[nodiscard]] Status update(const std::string& sparqlUpdate) override;
    [[nodiscard]] bool replacesGraphs() const override { return !endpoint_.graphStorePath.empty(); }
    [[nodiscard]] Status replaceGraph(const std::string& graphIri,
                                      const std::string& nTriples) override;

    [[nodiscard]] const HttpSparqlEndpoint& endpoint() const { return endpoint_; }

private:
    /// One Graph Store request: PUT (replace) or POST (merge) of `nTriples` into the graph.
    [[nodiscard]] Status sendGraph(bool replace, const std::string& graphIri,
                                   const std::string& nTriples);

    HttpSparqlEndpoint endpoint_;
    std::unique_ptr<http::HttpClient> client_;
};

}  // namespace skillcell::kb
