#pragma once
// SparqlEndpoint: the knowledge base over HTTP. One request in, one response out; no I/O of
// its own (HttpServer carries the bytes), so every answer can be tested without a socket.
//
//   GET  /sparql?query=Q                       SPARQL 1.1 Protocol query
//   POST /sparql  query=Q | update=U           form-encoded (application/x-www-form-urlencoded)
//   POST /sparql  application/sparql-query     the body is the query
//   POST /sparql  application/sparql-update    the body is the update
//   GET  /graphs                               the loaded graphs, one IRI per line
//   PUT  /graphs?graph=IRI  text/turtle        replace a graph, checked by the reasoner
//
// Results come in the media type the client's Accept asks for (JSON results by default for
// SELECT and ASK, Turtle for CONSTRUCT and DESCRIBE), as the store serializes them. A bad
// query or update is 400 with the engine's message; a load the reasoner refuses is 409 with
// the conflicting statements; an unreachable store 503.
//
// HTTP has no users here (OPC UA has, and its Update needs the Engineer role): unless the
// endpoint is told to take writes, updates and PUT are 403, so that a query port left open
// cannot change the plant's models.
#include "kb/http/http_message.hpp"
#include "kb/knowledge_base.hpp"

namespace skillcell::kb {

class SparqlEndpoint {
public:
    /// `acceptWrites`: take SPARQL updates and graph loads (else 403).
    SparqlEndpoint(KnowledgeBase& kb, bool acceptWrites) : kb_(kb), acceptWrites_(acceptWrites) {}

    /// Answers one request. Blocks while the store works: call it off the I/O thread.
    [[nodiscard]] http::HttpResponse handle(const http::HttpRequest& request);

private:
    http::HttpResponse sparql(const http::HttpRequest& request);
    http::HttpResponse graphs(const http::HttpRequest& request);

    KnowledgeBase& kb_;
    bool acceptWrites_;
};

}  // namespace skillcell::kb
