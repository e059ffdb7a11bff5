#pragma once
// HttpSparqlStore: any SPARQL 1.1 Protocol endpoint by URL (Virtuoso's /sparql, or a remote
// store for plants that outgrow one machine). Queries and updates are sent form-encoded in a
// POST: Virtuoso can hang on a POST with application/sparql-query (INTEROP-NOTES.md), and
// form encoding is the one form every SPARQL 1.1 endpoint must take.
#include <chrono>
#include <cstdint>
#include <string>

#include "kb/store/sparql_store.hpp"

namespace skillcell::kb {

struct HttpSparqlEndpoint {
    std::string host = "127.0.0.1";  // numeric: resolution is not bounded by the timeout
    std::uint16_t port = 8890;
    std::string path = "/sparql";
    std::chrono::milliseconds timeout{30'000};
    /// The path of the same server's SPARQL 1.1 Graph Store HTTP Protocol service
    /// (Virtuoso: /sparql-graph-crud); empty when it has none or it is not known.
    std::string graphStorePath;

    /// Parses "http://HOST:PORT/PATH"; an Error says what is wrong with it.
    [[nodiscard]] static Expected<HttpSparqlEndpoint> fromUrl(const std::string& url);
    [[nodiscard]] std::string url() const;
};

class HttpSparqlStore final : public SparqlStore {
public:
    explicit HttpSparqlStore(HttpSparqlEndpoint endpoint) : endpoint_(std::move(endpoint)) {}

    [[nodiscard]] Expected<SparqlResponse> query(const std::string& sparql,
                                                 const std::string& accept) override;
    [[nodiscard]] Status update(const std::string& sparqlUpdate) override;
    [[nodiscard]] bool replacesGraphs() const override { return !endpoint_.graphStorePath.empty(); }
    [[nodiscard]] Status replaceGraph(const std::string& graphIri,
                                      const std::string& nTriples) override;

    [[nodiscard]] const HttpSparqlEndpoint& endpoint() const { return endpoint_; }

private:
    HttpSparqlEndpoint endpoint_;
};

}  // namespace skillcell::kb
