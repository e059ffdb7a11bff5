// `skillcell kb`: the knowledge base as a component of the cell (docs/knowledge_base.md).
//
// It starts and supervises a private Virtuoso in its data directory (or uses the SPARQL 1.1
// endpoint given by --sparql-url), loads the project's ontologies and every embedded NodeSet
// as OWL (checked by Konclude), and then serves:
//   - a SPARQL 1.1 Protocol endpoint at https://<http-host>:<http-port>/sparql, and /graphs
//     (kb/sparql_endpoint.hpp), with the KB's certificate and the cell's users (plain http
//     on loopback only with --insecure);
//   - Objects/KnowledgeBase on its OPC UA server: Query(Query, Accept) -> (Result,
//     ContentType) for Observers, Update(Update) for Engineers;
//   - discovery-driven loading: every component discovery finds gets a graph with its skills
//     and their parameter values as read from it (kb/component_graph.hpp,
//     kb/component_reader.hpp), kept current as skills come and go, and the models of every
//     namespace in its NamespaceArray that --models holds.
// Prints "SPARQL <url>" once the endpoint listens, then the server process's "READY <url>".
#include <spdlog/spdlog.h>

#include <asio/steady_timer.hpp>
#include <asio/thread_pool.hpp>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include "cell/cell_file.hpp"
#include "cell/component_uris.hpp"
#include "cell/scene_graph.hpp"
#include "commands.hpp"
#include "http/web_server.hpp"
#include "kb/component_graph.hpp"
#include "kb/component_reader.hpp"
#include "kb/engine/konclude_reasoner.hpp"
#include "kb/engine/virtuoso_instance.hpp"
#include "kb/engine/virtuoso_watch.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/owl/model_repository.hpp"
#include "kb/rdf/turtle.hpp"
#include "kb/sparql_endpoint.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "process/child_process.hpp"
#include "server_process.hpp"
#include "sparql_client_options.hpp"
#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::apps {

namespace {

namespace fs = std::filesystem;

struct KbOptions {
    ServerProcessOptions process;
    std::string dataDir;
    std::string sparqlUrl;
    std::string httpHost = "127.0.0.1";
    std::uint16_t httpPort = 8870;  // not 8890, Virtuoso's own default
    std::uint16_t virtuosoHttpPort = 0;
    std::uint16_t virtuosoSqlPort = 0;
    bool demoProcess = false;
    bool noReasoner = false;
    std::string koncludeBinary = kb::engine::KoncludeConfig{}.binary;
    bool httpWrites = false;
    std::vector<std::string> loads;      // GRAPH=FILE
    std::vector<std::string> processes;  // Turtle files, each in a graph of its own
    std::string cellFile;                // whose scene (docks, tools, objects) to load
    std::string modelsDir;
};

fs::path defaultDataDir() {
    const char* home = std::getenv("HOME");
    return fs::path(home != nullptr ? home : "/tmp") / ".local/share/skillcell/kb";
}

ua::StatusCode statusOf(const kb::Error& e) {
    switch (e.kind) {
        case kb::ErrorKind::BadInput:
            return ua::status::BadSyntaxError;
        case kb::ErrorKind::Refused:
            return ua::status::BadInvalidState;
        case kb::ErrorKind::Unavailable:
            return ua::status::BadResourceUnavailable;
        case kb::ErrorKind::Failed:
            break;
    }
    return ua::status::BadInternalError;
}

const ua::Variant* stringInput(std::span<const ua::Variant> in, std::size_t i) {
    return i < in.size() && in[i].get<ua::String>() != nullptr ? &in[i] : nullptr;
}

ua::Argument argument(const char* name, const char* text) {
    ua::Argument a;
    a.name = name;
    a.dataType = ua::NodeId(ua::ns0::String);
    a.description = ua::LocalizedText{"", text};
    return a;
}

// Objects/KnowledgeBase with Query and Update. The methods block the server's thread while
// the store works (a SPARQL query takes milliseconds here); long analyses belong on /sparql.
ua::StatusCode addKnowledgeBaseNodes(ua::AddressSpace& as, kb::KnowledgeBase& knowledge) {
    const ua::NodeId object(1, ua::String("KnowledgeBase"));
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), object, "KnowledgeBase"); !r) {
        return r.status();
    }
    auto query = as.addMethod(
        object, ua::NodeId(1, ua::String("KnowledgeBase.Query")), "Query",
        {argument("Query", "a SPARQL 1.1 query"),
         argument("Accept",
                  "the media type of the result (empty: SPARQL JSON results, or "
                  "Turtle for CONSTRUCT)")},
        {argument("Result", "the result, serialized"), argument("ContentType", "its media type")},
        [&knowledge](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                     std::vector<ua::Variant>& out) -> ua::StatusCode {
            const auto* q = stringInput(in, 0);
            const auto* accept = stringInput(in, 1);
            if (q == nullptr || accept == nullptr) return ua::status::BadInvalidArgument;
            std::string acceptText = *accept->get<ua::String>();
            if (acceptText.empty()) {
                acceptText = std::string(kb::media::kSparqlJson) + ", " + kb::media::kTurtle;
            }
            auto r = knowledge.query(*q->get<ua::String>(), acceptText);
            if (!r) {
                spdlog::warn("kb: Query refused: {}", r.error());
                return statusOf(r.failure());
            }
            out.emplace_back(ua::String(std::move(r->body)));
            out.emplace_back(ua::String(std::move(r->contentType)));
            return ua::status::Good;
        });
    if (!query) return query.status();
    (*query)->requiredRole = ua::Role::Observer;  // a question, not a change
    auto update = as.addMethod(
        object, ua::NodeId(1, ua::String("KnowledgeBase.Update")), "Update",
        {argument("Update", "a SPARQL 1.1 update request (all of it, or nothing)")}, {},
        [&knowledge](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                     std::vector<ua::Variant>&) -> ua::StatusCode {
            const auto* u = stringInput(in, 0);
            if (u == nullptr) return ua::status::BadInvalidArgument;
            auto s = knowledge.update(*u->get<ua::String>());
            if (!s) {
                spdlog::warn("kb: Update refused: {}", s.error());
                return statusOf(s.failure());
            }
            return ua::status::Good;
        });
    if (!update) return update.status();
    (*update)->requiredRole = ua::Role::Engineer;  // it changes the plant's models
    // A graph from Turtle, as at start (--process, --load): checked by the reasoner and
    // registered, replacing the graph's earlier content; all of it or nothing.
    auto load = as.addMethod(
        object, ua::NodeId(1, ua::String("KnowledgeBase.Load")), "Load",
        {argument("GraphIri", "the graph to load into (its earlier content is replaced)"),
         argument("Turtle", "the graph's content")},
        {},
        [&knowledge](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                     std::vector<ua::Variant>&) -> ua::StatusCode {
            const auto* graph = stringInput(in, 0);
            const auto* turtle = stringInput(in, 1);
            if (graph == nullptr || turtle == nullptr) return ua::status::BadInvalidArgument;
            const std::string iri = *graph->get<ua::String>();
            if (iri.empty() || iri.rfind("urn:skillcell:kb:", 0) == 0) {
                return ua::status::BadInvalidArgument;  // the KB's own graphs are not for loads
            }
            auto s = knowledge.loadTurtle(iri, *turtle->get<ua::String>());
            if (!s) {
                spdlog::warn("kb: Load of <{}> refused: {}", iri, s.error());
                return statusOf(s.failure());
            }
            spdlog::info("kb: loaded <{}>", iri);
            return ua::status::Good;
        });
    if (!load) return load.status();
    (*load)->requiredRole = ua::Role::Engineer;
    return ua::status::Good;
}

inline constexpr std::chrono::milliseconds kFirstRecordRetry{250};
inline constexpr std::chrono::milliseconds kLongestRecordRetry{8000};

// What the KB runs while its server runs: the HTTP endpoint (its requests are answered on
// the web server's own threads), and discovery-driven loading on a thread of its own.
struct KbComponent {
    KbComponent(kb::KnowledgeBase& knowledge, bool httpWrites, ua::ClientConfig readerConfig)
        : endpoint(knowledge, httpWrites), kb(knowledge), reader(std::move(readerConfig)) {}
    ~KbComponent() {
        watch.reset();    // no restart of Virtuoso, and no recording it asks for, from now on
        stopping = true;  // queued discovery jobs end at once: the KB is going
        reader.cancel();  // and a component being read is dropped
        asio::post(loads, [this] { retryTimer.cancel(); });
        if (detector) detector->unsubscribe(subscription);
        if (web) web->stop();
        workers.join();  // before the KB goes: jobs use it
    }
    KbComponent(const KbComponent&) = delete;
    KbComponent& operator=(const KbComponent&) = delete;

    kb::SparqlEndpoint endpoint;
    kb::KnowledgeBase& kb;
    asio::thread_pool workers{1};
    // Discovery jobs one after another, in the order the events came.
    asio::strand<asio::thread_pool::executor_type> loads{asio::make_strand(workers)};
    kb::ComponentGraphs graphs;  // used on `loads` only
    kb::ComponentReader reader;  // reads on `loads`; cancelled from anywhere
    // Models beyond the compiled-in ones (--models), and the model URIs in the KB or tried.
    std::optional<kb::owl::ModelRepository> models;
    std::set<std::string> modelsLoaded;  // used on `loads` only
    std::unique_ptr<http::WebServer> web;
    std::unique_ptr<kb::engine::VirtuosoWatch> watch;  // our own Virtuoso, restarted if it dies
    std::shared_ptr<skills::SkillDetector> detector;
    std::size_t subscription = 0;
    std::atomic<bool> stopping{false};
    // Components with a recording queued: a burst of skill events (a component with three
    // skills appearing or leaving, a cell starting) becomes one recording.
    std::mutex pendingMutex;
    std::set<std::string> pending;
    // Components whose recording failed (the reasoner killed mid-check, the store
    // restarting) or was made without their parameter values (the component could not be
    // read): recorded again after a pause, which doubles while they keep failing. Without
    // this, a live component's facts stayed missing until its skills next changed, and an MES
    // waiting for them gave up. On `loads` only.
    std::set<std::string> failed;
    asio::steady_timer retryTimer{loads};
    bool retryArmed = false;
    std::chrono::milliseconds retryPause = kFirstRecordRetry;
};

// Loads the model of `ns` and the models it requires from --models, once. `fromSkillType`:
// a skill is typed by it, so a missing model is worth a warning; a namespace the
// component merely uses (its NamespaceArray) may well have none.
void loadModel(KbComponent& c, const std::string& ns, const std::string& componentUri,
               bool fromSkillType) {
    if (!c.modelsLoaded.insert(ns).second) return;  // loaded, or tried once
    std::vector<kb::GraphData> needed;
    if (c.models) {
        for (const auto* o : c.models->withRequirements(ns)) {
            if (c.modelsLoaded.count(o->iri) != 0 && o->iri != ns) continue;
            needed.push_back({o->iri, o->triples});
            c.modelsLoaded.insert(o->iri);
        }
    }
    if (needed.empty()) {
        if (fromSkillType) {
            spdlog::warn("kb: no model for namespace {} of {} (give --models DIR)", ns,
                         componentUri);
        } else {
            spdlog::debug("kb: no model for namespace {} of {}", ns, componentUri);
        }
        return;
    }
    if (auto s = c.kb.load(needed); !s) {
        spdlog::error("kb: cannot load the model {}: {}", ns, s.error());
        return;
    }
    spdlog::info("kb: loaded the model {} for {}", ns, componentUri);
}

// What one component says now, ready to load: its graph, read on `loads`.
struct ComponentRecord {
    std::string uri;
    kb::GraphData graph;
    std::size_t skills = 0;
    std::size_t values = 0;
    bool unread = false;  // live, but its values could not be read: recorded without them
};

ComponentRecord readComponent(KbComponent& c, const std::string& componentUri) {
    // The detector's map may be read from any thread.
    std::vector<skills::SkillInstance> live;
    for (auto& s : c.detector->instances()) {
        if (s.componentUri == componentUri) live.push_back(std::move(s));
    }
    // Its parameter values and its NamespaceArray. One that cannot be read is recorded all
    // the same, without values.
    kb::ComponentReading reading;
    bool unread = false;
    if (!live.empty()) {
        auto r = c.reader.read(live.front().endpointUrl, live);
        if (r) {
            reading = std::move(*r);
        } else if (!c.stopping) {
            unread = true;
            spdlog::warn("kb: cannot read {} at {} ({}): recorded without parameter values for now",
                         componentUri, live.front().endpointUrl, ua::statusName(r.status()));
        }
    }
    ComponentRecord record{componentUri, c.graphs.update(componentUri, live, reading.values),
                           live.size(), reading.values.size(), false};
    record.unread = unread;
    // The models of the component's skill types first, so that its skills are typed by
    // classes the KB knows; then those of every namespace it uses (index 0 is the OPC UA
    // namespace, index 1 the server's own: neither has a model to load).
    for (const auto& ns : c.graphs.typeNamespaces()) loadModel(c, ns, componentUri, true);
    for (std::size_t i = 2; i < reading.namespaceArray.size(); ++i) {
        loadModel(c, reading.namespaceArray[i], componentUri, false);
    }
    return record;
}

void logRecorded(const ComponentRecord& r) {
    spdlog::info("kb: recorded {} ({} skills available, {} with parameter values)", r.uri, r.skills,
                 r.values);
}

void retryFailed(KbComponent& c);

// Records every component with a recording queued. Components that appear together (a cell
// starting, a rack plugged in) are read one by one and then recorded together
// (KnowledgeBase::record: checked against the models, not against each other), in batches
// of what one recording may hold.
void recordPending(KbComponent& c) {
    std::set<std::string> uris;
    {
        const std::lock_guard lock(c.pendingMutex);
        uris.swap(c.pending);  // events from now on queue another recording
    }
    std::vector<ComponentRecord> records;
    for (const auto& uri : uris) {
        if (c.stopping) return;
        records.push_back(readComponent(c, uri));
    }
    for (std::size_t at = 0; at < records.size() && !c.stopping;
         at += kb::KnowledgeBase::kMaxGraphsPerLoad) {
        const std::size_t end = std::min(records.size(), at + kb::KnowledgeBase::kMaxGraphsPerLoad);
        std::vector<kb::GraphData> graphs;
        graphs.reserve(end - at);
        for (std::size_t i = at; i < end; ++i) graphs.push_back(records[i].graph);
        const auto loaded = c.kb.record(graphs);
        std::size_t recorded = 0;
        for (std::size_t i = at; i < end; ++i) {
            if (const auto& s = loaded[i - at]; !s) {
                spdlog::error("kb: cannot record {}: {} (trying again in {} ms)", records[i].uri,
                              s.error(), c.retryPause.count());
                c.failed.insert(records[i].uri);
                continue;
            }
            logRecorded(records[i]);
            ++recorded;
            if (records[i].unread) {
                c.failed.insert(records[i].uri);
            } else {
                c.failed.erase(records[i].uri);
            }
        }
        if (recorded > 1) spdlog::info("kb: {} components recorded", recorded);
    }
    retryFailed(c);
}

// Queues the failed recordings again after the pause (one timer for all of them).
void retryFailed(KbComponent& c) {
    if (c.failed.empty()) {
        c.retryPause = kFirstRecordRetry;
        return;
    }
    if (c.retryArmed || c.stopping) return;
    c.retryArmed = true;
    c.retryTimer.expires_after(c.retryPause);
    c.retryPause = std::min(c.retryPause * 2, kLongestRecordRetry);
    c.retryTimer.async_wait([&c](const std::error_code& ec) {
        c.retryArmed = false;
        if (ec || c.stopping) return;
        bool wasEmpty = false;
        {
            const std::lock_guard lock(c.pendingMutex);
            wasEmpty = c.pending.empty();
            c.pending.insert(c.failed.begin(), c.failed.end());
        }
        if (wasEmpty) recordPending(c);
    });
}

// Queues a recording of each component that `c`'s detector lists as live.
void recordAllLive(KbComponent& c) {
    if (!c.detector || c.stopping) return;
    bool wasEmpty = false;
    {
        const std::lock_guard lock(c.pendingMutex);
        wasEmpty = c.pending.empty();
        for (const auto& s : c.detector->instances()) c.pending.insert(s.componentUri);
        if (c.pending.empty()) return;
    }
    if (wasEmpty) asio::post(c.loads, [&c] { recordPending(c); });
}

ua::Result<ComponentContent> startComponent(const ComponentContext& ctx, const KbOptions& o,
                                            kb::KnowledgeBase& knowledge,
                                            kb::engine::VirtuosoInstance* virtuoso) {
    if (auto s = addKnowledgeBaseNodes(ctx.server.addressSpace(), knowledge); s.isBad()) return s;
    // How the KB reads the components it records: as the KB's client, within bounds (a
    // component that hangs costs a few seconds, and nothing at shutdown).
    ua::ClientConfig readerConfig;
    readerConfig.applicationUri = ctx.applicationUri;
    readerConfig.sessionName = "knowledge base";
    readerConfig.security = ctx.clientSecurity;
    readerConfig.connectTimeout = std::chrono::milliseconds(2000);
    readerConfig.requestTimeout = std::chrono::milliseconds(3000);
    // With users, their roles decide who writes; without, --http-writes does.
    auto c = std::make_shared<KbComponent>(knowledge, ctx.users != nullptr || o.httpWrites,
                                           std::move(readerConfig));
    if (!o.modelsDir.empty()) {
        auto repository = kb::owl::ModelRepository::fromDirectory(o.modelsDir);
        if (!repository) {
            spdlog::critical("kb: --models: {}", repository.error());
            return ua::status::BadInvalidArgument;
        }
        spdlog::info("kb: {} model(s) in {}", repository->uris().size(), o.modelsDir);
        c->models = std::move(*repository);
    }
    // What is loaded already (the compiled-in models, --load) needs no loading.
    if (auto loaded = knowledge.graphs()) {
        c->modelsLoaded.insert(loaded->begin(), loaded->end());
    }
    // The SPARQL endpoint: HTTPS with the KB's certificate, for the cell's users; plain HTTP
    // for anyone only without users (--insecure), and then only on loopback.
    http::WebServerConfig web;
    web.host = o.httpHost;
    web.port = o.httpPort;
    if (ctx.users) {
        web.tls = http::ServerTls{ctx.identity.certificate().der, ctx.identity.privateKey(), true};
        web.gate = std::make_shared<http::UserGate>(ctx.users);
    } else {
        web.gate = std::make_shared<http::UserGate>(
            nullptr, ua::RoleSet{ua::Role::Anonymous, ua::Role::Admin});
    }
    c->web = std::make_unique<http::WebServer>(std::move(web));
    c->endpoint.serveOn(*c->web);
    if (auto s = c->web->start(); !s) {
        spdlog::critical("kb: SPARQL endpoint: {}", s.error());
        return ua::status::BadResourceUnavailable;
    }
    std::cout << "SPARQL " << c->web->url("/sparql") << std::endl;
    spdlog::info("kb: SPARQL endpoint {} ({})", c->web->url("/sparql"),
                 ctx.users ? "HTTPS; Observers query, Engineers update"
                           : (o.httpWrites ? "plain HTTP, anyone may query and update"
                                           : "plain HTTP, anyone may query"));
    auto* component = c.get();
    if (ctx.detector) {
        c->detector = ctx.detector;
        c->subscription = ctx.detector->subscribe([component](const skills::SkillEvent& e) {
            {
                // One job takes every component queued when it starts: a job is posted
                // only when the queue was empty.
                const std::lock_guard lock(component->pendingMutex);
                const bool wasEmpty = component->pending.empty();
                component->pending.insert(e.instance.componentUri);
                if (!wasEmpty) return;
            }
            asio::post(component->loads, [component] { recordPending(*component); });
        });
    }
    if (virtuoso != nullptr) {
        // Restarted after a crash: what discovery reported meanwhile may not be in the store.
        c->watch = std::make_unique<kb::engine::VirtuosoWatch>(
            *virtuoso, [component] { recordAllLive(*component); });
    }
    return ComponentContent(std::move(c));
}

int run(KbOptions& o) {
    // Checked before anything starts: a reasoner that cannot run would fail every recording,
    // again and again, with the KB otherwise up.
    if (!o.noReasoner && process::findInPath(o.koncludeBinary).empty()) {
        spdlog::critical(
            "kb: --konclude {}: no such executable (install Konclude, give its path, or run "
            "with --no-reasoner)",
            o.koncludeBinary);
        return 1;
    }
    std::optional<kb::engine::VirtuosoInstance> virtuoso;
    if (o.sparqlUrl.empty()) {
        kb::engine::VirtuosoConfig config;
        config.dataDir = o.dataDir.empty() ? defaultDataDir() : fs::path(o.dataDir);
        config.httpPort = o.virtuosoHttpPort;
        config.sqlPort = o.virtuosoSqlPort;
        virtuoso.emplace(config);
        if (auto s = virtuoso->start(); !s) {
            spdlog::critical("kb: cannot start Virtuoso: {}", s.error());
            return 1;
        }
    }
    kb::HttpSparqlEndpoint endpoint;
    if (virtuoso) {
        endpoint = kb::HttpSparqlEndpoint::of(*virtuoso);
    } else {
        auto given = kb::HttpSparqlEndpoint::fromUrl(o.sparqlUrl);
        if (!given) {
            spdlog::critical("kb: {}", given.error());
            return 2;
        }
        endpoint = std::move(*given);
        if (endpoint.url.tls) {
            // Another KB over HTTPS: trusted and used as this component is on OPC UA.
            std::string error;
            auto identity = ApplicationIdentity::load(o.process.pkiDir, o.process.applicationUri,
                                                      o.process.applicationName, &error);
            auto security = identity ? componentClientSecurity(*identity, o.process.client,
                                                               o.process.insecure, &error)
                                     : ua::Result<ua::ClientSecurity>(identity.status());
            if (!security) {
                spdlog::critical("kb: --sparql-url {}: {}", o.sparqlUrl, error);
                return 1;
            }
            endpoint.client = sparqlClientOptions(*security);
        }
    }
    const std::string sparqlUrl = endpoint.urlText();
    // Our own Virtuoso takes large graphs as whole documents (Graph Store protocol); a store
    // given by --sparql-url gets them as SPARQL Update requests.
    kb::HttpSparqlStore store(std::move(endpoint));
    std::optional<kb::engine::KoncludeReasoner> reasoner;
    if (!o.noReasoner) {
        kb::engine::KoncludeConfig konclude;
        konclude.binary = o.koncludeBinary;
        reasoner.emplace(std::move(konclude));
    }
    kb::KnowledgeBase knowledge(store, reasoner ? &*reasoner : nullptr);
    // What the KB starts with: the built-in models, the cell's scene (the docks, tools and
    // objects processes refer to) and the files of --load and --process.
    struct StartupLoad {
        std::string what;  // for errors
        std::vector<kb::GraphData> graphs;
    };
    std::vector<StartupLoad> startup;
    auto builtIn = kb::KnowledgeBase::builtInModels(o.demoProcess);
    if (!builtIn) {
        spdlog::critical("kb: cannot load the built-in models: {}", builtIn.error());
        return 1;
    }
    startup.push_back({"the built-in models", std::move(*builtIn)});
    const std::string cellFile =
        !o.cellFile.empty() ? o.cellFile : (o.demoProcess ? SKILLCELL_DEFAULT_CELL : "");
    if (!cellFile.empty()) {
        const auto read = cell::readCellFile(cellFile);
        if (!read.cell) {
            for (const auto& p : read.problems) spdlog::critical("kb: {}", p.describe());
            return 2;
        }
        startup.push_back({"the scene of " + cellFile,
                           {{cell::sceneGraphIri(*read.cell), cell::sceneTriples(*read.cell)}}});
    }
    std::vector<std::string> loads = o.loads;
    for (const auto& file : o.processes) {
        loads.push_back(std::string(kb::kProcessGraphPrefix) +
                        std::filesystem::path(file).stem().string() + "=" + file);
    }
    for (const auto& spec : loads) {
        const auto eq = spec.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
            spdlog::critical("kb: --load {}: expected GRAPH=FILE", spec);
            return 2;
        }
        std::ifstream in(spec.substr(eq + 1), std::ios::binary);
        if (!in) {
            spdlog::critical("kb: --load: cannot read {}", spec.substr(eq + 1));
            return 1;
        }
        std::ostringstream text;
        text << in.rdbuf();
        const std::string graphIri = spec.substr(0, eq);
        auto triples = kb::rdf::readTurtle(text.str(), graphIri);
        if (!triples) {
            spdlog::critical("kb: --load {}: <{}>: {}", spec, graphIri, triples.error());
            return 1;
        }
        startup.push_back({"--load " + spec, {{graphIri, std::move(*triples)}}});
    }
    // As few loads as the reasoner allows; a part refused is named.
    std::vector<std::vector<kb::GraphData>> parts;
    parts.reserve(startup.size());
    for (const auto& part : startup) parts.push_back(part.graphs);
    const auto loaded = knowledge.loadParts(parts);
    for (std::size_t i = 0; i < startup.size(); ++i) {
        if (!loaded[i]) {
            spdlog::critical("kb: {}: {}", startup[i].what, loaded[i].error());
            return 1;
        }
    }
    spdlog::info("kb: store {} ready, reasoner {}", sparqlUrl, reasoner ? "Konclude" : "off");
    o.process.usesDetector = true;
    const int rc = runServerProcess(o.process, [&](const ComponentContext& ctx) {
        return startComponent(ctx, o, knowledge, virtuoso ? &*virtuoso : nullptr);
    });
    if (virtuoso) {
        if (auto s = virtuoso->stop(); !s) spdlog::error("kb: Virtuoso: {}", s.error());
    }
    return rc;
}

}  // namespace

Command addKbCommand(CLI::App& app) {
    auto o = std::make_shared<KbOptions>();
    o->process.port = 4850;
    o->process.applicationUri = std::string(cell::kKbUri);
    o->process.applicationName = "skillcell knowledge base";
    auto* cmd = app.add_subcommand(
        "kb",
        "Run the knowledge base: a supervised Virtuoso (or --sparql-url), the project's "
        "ontologies and NodeSets as OWL checked by Konclude, a SPARQL 1.1 endpoint, Query and "
        "Update on its OPC UA server, and a graph per component that discovery finds.");
    addServerProcessOptions(cmd, o->process);
    addDiscoveryOptions(cmd, o->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--data-dir", o->dataDir,
                    "Virtuoso's data directory, kept across restarts (default: "
                    "~/.local/share/skillcell/kb)");
    cmd->add_option("--sparql-url", o->sparqlUrl,
                    "use this SPARQL 1.1 endpoint (http[s]://HOST:PORT/PATH) instead of "
                    "starting Virtuoso; over https, trusted and used as this component is on "
                    "OPC UA (--client-user)");
    cmd->add_option("--http-host", o->httpHost,
                    "address of the SPARQL endpoint (HTTPS; plain HTTP with --insecure, on "
                    "loopback only)")
        ->capture_default_str();
    cmd->add_option("--http-port", o->httpPort, "port of the SPARQL endpoint (0: any free one)")
        ->capture_default_str();
    cmd->add_option("--virtuoso-http-port", o->virtuosoHttpPort,
                    "Virtuoso's own HTTP port on 127.0.0.1 (0: a free one, kept in the data "
                    "directory)");
    cmd->add_option("--virtuoso-sql-port", o->virtuosoSqlPort,
                    "Virtuoso's SQL port on 127.0.0.1 (0: a free one, kept)");
    cmd->add_flag("--http-writes", o->httpWrites,
                  "with --insecure, where there are no users: let the SPARQL endpoint take "
                  "updates and graph loads from anyone on loopback (with users, the role "
                  "Engineer decides)");
    cmd->add_flag("--demo-process", o->demoProcess,
                  "also load the paper's demo process (models/owl/demo-process.ttl) and, unless "
                  "--cell names another, the scene of the paper's cell (" SKILLCELL_DEFAULT_CELL
                  ")");
    cmd->add_option("--cell", o->cellFile,
                    "load the scene of this cell file (its docks, tools and objects, which "
                    "processes refer to; docs/processes.md)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--konclude", o->koncludeBinary, "the Konclude binary the KB runs")
        ->capture_default_str();
    cmd->add_flag("--no-reasoner", o->noReasoner,
                  "load without checking consistency and infer nothing (not for production)");
    cmd->add_option("--load", o->loads, "load a Turtle file into a graph: GRAPH=FILE (checked)");
    cmd->add_option("--process", o->processes,
                    "load a process (Turtle, docs/processes.md) into the graph " +
                        std::string(kb::kProcessGraphPrefix) +
                        "<file name without .ttl> (checked; "
                        "repeatable)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--models", o->modelsDir,
                    "NodeSet2 files (*.xml) of models beyond skillcell's own: loaded when a "
                    "component with skills of their types appears")
        ->check(CLI::ExistingDirectory);
    return {cmd, [o] { return run(*o); }};
}

}  // namespace skillcell::apps
