#include "kb/sparql_endpoint.hpp"

namespace skillcell::kb {
namespace {

http::HttpResponse errorResponse(const Error& e) {
    int status = 500;
    switch (e.kind) {
        case ErrorKind::BadInput:
            status = 400;
            break;
        case ErrorKind::Refused:
            status = 409;
            break;
        case ErrorKind::Unavailable:
            status = 503;
            break;
        case ErrorKind::Failed:
            status = 500;
            break;
    }
    return http::makeResponse(status, e.message + "\n");
}

http::HttpResponse methodNotAllowed(const char* allow) {
    auto r = http::makeResponse(405, std::string("allowed: ") + allow + "\n");
    r.headers.set("Allow", allow);
    return r;
}

http::HttpResponse writesRefused() {
    return http::makeResponse(403,
                              "this endpoint takes queries only (skillcell kb --http-writes "
                              "opens it to updates and loads; OPC UA's Update needs no such "
                              "switch, it checks the user's role)\n");
}

// The media type of a request body, without parameters; empty when there is none.
std::string contentTypeOf(const http::HttpRequest& request) {
    const auto header = request.headers.get("Content-Type");
    if (!header) return {};
    auto parsed = http::parseMediaType(*header);
    return parsed ? parsed->essence() : std::string("invalid");
}

// What to ask the store for: the client's Accept as it is (the store negotiates by query
// form), or JSON results and Turtle when the client did not say.
std::string acceptOf(const http::HttpRequest& request) {
    const auto accept = request.headers.get("Accept");
    if (!accept || accept->empty() || *accept == "*/*") {
        return std::string(media::kSparqlJson) + ", " + media::kTurtle + ";q=0.9";
    }
    return std::string(*accept);
}

}  // namespace

http::HttpResponse SparqlEndpoint::handle(const http::HttpRequest& request) {
    if (request.path == "/sparql") return sparql(request);
    if (request.path == "/graphs") return graphs(request);
    return http::makeResponse(404, "no such resource: " + request.path +
                                       " (the SPARQL endpoint is /sparql; graphs at /graphs)\n");
}

http::HttpResponse SparqlEndpoint::sparql(const http::HttpRequest& request) {
    std::optional<std::string> query;
    std::optional<std::string> update;
    if (request.method == "GET") {
        if (http::findParam(request.query, "update")) {
            return http::makeResponse(400, "an update must be sent with POST\n");
        }
        if (auto q = http::findParam(request.query, "query")) query = std::string(*q);
    } else if (request.method == "POST") {
        const std::string type = contentTypeOf(request);
        if (type == "application/x-www-form-urlencoded") {
            auto form = http::parseFormUrlEncoded(request.body);
            if (!form) return http::makeResponse(400, form.error() + "\n");
            if (auto q = http::findParam(*form, "query")) query = std::string(*q);
            if (auto u = http::findParam(*form, "update")) update = std::string(*u);
        } else if (type == "application/sparql-query") {
            query = request.body;
        } else if (type == "application/sparql-update") {
            update = request.body;
        } else {
            return http::makeResponse(
                415,
                "POST takes application/x-www-form-urlencoded, application/sparql-query "
                "or application/sparql-update, not '" +
                    type + "'\n");
        }
    } else {
        return methodNotAllowed("GET, POST");
    }
    if (query && update) return http::makeResponse(400, "give a query or an update, not both\n");
    if (!query && !update) {
        return http::makeResponse(400, "no 'query' (or, with POST, 'update') parameter\n");
    }
    if (update) {
        if (!acceptWrites_) return writesRefused();
        auto s = kb_.update(*update);
        if (!s) return errorResponse(s.failure());
        return http::makeResponse(200, "OK\n");
    }
    auto r = kb_.query(*query, acceptOf(request));
    if (!r) return errorResponse(r.failure());
    return http::makeResponse(200, std::move(r->body),
                              r->contentType.empty() ? "application/octet-stream" : r->contentType);
}

http::HttpResponse SparqlEndpoint::graphs(const http::HttpRequest& request) {
    if (request.method == "GET") {
        auto list = kb_.graphs();
        if (!list) return errorResponse(list.failure());
        std::string body;
        for (const auto& g : *list) body += g + "\n";
        return http::makeResponse(200, std::move(body));
    }
    if (request.method == "PUT") {
        if (!acceptWrites_) return writesRefused();
        const auto graph = http::findParam(request.query, "graph");
        if (!graph || graph->empty()) {
            return http::makeResponse(400, "PUT /graphs needs ?graph=<IRI>\n");
        }
        const std::string type = contentTypeOf(request);
        if (type != "text/turtle" && type != "application/n-triples") {
            return http::makeResponse(415,
                                      "a graph is sent as text/turtle or "
                                      "application/n-triples, not '" +
                                          type + "'\n");
        }
        auto s = kb_.loadTurtle(std::string(*graph), request.body);
        if (!s) return errorResponse(s.failure());
        return http::makeResponse(200, "loaded <" + std::string(*graph) + ">\n");
    }
    return methodNotAllowed("GET, PUT");
}

}  // namespace skillcell::kb
