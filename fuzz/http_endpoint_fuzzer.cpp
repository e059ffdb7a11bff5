// Fuzzing of the knowledge base's HTTP endpoint as a client reaches it: each input is the
// bytes one TCP connection sends to a real WebServer (cpp-httplib) that serves the SPARQL
// endpoint (kb::SparqlEndpoint) behind its UserGate. cpp-httplib parses the request line,
// headers, chunked and form bodies; the gate parses the Authorization header; the endpoint
// decides what the text is and who may do it; a PUT of a graph goes through the Turtle parser
// and the knowledge base's load.
//
// The store behind the knowledge base is a double that answers every query and takes every
// write, and that is also the oracle of the endpoint's one promise that matters most: nothing
// changes the store unless an Engineer asked (an update sent as `query=`, a graph load by an
// Observer). A write of anyone else aborts, as a crash does; so does a query that is an
// update by its text. Plain HTTP on loopback (TLS is OpenSSL's, not ours to fuzz); the users
// are checked by a fast table instead of scrypt, which would make each input cost 40 ms.
#include <netinet/in.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "http/web_server.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/sparql_endpoint.hpp"
#include "kb/sparql_form.hpp"
#include "process/child_process.hpp"

namespace {

using namespace skillcell;

// The user the gate identified for the request this thread serves (cpp-httplib serves a
// request on one thread of its pool, from the gate's check to the handler's end).
thread_local ua::UserIdentity currentUser;

class TableUsers final : public ua::UserAuthenticator {
public:
    ua::Result<ua::UserIdentity> authenticatePassword(std::string_view name,
                                                      std::string_view password) const override {
        ua::UserIdentity user;
        if (name == "observer" && password == "observer-pw") {
            user = {"observer", ua::RoleSet{ua::Role::Observer}};
        } else if (name == "engineer" && password == "engineer-pw") {
            user = {"engineer", ua::RoleSet{ua::Role::Engineer}};
        } else {
            return ua::status::BadUserAccessDenied;
        }
        currentUser = user;
        return user;
    }
    ua::Result<ua::UserIdentity> authenticateCertificate(const ua::ByteString&) const override {
        return ua::status::BadUserAccessDenied;
    }
};

void requireEngineer(const char* what) {
    if (!currentUser.roles.atLeast(ua::Role::Engineer)) {
        std::fprintf(stderr, "finding: %s reached the store for user '%s' (%s)\n", what,
                     currentUser.name.c_str(), currentUser.roles.toString().c_str());
        std::abort();
    }
}

class OracleStore final : public kb::SparqlStore {
public:
    kb::Expected<kb::SparqlResponse> query(const std::string& sparql,
                                           const std::string& accept) override {
        (void)accept;
        if (!kb::isQuery(sparql)) {
            std::fprintf(stderr, "finding: an update reached the store as a query\n");
            std::abort();
        }
        return kb::SparqlResponse{"application/sparql-results+json",
                                  R"({"head":{"vars":["g"]},"results":{"bindings":[]}})"};
    }
    kb::Status update(const std::string& sparqlUpdate) override {
        (void)sparqlUpdate;
        requireEngineer("an update");
        return kb::Done{};
    }
    [[nodiscard]] bool replacesGraphs() const override { return true; }
    kb::Status replaceGraph(const std::string& graphIri, const std::string& nTriples) override {
        (void)graphIri;
        (void)nTriples;
        requireEngineer("a graph load");
        return kb::Done{};
    }
};

struct Harness {
    OracleStore store;
    kb::KnowledgeBase kb{store, nullptr};
    kb::SparqlEndpoint endpoint{kb, true};
    std::unique_ptr<http::WebServer> server;

    Harness() {
        spdlog::set_level(spdlog::level::off);
        http::WebServerConfig config;
        // Nothing remembered: every request's user comes from TableUsers, on its thread.
        config.gate = std::make_shared<http::UserGate>(std::make_shared<TableUsers>(),
                                                       ua::RoleSet{}, std::chrono::seconds(0));
        config.readTimeout = std::chrono::milliseconds(200);
        config.writeTimeout = std::chrono::milliseconds(200);
        config.maxBodyBytes = 1 << 16;
        config.threads = 2;
        server = std::make_unique<http::WebServer>(config);
        endpoint.serveOn(*server);
        if (!server->start()) {
            std::fprintf(stderr, "the web server did not start\n");
            std::abort();
        }
    }
};

/// Whether a thread of this process other than the caller is runnable (state R): the server
/// working, or waiting for a CPU, which a loaded machine gives a fuzzer at nice 19 seldom.
bool othersRunnable() {
    const std::string self = std::to_string(::gettid());
    std::error_code ec;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
        if (task.path().filename() == self) continue;
        std::ifstream stat(task.path() / "stat");
        std::string fields;
        std::getline(stat, fields);
        const auto close = fields.rfind(')');
        if (close != std::string::npos && close + 2 < fields.size() && fields[close + 2] == 'R') {
            return true;
        }
    }
    return false;
}

/// Before a hang is reported: what each thread of this process waits in (state and kernel
/// wait channel), to tell a deadlock (futex) from a wait on the network (poll, accept).
void describeThreads() {
    std::error_code ec;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
        std::ifstream comm(task.path() / "comm");
        std::ifstream wchan(task.path() / "wchan");
        std::ifstream stat(task.path() / "stat");
        std::string name;
        std::string channel;
        std::string fields;
        std::getline(comm, name);
        std::getline(wchan, channel);
        std::getline(stat, fields);
        const auto close = fields.rfind(')');
        const char state =
            close != std::string::npos && close + 2 < fields.size() ? fields[close + 2] : '?';
        std::fprintf(stderr, "  thread %s (%s): state %c, waiting in %s\n",
                     task.path().filename().c_str(), name.c_str(), state, channel.c_str());
    }
    // Where each thread is, in our code and cpp-httplib's: a wait channel names only the
    // kernel's side. gdb, where the machine has it (bounded: 60 s).
    if (process::findInPath("gdb").empty()) return;
    auto bt = process::runToCompletion(
        {"gdb", "-p", std::to_string(::getpid()), "-batch", "-nx", "-ex", "thread apply all bt 40"},
        std::chrono::seconds(60));
    if (bt) std::fprintf(stderr, "%s\n", bt->out.c_str());
}

/// Sends `data` on a new connection, closes our side, and reads the answer to its end.
void exchange(std::uint16_t port, const std::uint8_t* data, std::size_t size) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) std::abort();
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) std::abort();
    std::size_t sent = 0;
    while (sent < size) {
        const auto n = ::send(fd, data + sent, size - sent, MSG_NOSIGNAL);
        if (n <= 0) break;  // the server may close early (a request it refused)
        sent += static_cast<std::size_t>(n);
    }
    ::shutdown(fd, SHUT_WR);
    // Bounded: the server's read timeout (200 ms) ends any request it waits on, so 30 s
    // without an answer or a close while every thread of the server sleeps is a hang. A
    // server thread that is runnable is not hung but starved: at nice 19 beside a build, the
    // three earlier "hangs" were that (a pool thread in state R at the 30 s mark, idle a
    // moment later, and the input alone runs in 1 ms). Up to 10 such waits (5 min), then
    // whatever the threads do is a finding: a loop that never ends is one too.
    std::array<char, 4096> buffer{};
    int starved = 0;
    for (int i = 0; i < 1000; ++i) {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, 30'000) <= 0) {
            if (othersRunnable() && ++starved <= 10) continue;
            std::fprintf(stderr, "finding: no answer and no close within %d s\n",
                         30 * (starved + 1));
            describeThreads();
            std::abort();
        }
        if (::recv(fd, buffer.data(), buffer.size(), 0) <= 0) break;
    }
    ::close(fd);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static Harness harness;  // one server for the whole run, as a deployed KB has
    exchange(harness.server->port(), data, size);
    return 0;
}
