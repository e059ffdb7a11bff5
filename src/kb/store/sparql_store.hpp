#pragma once
// SparqlStore: what the knowledge base needs of a triple store (query, update), so that
// Virtuoso is one engine among possible others. Results stay in the engine's serialization
// (SPARQL JSON, Turtle, ...): the KB forwards them and parses only what it reads itself.
#include <string>

#include "kb/expected.hpp"

namespace skillcell::kb {

namespace media {
inline constexpr const char* kSparqlJson = "application/sparql-results+json";
inline constexpr const char* kSparqlXml = "application/sparql-results+xml";
inline constexpr const char* kTurtle = "text/turtle";
inline constexpr const char* kNTriples = "application/n-triples";
}  // namespace media

struct SparqlResponse {
    std::string contentType;
    std::string body;
};

class SparqlStore {
public:
    virtual ~SparqlStore() = default;
    /// Runs a query (SELECT, ASK: results in `accept`, e.g. media::kSparqlJson; CONSTRUCT,
    /// DESCRIBE: RDF in `accept`, e.g. media::kTurtle). An Error carries the engine's message.
    [[nodiscard]] virtual Expected<SparqlResponse> query(const std::string& sparql,
                                                         const std::string& accept) = 0;
    /// Runs a SPARQL 1.1 Update request: all its operations or none.
    [[nodiscard]] virtual Status update(const std::string& sparqlUpdate) = 0;

    /// Whether replaceGraph() works: the store offers the SPARQL 1.1 Graph Store HTTP
    /// Protocol. Loading a document that way is an order of magnitude cheaper for Virtuoso
    /// than INSERT DATA, which it compiles to SQL (6,300 triples: 0.1 s of CPU against 2 s).
    [[nodiscard]] virtual bool replacesGraphs() const { return false; }
    /// Replaces the content of one graph by an N-Triples document (Graph Store PUT). Blank
    /// node labels are the document's: the same label is the same node within it only.
    [[nodiscard]] virtual Status replaceGraph(const std::string& graphIri,
                                              const std::string& nTriples) {
        (void)graphIri;
        (void)nTriples;
        return Error{"this store does not take whole graphs (SPARQL 1.1 Graph Store)"};
    }
};

}  // namespace skillcell::kb
