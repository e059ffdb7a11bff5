// `skillcell dashboard`: the cell's live view in a browser (docs/dashboard.md).
//
// A component like any other: discovery finds it, it has its own certificate and acts as
// its --client-user. It detects the cell's skills as every composite does, watches each
// skill's transition events through a session of its own, and serves one page over HTTPS,
// behind a login with the cell's users, that the changes are pushed to as server-sent
// events. Prints "DASHBOARD <url>" once the page is served, then the server's "READY".
#include <spdlog/spdlog.h>

#include <array>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <charconv>
#include <filesystem>
#include <future>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "cell/component_uris.hpp"
#include "cell/paper_figures.hpp"
#include "commands.hpp"
#include "dashboard/cell_view.hpp"
#include "dashboard/event_hub.hpp"
#include "dashboard/periodic_task.hpp"
#include "dashboard/scene_watcher.hpp"
#include "dashboard/skill_state_follower.hpp"
#include "dashboard/web_assets.hpp"
#include "http/web_server.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "mes/journal.hpp"
#include "mes/mes_component.hpp"
#include "mes/order_nodes.hpp"
#include "mes/process_description.hpp"
#include "server_process.hpp"
#include "skills/skill_connection.hpp"
#include "sparql_client_options.hpp"

namespace skillcell::apps {

// At namespace scope, as in the other commands: in a unity batch, an alias in an anonymous
// namespace would shadow theirs.
using Json = nlohmann::ordered_json;

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

struct DashboardOptions {
    ServerProcessOptions process;
    std::string httpHost = "127.0.0.1";
    std::uint16_t httpPort = 8443;
    std::string worldUrl;  // the world model, for the scene's picture; empty: none
    std::string journal;   // the MES's journal, for the runs; empty: none
    std::string kbUrl;     // the knowledge base's SPARQL endpoint, for its processes
};

/// Reads the MES's last runs from its journal (SQLite, which the MES writes in WAL mode, so
/// a reader beside it is safe) whenever the MES reports progress (wake()), and every 5 s
/// besides, and gives the view what changed.
class JournalReader {
public:
    static constexpr std::int64_t kRuns = 5;

    JournalReader(fs::path path, dashboard::CellView& view)
        : path_(std::move(path)), view_(view), task_([this] { return tick(); }) {}

    /// The MES reported progress: read now.
    void wake() { task_.wake(); }

private:
    std::chrono::milliseconds tick() {
        if (!journal_) {
            std::error_code ec;
            if (!fs::exists(path_, ec)) return 1000ms;  // the MES has not written one yet
            auto opened = mes::Journal::open(path_.string());
            if (!opened) {
                spdlog::warn("dashboard: the journal: {}", opened.error());
                return 5000ms;
            }
            journal_ = std::move(*opened);
        }
        auto runs = journal_->recentRuns(kRuns);
        if (!runs) {
            spdlog::warn("dashboard: the journal: {}", runs.error());
            journal_.reset();
            return 2000ms;
        }
        std::vector<dashboard::RunView> out;
        for (const auto& r : *runs) {
            dashboard::RunView v{
                r.id, r.processIri, mes::toString(r.state), r.reason, r.startedMs, r.endedMs, {}};
            v.priority = r.priority;
            for (const auto& st : r.steps) {
                v.steps.push_back({st.index, st.attempt, mes::toString(st.state),
                                   mes::shortName(st.skillTypeIri), st.componentUri, st.startedMs,
                                   st.endedMs, st.reason, st.note});
            }
            out.push_back(std::move(v));
        }
        view_.runs(out);
        return 5000ms;
    }

    fs::path path_;
    dashboard::CellView& view_;
    std::unique_ptr<mes::Journal> journal_;  // on the task's thread only
    dashboard::PeriodicTask task_;           // last
};

/// Reads the processes the knowledge base holds every 4 s (its SPARQL endpoint over HTTPS, as
/// this component's client user; blocking calls, so on a PeriodicTask's thread) and gives the
/// view what changed. A process that cannot be read is listed with the reason.
class ProcessReader {
public:
    ProcessReader(kb::HttpSparqlEndpoint endpoint, dashboard::CellView& view)
        : store_(std::move(endpoint)), view_(view), task_([this] { return tick(); }) {}

private:
    std::chrono::milliseconds tick() {
        auto iris = mes::processIris(store_);
        if (!iris) {
            if (!complained_) {
                spdlog::warn("dashboard: the knowledge base: {} (trying again)", iris.error());
            }
            complained_ = true;
            return 2000ms;
        }
        complained_ = false;
        std::vector<dashboard::ProcessView> out;
        out.reserve(iris->size());
        for (const auto& iri : *iris) {
            dashboard::ProcessView v{iri, {}, {}};
            if (auto p = mes::readProcess(store_, iri)) {
                for (const auto& step : p->steps)
                    v.steps.push_back(mes::shortName(step.skillTypeIri));
            } else {
                v.problem = p.error();
            }
            out.push_back(std::move(v));
        }
        view_.processes(out);
        return 4000ms;  // not the 5 s after which the KB's web server closes an idle connection
    }

    kb::HttpSparqlStore store_;  // on the task's thread only
    dashboard::CellView& view_;
    bool complained_ = false;
    dashboard::PeriodicTask task_;  // last
};

/// What the component keeps alive: the view, the web server and one session per component.
/// Members go in reverse: the sessions first, the page's streams before the view.
struct DashboardContent {
    explicit DashboardContent(asio::io_context& context) : io(context) {}
    ~DashboardContent() {
        if (scene) scene->stop();
        journal.reset();
        processes.reset();
        if (detector) {
            detector->unsubscribe(subscription);
            detector->unsubscribe(componentSubscription);
        }
        hub.close();  // every open stream ends, so that the web server can stop
        if (web) web->stop();
    }
    DashboardContent(const DashboardContent&) = delete;
    DashboardContent& operator=(const DashboardContent&) = delete;

    asio::io_context& io;
    dashboard::EventHub hub;
    dashboard::CellView view{hub, [](const std::string& uri) {
                                 const auto* paper = cell::paperDetection(uri);
                                 return paper != nullptr ? paper->ms : 0.0;
                             }};
    std::shared_ptr<dashboard::SceneWatcher> scene;
    std::unique_ptr<JournalReader> journal;    // before the view goes
    std::unique_ptr<ProcessReader> processes;  // before the view goes
    std::unique_ptr<http::WebServer> web;
    std::shared_ptr<skills::SkillDetector> detector;
    std::size_t subscription = 0;
    std::size_t componentSubscription = 0;
    ua::ClientConfig client;
    // On the io thread only: the skills as detected, by CellView::keyOf, and their states.
    std::map<std::string, skills::SkillInstance> instances;
    std::shared_ptr<dashboard::SkillStateFollower> states;
};

/// What a Start or Halt from the page came to.
struct ActionResult {
    ua::StatusCode status = ua::status::Good;
    std::string detail;
};

// Starts, halts or resets one skill as the page's user: a session of its own, the parameters the
// page gave (as strings), the method. On the io thread.
asio::awaitable<ActionResult> act(std::weak_ptr<DashboardContent> weak, std::string key,
                                  skills::SkillMethod method,
                                  std::map<std::string, std::string> parameters,
                                  ua::ClientConfig config) {
    skills::SkillInstance skill;
    {
        auto c = weak.lock();
        if (!c) co_return ActionResult{ua::status::BadShutdown, "the dashboard is stopping"};
        const auto it = c->instances.find(key);
        if (it == c->instances.end()) {
            co_return ActionResult{ua::status::BadNodeIdUnknown, "no such skill (gone?)"};
        }
        skill = it->second;
    }
    const auto executor = co_await asio::this_coro::executor;
    ActionResult result;
    auto opened = co_await skills::SkillConnection::open(executor, skill, config, &result.detail);
    if (!opened) co_return ActionResult{opened.status(), result.detail};
    const std::unique_ptr<skills::SkillConnection> connection = std::move(*opened);
    for (const auto& [name, value] : parameters) {
        ua::Variant v{ua::String(value)};
        result.status = co_await connection->skill().setParameter(name, std::move(v));
        if (result.status.isBad()) {
            result.detail = "writing " + name;
            break;
        }
    }
    if (result.status.isGood()) {
        result.status = co_await connection->skill().call(method);
        result.detail = std::string(skills::name(method));
    }
    co_await connection->close();
    co_return result;
}

// Cancels an order as the page's user: a session of its own with the MES (the component that
// offers ExecuteProcess), Objects/Orders/CancelOrder. On the io thread.
asio::awaitable<ActionResult> cancelOrder(std::weak_ptr<DashboardContent> weak, std::int64_t order,
                                          ua::ClientConfig config) {
    std::optional<skills::SkillInstance> mes;
    {
        auto c = weak.lock();
        if (!c) co_return ActionResult{ua::status::BadShutdown, "the dashboard is stopping"};
        for (const auto& [key, instance] : c->instances) {
            if (instance.type().browseName == "ExecuteProcessSkillType") mes = instance;
        }
    }
    if (!mes) co_return ActionResult{ua::status::BadNodeIdUnknown, "no MES in the cell"};
    const auto executor = co_await asio::this_coro::executor;
    ActionResult result;
    auto opened = co_await skills::SkillConnection::open(executor, *mes, config, &result.detail);
    if (!opened) co_return ActionResult{opened.status(), result.detail};
    const std::unique_ptr<skills::SkillConnection> connection = std::move(*opened);
    std::vector<ua::Variant> in{ua::Variant(order)};  // named: GCC 12 and co_await temporaries
    const ua::NodeId object = mes::ordersObject();
    const ua::NodeId method = mes::orderMethod("CancelOrder");
    auto out = co_await connection->client().call(object, method, std::move(in));
    result.status = out ? ua::StatusCode(ua::status::Good) : out.status();
    result.detail = "cancel order " + std::to_string(order);
    co_await connection->close();
    co_return result;
}

// Wakes the journal's reader whenever the MES's Objects/ProcessExecution/Progress changes, by
// a subscription in the session that follows the MES's skills (it ends with that session).
// On the io thread.
asio::awaitable<void> followProgress(std::weak_ptr<DashboardContent> weak,
                                     std::shared_ptr<skills::SkillConnection> connection) {
    // Named before co_await: GCC 12 destroys closure temporaries in a co_await twice.
    const ua::SubscriptionSettings settings(50, 600, 20);
    auto subscription = co_await connection->client().createSubscription(settings);
    if (!subscription) {
        spdlog::warn("dashboard: cannot follow the MES's progress ({}): runs every 5 s",
                     ua::statusName(subscription.status()));
        co_return;
    }
    ua::Subscription::DataChangeCallback onProgress = [weak](const ua::DataValue&) {
        if (auto c = weak.lock(); c && c->journal) c->journal->wake();
    };
    const std::optional<ua::DataChangeFilter> noFilter;
    auto item = co_await (*subscription)
                    ->monitorDataChange(mes::progressVariable("Progress"), ua::AttributeId::Value,
                                        0, 10, noFilter, std::move(onProgress));
    if (!item) {
        spdlog::warn("dashboard: the MES offers no Progress to follow ({}): runs every 5 s",
                     ua::statusName(item.status()));
        co_return;
    }
    spdlog::info("dashboard: the runs follow the MES's progress at {}", connection->endpointUrl());
}

void onSkillEvent(const std::shared_ptr<DashboardContent>& c, const skills::SkillEvent& e) {
    const std::string key = dashboard::CellView::keyOf(e.instance);
    if (e.kind == skills::SkillEvent::Kind::Added) {
        c->instances[key] = e.instance;
        c->view.skillAdded(e.instance);
        c->states->add(e.instance);
        return;
    }
    c->view.skillRemoved(e.instance, e.reason);
    c->instances.erase(key);
    c->states->remove(e.instance);
}

// Follows every detected skill's state into the view, over one session per component; the
// MES's session also carries the subscription to its progress. On the io thread.
std::shared_ptr<dashboard::SkillStateFollower> followStates(
    const std::shared_ptr<DashboardContent>& c) {
    std::weak_ptr<DashboardContent> weak = c;
    dashboard::SkillStateFollower::Listeners listeners;
    listeners.state = [weak](const std::string& key, std::optional<skills::SkillState> state,
                             const skills::SkillTransitionRecord* transition) {
        if (auto content = weak.lock()) content->view.skillState(key, state, transition);
    };
    listeners.followed = [weak](const skills::SkillInstance& skill,
                                const std::shared_ptr<skills::SkillConnection>& connection) {
        auto content = weak.lock();
        // The MES's Progress changes with every step: the journal has news then.
        if (content && content->journal && skill.type().browseName == "ExecuteProcessSkillType") {
            asio::co_spawn(content->io, followProgress(weak, connection), asio::detached);
        }
    };
    listeners.failed = [](const skills::SkillInstance& skill, const std::string& why) {
        spdlog::warn("dashboard: cannot follow {} ({}): its state stays unknown",
                     dashboard::CellView::keyOf(skill), why);
    };
    return dashboard::SkillStateFollower::create(c->io.get_executor(), c->client,
                                                 std::move(listeners));
}

void serveAsset(httplib::Response& res, std::string_view name, const char* type) {
    const auto body = dashboard::webAsset(name);
    res.set_content(std::string(body), type);
    res.set_header("Cache-Control", "no-cache");
    // The page loads nothing from elsewhere, and nothing may frame it.
    res.set_header("Content-Security-Policy", "default-src 'self'; frame-ancestors 'none'");
    res.set_header("X-Content-Type-Options", "nosniff");
}

Json me(const ua::UserIdentity& user) {
    Json roles = Json::array();
    for (const auto r : user.roles.roles()) roles.push_back(std::string(ua::roleName(r)));
    return {{"user", user.name}, {"roles", std::move(roles)}};
}

// The answer to an action of the page, with the HTTP status given, or the one the OPC UA
// status decides (Good 200, a refusal of the user's role 403, no answer 504, others 409).
void reply(httplib::Response& res, int http, const ua::StatusCode& code,
           const std::string& detail) {
    res.status = http;
    res.set_content(Json{{"status", std::string(ua::statusName(code))}, {"detail", detail}}.dump(
                        -1, ' ', false, Json::error_handler_t::replace),
                    "application/json");
}

void reply(httplib::Response& res, const ActionResult& r) {
    int http = 409;
    if (r.status.isGood()) http = 200;
    if (r.status == ua::status::BadUserAccessDenied) http = 403;
    if (r.status == ua::status::BadTimeout) http = 504;
    reply(res, http, r.status, r.detail);
}

// The client configuration of a session as the page's logged-in user: each action is an
// OPC UA session as that user, so that the component's own role check applies. It needs the
// password of the page's login; none without one.
std::optional<ua::ClientConfig> asUser(const DashboardContent& c, http::UserGate& gate,
                                       const httplib::Request& req, const ua::UserIdentity& user) {
    const auto secret = gate.sessionCredentials(req.get_header_value("Cookie"));
    if (!secret) return std::nullopt;
    ua::ClientConfig config = c.client;
    config.sessionName = "skillcell dashboard, for " + user.name;
    config.security.user = ua::UserCredentials{};
    config.security.user.kind = ua::UserCredentials::Kind::UserName;
    config.security.user.userName = secret->first;
    config.security.user.password = secret->second;
    return config;
}

// Runs `action` on the io thread and waits for it (at most 20 s) on the web server's.
ActionResult await(asio::io_context& io, asio::awaitable<ActionResult> action) {
    auto done = std::make_shared<std::promise<ActionResult>>();
    auto outcome = done->get_future();
    asio::co_spawn(io, std::move(action), [done](const std::exception_ptr& e, ActionResult r) {
        if (e) r = ActionResult{ua::status::BadInternalError, "failed"};
        done->set_value(std::move(r));
    });
    if (outcome.wait_for(20s) != std::future_status::ready) {
        return ActionResult{ua::status::BadTimeout, "no answer within 20 s"};
    }
    return outcome.get();
}

constexpr const char* kLogInFirst = "actions are made as the logged-in user: log in on the page";

// POST /api/skill: key, action (start | halt | reset), and param.NAME=VALUE for parameters
// (written before a Start). The page starts a process with the MES's ExecuteProcess skill and
// its ProcessIri.
void skillAction(const std::shared_ptr<DashboardContent>& c, http::UserGate& gate,
                 const httplib::Request& req, httplib::Response& res,
                 const ua::UserIdentity& user) {
    const std::string action = req.get_param_value("action");
    const std::map<std::string, skills::SkillMethod> methods{{"start", skills::SkillMethod::Start},
                                                             {"halt", skills::SkillMethod::Halt},
                                                             {"reset", skills::SkillMethod::Reset}};
    const auto method = methods.find(action);
    if (method == methods.end()) {
        return reply(res, 400, ua::status::BadInvalidArgument, "action is start, halt or reset");
    }
    auto config = asUser(*c, gate, req, user);
    if (!config) return reply(res, 403, ua::status::BadUserAccessDenied, kLogInFirst);
    std::map<std::string, std::string> parameters;
    for (const auto& [name, value] : req.params) {
        if (method->second == skills::SkillMethod::Start && name.rfind("param.", 0) == 0 &&
            !value.empty()) {
            parameters[name.substr(6)] = value;
        }
    }
    const ActionResult r = await(c->io, act(c, req.get_param_value("key"), method->second,
                                            std::move(parameters), std::move(*config)));
    spdlog::info("dashboard: {} by {} on {}: {} ({})", action, user.name,
                 req.get_param_value("key"), ua::statusName(r.status), r.detail);
    reply(res, r);
}

// POST /api/order: order, action (cancel). As /api/skill: an OPC UA session as the
// logged-in user, whose role the MES checks (Operator).
void orderAction(const std::shared_ptr<DashboardContent>& c, http::UserGate& gate,
                 const httplib::Request& req, httplib::Response& res,
                 const ua::UserIdentity& user) {
    if (req.get_param_value("action") != "cancel") {
        return reply(res, 400, ua::status::BadInvalidArgument, "action is cancel");
    }
    std::int64_t order = 0;
    const std::string text = req.get_param_value("order");
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), order);
    if (parsed.ec != std::errc{} || parsed.ptr != text.data() + text.size() || order <= 0) {
        return reply(res, 400, ua::status::BadInvalidArgument, "order is an order's id");
    }
    auto config = asUser(*c, gate, req, user);
    if (!config) return reply(res, 403, ua::status::BadUserAccessDenied, kLogInFirst);
    const ActionResult r = await(c->io, cancelOrder(c, order, std::move(*config)));
    spdlog::info("dashboard: cancel of order {} by {}: {}", order, user.name,
                 ua::statusName(r.status));
    reply(res, r);
}

/// Open pages (event streams) at once, and the web server's threads: a stream holds one.
constexpr std::size_t kMaxPages = 24;
constexpr std::size_t kWebThreads = kMaxPages + 8;

void addRoutes(http::WebServer& web, const std::shared_ptr<DashboardContent>& content, bool tls) {
    web.publicGet("/", [](const httplib::Request&, httplib::Response& res) {
        serveAsset(res, "index.html", "text/html; charset=utf-8");
    });
    web.publicGet("/app.js", [](const httplib::Request&, httplib::Response& res) {
        serveAsset(res, "app.js", "text/javascript; charset=utf-8");
    });
    web.publicGet("/style.css", [](const httplib::Request&, httplib::Response& res) {
        serveAsset(res, "style.css", "text/css; charset=utf-8");
    });
    auto* gate = &web.gate();
    std::weak_ptr<DashboardContent> weak = content;
    web.publicPost("/login", [gate, tls](const httplib::Request& req, httplib::Response& res) {
        std::chrono::seconds retryAfter{0};
        auto session =
            gate->login(req.get_param_value("user"), req.get_param_value("password"), &retryAfter);
        if (!session && session.status() == ua::status::BadTooManyOperations) {
            spdlog::warn("dashboard: logins as '{}' throttled (too many wrong passwords), from {}",
                         req.get_param_value("user"), req.remote_addr);
            res.status = 429;
            res.set_header("Retry-After", std::to_string(retryAfter.count()));
            res.set_content(Json{{"error", "too many wrong passwords: try again later"},
                                 {"retryAfter", retryAfter.count()}}
                                .dump(),
                            "application/json");
            return;
        }
        if (!session) {
            spdlog::info("dashboard: a login as '{}' from {} refused", req.get_param_value("user"),
                         req.remote_addr);
            res.status = 401;
            res.set_content(R"({"error":"wrong user or password"})", "application/json");
            return;
        }
        spdlog::info("dashboard: {} logged in from {}", session->first.name, req.remote_addr);
        res.set_header("Set-Cookie", std::string(http::UserGate::kSessionCookie) + "=" +
                                         session->second + "; Path=/; HttpOnly; SameSite=Strict" +
                                         (tls ? "; Secure" : ""));
        res.set_content(me(session->first).dump(), "application/json");
    });
    web.post("/logout", [gate](const httplib::Request& req, httplib::Response& res,
                               const ua::UserIdentity& user) {
        gate->logout(req.get_header_value("Cookie"));
        spdlog::info("dashboard: {} logged out", user.name);
        res.set_header("Set-Cookie", std::string(http::UserGate::kSessionCookie) +
                                         "=; Path=/; Max-Age=0; HttpOnly; SameSite=Strict");
        res.set_content("{}", "application/json");
    });
    web.get("/api/me",
            [](const httplib::Request&, httplib::Response& res, const ua::UserIdentity& user) {
                res.set_content(me(user).dump(), "application/json");
            });
    web.post("/api/skill", [weak, gate](const httplib::Request& req, httplib::Response& res,
                                        const ua::UserIdentity& user) {
        if (auto c = weak.lock()) skillAction(c, *gate, req, res, user);
    });
    web.post("/api/order", [weak, gate](const httplib::Request& req, httplib::Response& res,
                                        const ua::UserIdentity& user) {
        if (auto c = weak.lock()) orderAction(c, *gate, req, res, user);
    });
    // The live view: a snapshot, then every change, as server-sent events. A comment line
    // every 15 s keeps proxies from closing a quiet stream and notices a closed one.
    web.get("/events", [weak](const httplib::Request&, httplib::Response& res,
                              const ua::UserIdentity&) {
        auto c = weak.lock();
        if (!c) {
            res.status = 503;
            return;
        }
        // Each open page holds a thread of the web server: beyond kMaxPages, a new one is
        // turned away so that actions and logins always find a thread.
        if (c->hub.listeners() >= kMaxPages) {
            spdlog::warn("dashboard: {} pages are open already; one more refused (503)", kMaxPages);
            res.status = 503;
            res.set_header("Retry-After", "10");
            res.set_content("too many open pages of this dashboard: close one\n", "text/plain");
            return;
        }
        auto [snapshot, listener] = c->view.open();
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "text/event-stream", [first = "data: " + snapshot + "\n\n", listener = listener](
                                     std::size_t, httplib::DataSink& sink) mutable {
                std::string chunk;
                if (!first.empty()) {
                    chunk.swap(first);
                } else {
                    auto event = listener->next(15s);
                    if (listener->closed()) {
                        sink.done();
                        return true;
                    }
                    chunk = event ? "data: " + *event + "\n\n" : ": keep-alive\n\n";
                }
                return sink.write(chunk.data(), chunk.size());
            });
    });
}

int run(DashboardOptions& o) {
    // A wrong --kb is refused before anything starts (exit 2), not after the page is up.
    std::optional<kb::HttpSparqlEndpoint> kbEndpoint;
    if (!o.kbUrl.empty()) {
        auto endpoint = kb::HttpSparqlEndpoint::fromUrl(o.kbUrl);
        if (!endpoint) {
            spdlog::critical("dashboard: --kb {}: {}", o.kbUrl, endpoint.error());
            return 2;
        }
        kbEndpoint = std::move(*endpoint);
    }
    o.process.usesDetector = true;
    return runServerProcess(
        o.process, [&o, kbEndpoint](const ComponentContext& ctx) -> ua::Result<ComponentContent> {
            auto c = std::make_shared<DashboardContent>(ctx.io);
            c->client.applicationUri = ctx.applicationUri;
            c->client.sessionName = "skillcell dashboard";
            c->client.security = ctx.clientSecurity;
            c->client.connectTimeout = 2000ms;
            c->client.requestTimeout = 3000ms;
            http::WebServerConfig web;
            web.host = o.httpHost;
            web.port = o.httpPort;
            web.challenge = R"(Session realm="skillcell dashboard")";  // the page's form logs in
            web.threads = kWebThreads;
            if (ctx.users) {
                web.tls = http::ServerTls{ctx.identity.certificate().der, ctx.identity.privateKey(),
                                          false};
                web.gate = std::make_shared<http::UserGate>(ctx.users);
            } else {
                web.gate = std::make_shared<http::UserGate>(
                    nullptr, ua::RoleSet{ua::Role::Anonymous, ua::Role::Observer});
            }
            const bool tls = web.tls.has_value();
            c->web = std::make_unique<http::WebServer>(std::move(web));
            addRoutes(*c->web, c, tls);
            if (auto s = c->web->start(); !s) {
                spdlog::critical("dashboard: {}", s.error());
                return ua::status::BadResourceUnavailable;
            }
            if (!o.worldUrl.empty()) {
                std::weak_ptr<DashboardContent> weak = c;
                c->scene =
                    dashboard::SceneWatcher::start(ctx.io.get_executor(), o.worldUrl, c->client,
                                                   [weak](const dashboard::SceneView& scene) {
                                                       if (auto content = weak.lock())
                                                           content->view.scene(scene);
                                                   });
            }
            if (!o.journal.empty()) {
                c->journal = std::make_unique<JournalReader>(o.journal, c->view);
            }
            if (kbEndpoint) {
                auto endpoint = *kbEndpoint;
                if (endpoint.url.tls) endpoint.client = sparqlClientOptions(ctx.clientSecurity);
                c->processes = std::make_unique<ProcessReader>(std::move(endpoint), c->view);
            }
            std::cout << "DASHBOARD " << c->web->url("/") << std::endl;
            spdlog::info("dashboard: {} ({})", c->web->url("/"),
                         tls ? "HTTPS, the cell's users log in" : "plain HTTP, no login");
            if (ctx.detector) {
                c->detector = ctx.detector;
                c->states = followStates(c);
                std::weak_ptr<DashboardContent> weak = c;
                // Detector events come on the io thread, where the sessions live too.
                c->subscription = ctx.detector->subscribe([weak](const skills::SkillEvent& e) {
                    if (auto content = weak.lock()) onSkillEvent(content, e);
                });
                // Components without skills too: the LDS, the KB, the world model.
                c->componentSubscription =
                    ctx.detector->subscribeComponents([weak](const skills::ComponentEvent& e) {
                        if (auto content = weak.lock()) content->view.componentStatus(e);
                    });
            }
            return ComponentContent(c);
        });
}

}  // namespace

Command addDashboardCommand(CLI::App& app) {
    auto o = std::make_shared<DashboardOptions>();
    o->process.port = 4860;
    o->process.applicationUri = std::string(cell::kDashboardUri);
    o->process.applicationName = "skillcell dashboard";
    auto* cmd = app.add_subcommand(
        "dashboard",
        "Serve the cell's live view to browsers: the components discovery finds and every "
        "skill with its state and last transitions, pushed as they change. HTTPS with this "
        "component's certificate, behind a login with the cell's users (--users); plain HTTP "
        "on loopback only with --insecure. Prints 'DASHBOARD <url>', then 'READY <url>'.");
    addServerProcessOptions(cmd, o->process);
    addDiscoveryOptions(cmd, o->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--http-host", o->httpHost,
                    "address of the page (HTTPS; plain HTTP with --insecure, loopback only)")
        ->capture_default_str();
    cmd->add_option("--http-port", o->httpPort, "port of the page (0: any free one)")
        ->capture_default_str();
    cmd->add_option("--journal", o->journal,
                    "the MES's journal (SQLite): the page shows its last runs, step by step, as "
                    "a timeline, and the one in progress");
    cmd->add_option("--kb", o->kbUrl,
                    "the knowledge base's SPARQL endpoint: the page lists its processes, and an "
                    "Operator starts one with the MES's ExecuteProcess skill");
    cmd->add_option("--world", o->worldUrl,
                    "the world model's endpoint: the page draws its scene (docks, tools, boxes, "
                    "the flange) from above");
    return {cmd, [o] { return run(*o); }};
}

}  // namespace skillcell::apps
