#include "kb/sparql_endpoint.hpp"

#include <spdlog/spdlog.h>

#include "http/web_server.hpp"
#include "kb/sparql_form.hpp"

namespace skillcell::kb {
namespace {

void answer(httplib::Response& r, int status, const std::string& text) {
    r.status = status;
    r.set_content(text, "text/plain; charset=utf-8");
}

void errorResponse(httplib::Response& r, const Error& e) {
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
    answer(r, status, e.message + "\n");
}

void methodNotAllowed(httplib::Response& r, const char* allow) {
    answer(r, 405, std::string("allowed: ") + allow + "\n");
    r.set_header("Allow", allow);
}

// The media type of a request body, without parameters, lower-case; empty when none.
std::string contentTypeOf(const httplib::Request& request) {
    std::string type = request.get_header_value("Content-Type");
    type = type.substr(0, type.find(';'));
    while (!type.empty() && (type.back() == ' ' || type.back() == '\t')) type.pop_back();
    for (auto& c : type) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return type;
}

// What to ask the store for: the client's Accept as it is (the store negotiates by query
// form), or JSON results and Turtle when the client did not say.
std::string acceptOf(const httplib::Request& request) {
    std::string accept = request.get_header_value("Accept");
    if (accept.empty() || accept == "*/*") {
        return std::string(media::kSparqlJson) + ", " + media::kTurtle + ";q=0.9";
    }
    return accept;
}

std::optional<std::string> param(const httplib::Request& request, const char* name) {
    if (!request.has_param(name)) return std::nullopt;
    return request.get_param_value(name);
}

}  // namespace

void SparqlEndpoint::serveOn(http::WebServer& server) {
    auto h = [this](const httplib::Request& q, httplib::Response& r, const ua::UserIdentity& u) {
        handle(q, r, u);
    };
    server.get("/sparql", h);
    server.post("/sparql", h);
    server.get("/graphs", h);
    server.put("/graphs", h);
}

void SparqlEndpoint::handle(const httplib::Request& request, httplib::Response& response,
                            const ua::UserIdentity& user) {
    if (!user.roles.atLeast(ua::Role::Observer)) {
        answer(response, 403, "user " + user.name + " has no role that may read the KB\n");
        return;
    }
    if (request.path == "/sparql") return sparql(request, response, user);
    if (request.path == "/graphs") return graphs(request, response, user);
    answer(response, 404,
           "no such resource: " + request.path +
               " (the SPARQL endpoint is /sparql; graphs at /graphs)\n");
}

bool SparqlEndpoint::mayWrite(const ua::UserIdentity& user, httplib::Response& response) const {
    if (!acceptWrites_) {
        answer(response, 403,
               "this endpoint takes queries only (a KB without users takes updates with "
               "--http-writes)\n");
        return false;
    }
    if (!user.roles.atLeast(ua::Role::Engineer)) {
        spdlog::warn("kb: an update by {} ({}) refused: it needs the role Engineer", user.name,
                     user.roles.toString());
        answer(response, 403,
               "user " + user.name + " (" + user.roles.toString() +
                   ") may query, not change, the KB: updates need the role Engineer\n");
        return false;
    }
    return true;
}

void SparqlEndpoint::sparql(const httplib::Request& request, httplib::Response& response,
                            const ua::UserIdentity& user) {
    std::optional<std::string> query;
    std::optional<std::string> update;
    if (request.method == "GET") {
        if (request.has_param("update")) {
            return answer(response, 400, "an update must be sent with POST\n");
        }
        query = param(request, "query");
    } else if (request.method == "POST") {
        const std::string type = contentTypeOf(request);
        if (type == "application/x-www-form-urlencoded") {
            query = param(request, "query");
            update = param(request, "update");
        } else if (type == "application/sparql-query") {
            query = request.body;
        } else if (type == "application/sparql-update") {
            update = request.body;
        } else {
            return answer(response, 415,
                          "POST takes application/x-www-form-urlencoded, "
                          "application/sparql-query or application/sparql-update, not '" +
                              type + "'\n");
        }
    } else {
        return methodNotAllowed(response, "GET, POST");
    }
    if (query && update) return answer(response, 400, "give a query or an update, not both\n");
    if (!query && !update) {
        return answer(response, 400, "no 'query' (or, with POST, 'update') parameter\n");
    }
    // What the text is decides, not the parameter it came in.
    if (query && !isQuery(*query)) {
        if (request.method == "GET") {
            return answer(response, 400,
                          "this 'query' is an update (it is not SELECT, CONSTRUCT, DESCRIBE or "
                          "ASK): send it with POST as 'update'\n");
        }
        update.swap(query);  // query is empty now
    }
    if (update) {
        if (!mayWrite(user, response)) return;
        if (auto s = kb_.update(*update); !s) return errorResponse(response, s.failure());
        spdlog::info("kb: an update by {} applied", user.name);
        return answer(response, 200, "OK\n");
    }
    auto r = kb_.query(*query, acceptOf(request));
    if (!r) return errorResponse(response, r.failure());
    response.status = 200;
    response.set_content(r->body,
                         r->contentType.empty() ? "application/octet-stream" : r->contentType);
}

void SparqlEndpoint::graphs(const httplib::Request& request, httplib::Response& response,
                            const ua::UserIdentity& user) {
    if (request.method == "GET") {
        auto list = kb_.graphs();
        if (!list) return errorResponse(response, list.failure());
        std::string body;
        for (const auto& g : *list) body += g + "\n";
        return answer(response, 200, body);
    }
    if (request.method == "PUT") {
        if (!mayWrite(user, response)) return;
        const auto graph = param(request, "graph");
        if (!graph || graph->empty()) {
            return answer(response, 400, "PUT /graphs needs ?graph=<IRI>\n");
        }
        const std::string type = contentTypeOf(request);
        if (type != "text/turtle" && type != "application/n-triples") {
            return answer(
                response, 415,
                "a graph is sent as text/turtle or application/n-triples, not '" + type + "'\n");
        }
        if (auto s = kb_.loadTurtle(*graph, request.body); !s) {
            return errorResponse(response, s.failure());
        }
        spdlog::info("kb: graph <{}> loaded by {}", *graph, user.name);
        return answer(response, 200, "loaded <" + *graph + ">\n");
    }
    methodNotAllowed(response, "GET, PUT");
}

}  // namespace skillcell::kb
