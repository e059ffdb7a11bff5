// `skillcell mes`: the semantic MES as a component of the cell (docs/mes.md). Clients submit
// orders (`skillcell run`, order_commands.cpp).
//
// The MES serves Objects/Orders, the ExecuteProcess skill (ProcessIri) and
// Objects/ProcessExecution (what it is doing). For an order it reads the process from the
// knowledge base's SPARQL endpoint (--kb), picks the skills from what discovery finds, runs
// them, and records every step in its SQLite journal (--journal), from which a restarted MES
// resumes the orders it was running.
#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>
#include <asio/thread_pool.hpp>
#include <asio/use_awaitable.hpp>
#include <filesystem>
#include <iostream>

#include "cell/component_uris.hpp"
#include "client_security_options.hpp"
#include "commands.hpp"
#include "devices/common/blocking_call.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "mes/journal_lock.hpp"
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
    std::string journalPath;  // the journal used: --journal, else the default
    int skillWaitMs = 10'000;
    int stepTimeoutMs = 300'000;
};

fs::path defaultJournal() {
    const char* home = std::getenv("HOME");
    return fs::path(home != nullptr ? home : "/tmp") / ".local/share/skillcell/mes/journal.sqlite";
}

/// What `skillcell mes` keeps alive, destroyed in reverse: the wait for the journal's lock,
/// the component (it halts the orders), the executor, the journal and the thread the KB's
/// blocking HTTP requests run on.
struct MesContent {
    std::unique_ptr<mes::JournalLock> lock;
    std::unique_ptr<asio::thread_pool> kbThread;
    std::unique_ptr<kb::HttpSparqlStore> store;
    std::unique_ptr<mes::Journal> journal;
    std::shared_ptr<mes::ProcessExecutor> executor;
    std::unique_ptr<mes::MesComponent> component;
    std::shared_ptr<asio::steady_timer> lockRetry;  // standBy()'s
    ~MesContent() {
        if (lockRetry) lockRetry->cancel();
        component.reset();
        executor.reset();
        if (kbThread) kbThread->join();
    }
};

/// Tries the journal's lock every 100 ms (flock has no asynchronous wait) until the active
/// MES ends, then resumes its orders here. Ends with the content (its timer is cancelled).
asio::awaitable<void> standBy(std::weak_ptr<MesContent> weak,
                              std::shared_ptr<asio::steady_timer> timer) {
    for (;;) {
        timer->expires_after(std::chrono::milliseconds(100));
        const auto [ec] =
            co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        auto content = weak.lock();
        if (ec || !content) co_return;  // shutting down
        auto attempt = content->lock->tryAcquire();
        if (!attempt) {
            spdlog::error("mes: {}", attempt.error());
            continue;
        }
        if (*attempt == mes::JournalLock::Attempt::Held) continue;
        auto resumed = content->executor->resumeOpenOrders();
        if (resumed) {
            spdlog::warn("mes: the journal is ours now: {} open order(s) resumed", *resumed);
        } else {
            spdlog::error("mes: cannot resume the journal's orders: {}", resumed.error());
        }
        co_return;
    }
}

int runMes(MesOptions& o) {
    auto endpoint = kb::HttpSparqlEndpoint::fromUrl(o.kbUrl);
    if (!endpoint) {
        spdlog::critical("mes: --kb {}: {}", o.kbUrl, endpoint.error());
        return 2;
    }
    const fs::path journalPath = o.journal.empty() ? defaultJournal() : fs::path(o.journal);
    o.journalPath = journalPath.string();
    std::error_code ec;
    if (journalPath.has_parent_path()) fs::create_directories(journalPath.parent_path(), ec);
    auto journal = mes::Journal::open(journalPath.string());
    if (!journal) {
        spdlog::critical("mes: {}", journal.error());
        return 1;
    }
    if (auto open = (*journal)->unfinishedRuns(); open && !open->empty()) {
        for (const auto& r : *open) {
            spdlog::warn("mes: order {} of {} is {}{}", r.id, r.processIri, mes::toString(r.state),
                         r.reason.empty() ? "" : " (" + r.reason + ")");
        }
    }
    auto lock = mes::JournalLock::open(journalPath.string());
    if (!lock) {
        spdlog::critical("mes: {}", lock.error());
        return 1;
    }
    auto attempt = lock->tryAcquire();
    if (!attempt) {
        spdlog::critical("mes: {}", attempt.error());
        return 1;
    }
    if (*attempt == mes::JournalLock::Attempt::Held) {
        spdlog::warn(
            "mes: another MES runs the orders of {}: this one stands by, and takes them "
            "over when that one ends",
            journalPath.string());
    }
    auto lockHolder = std::make_shared<mes::JournalLock>(std::move(*lock));
    spdlog::info("mes: journal {}, knowledge base {}", journalPath.string(), endpoint->urlText());
    o.process.usesDetector = true;
    auto journalHolder = std::make_shared<std::unique_ptr<mes::Journal>>(std::move(*journal));
    return runServerProcess(
        o.process,
        [&o, journalHolder, lockHolder,
         endpoint = *endpoint](const ComponentContext& c) -> ua::Result<ComponentContent> {
            auto content = std::make_shared<MesContent>();
            content->lock = std::make_unique<mes::JournalLock>(std::move(*lockHolder));
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
            // The reservations' holder: this MES's journal (a standby on it is the same).
            std::error_code canonicalError;
            const auto journalFile = fs::weakly_canonical(o.journalPath, canonicalError);
            options.holder =
                c.applicationUri + " " + (canonicalError ? o.journalPath : journalFile.string());
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
            if (!content->lock->held()) content->executor->standBy();
            std::string error;
            auto component = mes::MesComponent::create(c.server, content->executor, &error);
            if (!component) {
                spdlog::critical("mes: {}", error);
                return component.status();
            }
            content->component = std::move(*component);
            if (!content->lock->held()) {
                content->lockRetry = std::make_shared<asio::steady_timer>(c.io);
                asio::co_spawn(c.io, standBy(content, content->lockRetry), asio::detached);
            }
            return ComponentContent(content);
        });
}

}  // namespace

Command addMesCommand(CLI::App& app) {
    auto o = std::make_shared<MesOptions>();
    o->process.port = 4851;
    o->process.applicationUri = std::string(cell::kMesUri);
    o->process.applicationName = "skillcell semantic MES";
    const auto models = mes::MesComponent::skillModels();
    o->process.skillModels.assign(models.begin(), models.end());
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

}  // namespace skillcell::apps
