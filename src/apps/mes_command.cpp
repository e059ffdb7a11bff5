// `skillcell mes`: the semantic MES as a component of the cell (docs/mes.md), and
// `skillcell run`: hand it a process and follow it.
//
// The MES serves the ExecuteProcess skill (ProcessIri) and Objects/ProcessExecution (what it
// is doing). For a run it reads the process from the knowledge base's SPARQL endpoint (--kb),
// picks the skills from what discovery finds, runs them, and records every step in its SQLite
// journal (--journal), from which a restarted MES resumes an interrupted run.
#include <spdlog/spdlog.h>

#include <asio/detached.hpp>
#include <asio/io_context.hpp>
#include <asio/thread_pool.hpp>
#include <filesystem>
#include <iostream>

#include "cell/component_uris.hpp"
#include "client_security_options.hpp"
#include "commands.hpp"
#include "devices/common/blocking_call.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "mes/mes_component.hpp"
#include "mes/process_check.hpp"
#include "server_process.hpp"
#include "skills/skill_client.hpp"
#include "sparql_client_options.hpp"

namespace skillcell::apps {
namespace {

namespace fs = std::filesystem;

struct MesOptions {
    ServerProcessOptions process;
    std::string kbUrl = "https://localhost:8870/sparql";
    std::string journal;
    int skillWaitMs = 10'000;
    int stepTimeoutMs = 300'000;
};

fs::path defaultJournal() {
    const char* home = std::getenv("HOME");
    return fs::path(home != nullptr ? home : "/tmp") / ".local/share/skillcell/mes/journal.sqlite";
}

/// What `skillcell mes` keeps alive, destroyed in reverse: the component (it halts a run),
/// the executor, the journal and the thread the KB's blocking HTTP requests run on.
struct MesContent {
    std::unique_ptr<asio::thread_pool> kbThread;
    std::unique_ptr<kb::HttpSparqlStore> store;
    std::unique_ptr<mes::Journal> journal;
    std::shared_ptr<mes::ProcessExecutor> executor;
    std::unique_ptr<mes::MesComponent> component;
    ~MesContent() {
        component.reset();
        executor.reset();
        if (kbThread) kbThread->join();
    }
};

int runMes(MesOptions& o) {
    auto endpoint = kb::HttpSparqlEndpoint::fromUrl(o.kbUrl);
    if (!endpoint) {
        spdlog::critical("mes: --kb {}: {}", o.kbUrl, endpoint.error());
        return 2;
    }
    const fs::path journalPath = o.journal.empty() ? defaultJournal() : fs::path(o.journal);
    std::error_code ec;
    if (journalPath.has_parent_path()) fs::create_directories(journalPath.parent_path(), ec);
    auto journal = mes::Journal::open(journalPath.string());
    if (!journal) {
        spdlog::critical("mes: {}", journal.error());
        return 1;
    }
    if (auto open = (*journal)->unfinishedRuns(); open && !open->empty()) {
        for (const auto& r : *open) {
            spdlog::warn(
                "mes: run {} of {} is {}{}: ExecuteProcess with this ProcessIri resumes it", r.id,
                r.processIri, mes::toString(r.state),
                r.reason.empty() ? "" : " (" + r.reason + ")");
        }
    }
    spdlog::info("mes: journal {}, knowledge base {}", journalPath.string(), endpoint->urlText());
    o.process.usesDetector = true;
    auto journalHolder = std::make_shared<std::unique_ptr<mes::Journal>>(std::move(*journal));
    return runServerProcess(
        o.process,
        [&o, journalHolder,
         endpoint = *endpoint](const ComponentContext& c) -> ua::Result<ComponentContent> {
            auto content = std::make_shared<MesContent>();
            content->kbThread = std::make_unique<asio::thread_pool>(1);
            // The KB's HTTPS is trusted, and used as this user, as OPC UA servers are.
            auto kbEndpoint = endpoint;
            kbEndpoint.client = sparqlClientOptions(c.clientSecurity);
            content->store = std::make_unique<kb::HttpSparqlStore>(std::move(kbEndpoint));
            content->journal = std::move(*journalHolder);
            mes::ExecutorOptions options;
            options.skillWait = std::chrono::milliseconds(o.skillWaitMs);
            options.stepTimeout = std::chrono::milliseconds(o.stepTimeoutMs);
            options.client.applicationUri = c.applicationUri;
            options.client.sessionName = "skillcell mes";
            options.client.security = c.clientSecurity;
            // The KB's HTTP client blocks: its requests run on a thread of their own, and
            // the answer comes back to the server's executor.
            auto* pool = content->kbThread.get();
            auto* store = content->store.get();
            mes::ProcessReader reader =
                [pool,
                 store](std::string iri) -> asio::awaitable<kb::Expected<mes::ProcessDescription>> {
                // A named lambda: GCC 12 destroys temporaries of a co_await expression twice.
                auto read = [store, iri] { return mes::readCheckedProcess(*store, iri); };
                co_return co_await devices::blockingCall(*pool, std::move(read));
            };
            mes::FactReader facts = [pool, store](std::vector<std::string> properties)
                -> asio::awaitable<kb::Expected<mes::SkillFacts>> {
                auto read = [store, properties] { return mes::readFacts(*store, properties); };
                co_return co_await devices::blockingCall(*pool, std::move(read));
            };
            content->executor = mes::ProcessExecutor::create(
                c.detector, *content->journal,
                mes::KnowledgeReaders{std::move(reader), std::move(facts)}, options);
            std::string error;
            auto component = mes::MesComponent::create(c.server, content->executor, &error);
            if (!component) {
                spdlog::critical("mes: {}", error);
                return component.status();
            }
            content->component = std::move(*component);
            return ComponentContent(content);
        });
}

// --- skillcell run ------------------------------------------------------------------------

struct RunOptions {
    std::string processIri;
    std::string mesUrl = "opc.tcp://localhost:4851";
    double timeoutSeconds = 3600;
    ClientSecurityOptions security;
};

/// Prints a progress line unless it is the one shown last.
void show(std::string& shown, const std::string& line) {
    if (line.empty() || line == shown) return;
    shown = line;
    std::cout << "PROGRESS " << line << std::endl;
}

asio::awaitable<int> runProcess(ua::Client& client, const RunOptions& o) {
    auto config = commandClientConfig(o.security, "skillcell run");
    if (!config) co_return 2;
    const std::string url = o.mesUrl;
    if (const auto s = co_await client.connect(url, std::move(*config)); s.isBad()) {
        std::cerr << "cannot connect to the MES at " << o.mesUrl << ": " << explainConnectFailure(s)
                  << "\n";
        co_return 2;
    }
    // A process runs for minutes: a keep-alive of 2 s, so that a busy MES is not taken for
    // a lost one.
    skills::SkillClientOptions followOptions;
    followOptions.publishingIntervalMs = 50;
    followOptions.maxKeepAliveCount = 40;
    const ua::NodeId executeProcess(1, ua::String("Skills/ExecuteProcess"));
    auto attached = co_await skills::SkillClient::attach(client, executeProcess, followOptions);
    if (!attached) {
        std::cerr << o.mesUrl
                  << " offers no ExecuteProcess skill: " << ua::statusName(attached.status())
                  << "\n";
        (void)co_await client.disconnect();
        co_return 2;
    }
    auto skill = *attached;
    // Progress: the MES's Progress variable, one line per change (queued, so that quick
    // changes between two publishes are all shown).
    auto shown = std::make_shared<std::string>();
    // What Progress says now is the previous run's end: not this run's progress.
    if (auto before = co_await client.readValue(mes::progressVariable("Progress"))) {
        if (const auto* line = before->get<ua::String>()) *shown = *line;
    }
    ua::SubscriptionSettings settings(50, 600, 10);
    auto subscription = co_await client.createSubscription(settings);
    if (subscription) {
        // Named locals: GCC 12 destroys temporaries of a co_await expression twice.
        ua::Subscription::DataChangeCallback onChange = [shown](const ua::DataValue& v) {
            const auto* line = v.value ? v.value->get<ua::String>() : nullptr;
            if (line != nullptr) show(*shown, *line);
        };
        const ua::NodeId node = mes::progressVariable("Progress");
        auto item = co_await (*subscription)
                        ->monitorDataChange(node, ua::AttributeId::Value, 0, 100, std::nullopt,
                                            std::move(onChange));
        if (!item)
            spdlog::warn("run: cannot follow the progress: {}", ua::statusName(item.status()));
    }
    // A Halted ExecuteProcess is the previous run's stop: reset it, so that this one can
    // start (and resume that run).
    if (skill->state() == skills::SkillState::Halted) {
        std::cout << "PROGRESS the MES's last run stopped (ExecuteProcess is Halted): Reset\n";
        if (const auto s = co_await skill->call(skills::SkillMethod::Reset); s.isBad()) {
            std::cerr << "cannot reset ExecuteProcess: " << ua::statusName(s) << "\n";
        }
    }
    std::map<std::string, ua::Variant> values;
    values.emplace("ProcessIri", ua::Variant(ua::String(o.processIri)));
    const auto timeout = std::chrono::milliseconds(static_cast<long>(o.timeoutSeconds * 1000));
    const auto outcome = co_await skill->run(std::move(values), timeout);
    // The last progress (the end of the run) may not have been published yet.
    if (auto last = co_await client.readValue(mes::progressVariable("Progress"))) {
        if (const auto* line = last->get<ua::String>()) show(*shown, *line);
    }
    std::cout << "OUTCOME " << skills::name(outcome.kind);
    if (outcome.status.isBad()) std::cout << " " << ua::statusName(outcome.status);
    if (!outcome.reason.empty()) std::cout << " (" << outcome.reason << ")";
    std::cout << std::endl;
    if (subscription) (void)co_await (*subscription)->remove();
    co_await skill->detach();
    (void)co_await client.disconnect();
    co_return outcome.ok() ? 0 : 1;
}

}  // namespace

Command addMesCommand(CLI::App& app) {
    auto o = std::make_shared<MesOptions>();
    o->process.port = 4851;
    o->process.applicationUri = std::string(cell::kMesUri);
    o->process.applicationName = "skillcell semantic MES";
    auto* cmd = app.add_subcommand(
        "mes",
        "Run the semantic MES: the ExecuteProcess skill reads a process from the knowledge "
        "base, runs each step on a suitable skill that discovery finds, and records every step "
        "in a journal; ExecuteProcess of a process with an interrupted or stopped run resumes "
        "it. Objects/ProcessExecution shows what it is doing.");
    addServerProcessOptions(cmd, o->process);
    addDiscoveryOptions(cmd, o->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--kb", o->kbUrl,
                    "the knowledge base's SPARQL endpoint (https: trusted and used as on OPC "
                    "UA, with --client-user; http: with --insecure)")
        ->capture_default_str();
    cmd->add_option("--journal", o->journal,
                    "the SQLite journal (default: ~/.local/share/skillcell/mes/journal.sqlite)");
    cmd->add_option("--skill-wait-ms", o->skillWaitMs,
                    "how long a step waits for a suitable skill to be detected")
        ->check(CLI::Range(0, 600'000))
        ->capture_default_str();
    cmd->add_option("--step-timeout-ms", o->stepTimeoutMs, "the longest a skill may run")
        ->check(CLI::Range(100, 86'400'000))
        ->capture_default_str();
    return {cmd, [o] { return runMes(*o); }};
}

Command addRunCommand(CLI::App& app) {
    auto o = std::make_shared<RunOptions>();
    auto* cmd = app.add_subcommand(
        "run",
        "Hand a process to the MES (its ExecuteProcess skill) and follow it: PROGRESS lines "
        "as steps start and end, then OUTCOME. Exit code 0 when the process completed, 1 when "
        "it stopped (the reason is printed; running it again resumes it), 2 when the MES "
        "cannot be reached.");
    cmd->add_option("process", o->processIri,
                    "the process's IRI, e.g. "
                    "http://skillcell.dev/demo#pickAndPlaceTwoBoxes")
        ->required();
    cmd->add_option("--mes", o->mesUrl, "the MES's endpoint")->capture_default_str();
    cmd->add_option("--timeout", o->timeoutSeconds, "seconds to wait for the end; then Halt")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    addClientSecurityOptions(cmd, o->security);
    return {cmd, [o] {
                return runClientCommand([o](ua::Client& client) { return runProcess(client, *o); });
            }};
}

}  // namespace skillcell::apps
