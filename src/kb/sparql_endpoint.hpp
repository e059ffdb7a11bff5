#pragma once
// SparqlEndpoint: the knowledge base over HTTP(S) (http/web_server.hpp carries the bytes).
//
//   GET  /sparql?query=Q                       SPARQL 1.1 Protocol query
//   POST /sparql  query=Q | update=U           form-encoded (application/x-www-form-urlencoded)
//   POST /sparql  application/sparql-query     the body is the query
//   POST /sparql  application/sparql-update    the body is the update
//   GET  /graphs                               the loaded graphs, one IRI per line
//   PUT  /graphs?graph=IRI  text/turtle        replace a graph, checked by the reasoner
//
// Who may do what follows the cell's roles, as on the KB's OPC UA server: an Observer (and
// every role above) queries; an Engineer also updates and loads graphs. What a request is
// comes from its text (kb/sparql_form.hpp): an update sent as `query=` is an update. A
// server without users (--insecure) takes updates only when told to (`acceptWrites`).
//
// Results come in the media type the client's Accept asks for (JSON results by default for
// SELECT and ASK, Turtle for CONSTRUCT and DESCRIBE), as the store serializes them. A bad
// query or update is 400 with the engine's message; a load the reasoner refuses is 409 with
// the conflicting statements; an unreachable store 503; a role too small 403.
#include <httplib.h>

#include "kb/knowledge_base.hpp"
#include "ua/server/user_identity.hpp"

namespace skillcell::http {
class WebServer;
}

namespace skillcell::kb {

class SparqlEndpoint {
public:
    /// `acceptWrites`: take SPARQL updates and graph loads from users whose role allows
    /// them (else 403 for everyone).
    SparqlEndpoint(KnowledgeBase& kb, bool acceptWrites) : kb_(kb), acceptWrites_(acceptWrites) {}

    /// Routes /sparql and /graphs on `server`, before it starts.
    void serveOn(http::WebServer& server);

    /// Answers one request of `user`. Blocks while the store works. Public so that every
    /// answer can be tested without a socket; `request.params` holds the query string's and
    /// a form body's parameters, as the server parses them.
    void handle(const httplib::Request& request, httplib::Response& response,
                const ua::UserIdentity& user);

private:
    void sparql(const httplib::Request& request, httplib::Response& response,
                const ua::UserIdentity& user);
    void graphs(const httplib::Request& request, httplib::Response& response,
                const ua::UserIdentity& user);
    /// Whether `user` may write; answers 403 when not.
    bool mayWrite(const ua::UserIdentity& user, httplib::Response& response) const;

    KnowledgeBase& kb_;
    bool acceptWrites_;
};

}  // namespace skillcell::kb
