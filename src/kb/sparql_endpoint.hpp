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
#include "kb/http/http_message.hpp"
#include "kb/knowledge_base.hpp"

namespace skillcell::kb {

class SparqlEndpoint {
public:
    explicit SparqlEndpoint(KnowledgeBase& kb) : kb_(kb) {}

    /// Answers one request. Blocks while the store works: call it off the I/O thread.
    [[nodiscard]] http::HttpResponse handle(const http::HttpRequest& request);

private:
    http::HttpResponse sparql(const http::HttpRequest& request);
    http::HttpResponse graphs(const http::HttpRequest& request);

    KnowledgeBase& kb_;
};

}  // namespace skillcell::kb
