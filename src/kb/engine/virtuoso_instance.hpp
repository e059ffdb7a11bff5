#pragma once
// VirtuosoInstance: a private Virtuoso (virtuoso-t) that the knowledge base starts, watches
// and stops, in a data directory of its own. Nothing is shared with a system-wide Virtuoso:
// the ini file is ours, both ports listen on 127.0.0.1 only, and the default dba/dba
// password is replaced on first start by a random one kept in <dataDir>/admin-password.
// Nothing of it takes anonymous requests: SPARQL over HTTP runs as an SQL user of the KB's
// own, with a password for this run only, and every other HTTP path is removed.
//
// Durability: every commit is appended to the transaction log (virtuoso.trx) before it is
// acknowledged, and a restart rolls that log forward, so data acknowledged before a
// `kill -9` is there after the next start() (tested).
//
// Orphans: the kernel kills our virtuoso-t when the KB dies (PR_SET_PDEATHSIG), but a big
// process takes a while to exit, and it holds virtuoso.lck until it has. A KB restarted at
// once would find its data directory locked; start() therefore ends a virtuoso-t that still
// runs on this data directory and waits for its end (tested).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "kb/expected.hpp"
#include "process/child_process.hpp"

namespace skillcell::kb::engine {

struct VirtuosoConfig {
    std::filesystem::path dataDir;  // created (mode 0700) if missing; kept across restarts
    std::uint16_t httpPort = 0;     // on 127.0.0.1; 0: pick a free port (kept across restarts)
    std::uint16_t sqlPort = 0;      // on 127.0.0.1; 0: pick a free port (kept across restarts)
    std::chrono::milliseconds startTimeout{60'000};
    std::chrono::milliseconds stopTimeout{30'000};
    std::chrono::milliseconds isqlTimeout{60'000};
    std::string virtuosoBinary = "/usr/bin/virtuoso-t";
    std::string isqlBinary = "/usr/bin/isql-vt";
};

class VirtuosoInstance {
public:
    /// No I/O here: start() does it.
    explicit VirtuosoInstance(VirtuosoConfig config);
    /// Stops a running instance cleanly.
    ~VirtuosoInstance();
    VirtuosoInstance(const VirtuosoInstance&) = delete;
    VirtuosoInstance& operator=(const VirtuosoInstance&) = delete;
    VirtuosoInstance(VirtuosoInstance&&) = delete;
    VirtuosoInstance& operator=(VirtuosoInstance&&) = delete;

    /// Writes the ini, starts virtuoso-t and returns once it answers SQL (bounded by
    /// startTimeout). The first start of a data directory also sets the admin password;
    /// every start closes anonymous access (closeAnonymousAccess). Errors carry the tail of
    /// the engine's output.
    Status start();
    /// Clean shutdown (SQL `shutdown`, then SIGTERM, then SIGKILL; bounded).
    Status stop();
    /// SIGKILL without a checkpoint: a crash, for tests of what survives one.
    void kill();
    [[nodiscard]] bool running();
    /// A descriptor that poll() reports readable when the running virtuoso-t ends (its
    /// pidfd); -1 when none runs. A new one after each start().
    [[nodiscard]] int exitFd() const { return process_ ? process_->exitFd() : -1; }
    /// How the last virtuoso-t ended, once it has ("still running" before).
    [[nodiscard]] std::string howItEnded();

    [[nodiscard]] std::uint16_t httpPort() const { return httpPort_; }
    [[nodiscard]] std::uint16_t sqlPort() const { return sqlPort_; }
    /// "http://127.0.0.1:<httpPort>/sparql-auth": queries and updates, as sparqlUser() with
    /// HTTP Digest. No path of Virtuoso's HTTP listener takes anonymous requests.
    [[nodiscard]] std::string sparqlUrl() const;
    /// The path of its SPARQL 1.1 Graph Store HTTP Protocol service on httpPort(), which
    /// takes a graph as one document (the same user and rights as sparqlUrl()).
    [[nodiscard]] static std::string graphStorePath() { return kGraphStorePath; }
    /// The SQL user that SPARQL over HTTP runs as, and its password (made by this object's
    /// first start(), kept by its restarts, known only to this process).
    [[nodiscard]] static std::string sparqlUser() { return kSparqlUser; }
    [[nodiscard]] const std::string& sparqlPassword() const { return sparqlPassword_; }
    /// Virtuoso's own log.
    [[nodiscard]] std::filesystem::path logPath() const;
    [[nodiscard]] const std::filesystem::path& dataDir() const { return config_.dataDir; }
    [[nodiscard]] std::filesystem::path passwordPath() const;
    /// The pid that the data directory's lock file (virtuoso.lck) names: the virtuoso-t that
    /// runs, or last ran, on it; 0 when there is none.
    [[nodiscard]] pid_t lockHolder() const;

    /// Runs `sql` (one or more statements, each ended by ';') through isql-vt as dba; its
    /// output without banners. Fails when isql reports an error.
    Expected<std::string> isql(const std::string& sql) const;

private:
    Status prepareDataDir();
    Status stopOrphan();
    Status launch();
    Status waitUntilReady(std::chrono::steady_clock::time_point deadline);
    Status firstTimeSetup();
    /// At every start: dav locked, the KB's SQL user (re)made, SPARQL Update taken from the
    /// anonymous user, and every HTTP path removed but the two that demand a user.
    Status closeAnonymousAccess();
    Expected<std::string> isqlAs(const std::string& password, const std::string& sql) const;
    [[nodiscard]] std::string outputTail() const;

    VirtuosoConfig config_;
    std::optional<process::ChildProcess> process_;
    std::uint16_t httpPort_ = 0;
    std::uint16_t sqlPort_ = 0;
    std::string password_;
    std::string sparqlPassword_;
    static constexpr const char* kSparqlUser = "skillcell_kb";
    static constexpr const char* kSparqlPath = "/sparql-auth";
    static constexpr const char* kGraphStorePath = "/sparql-graph-crud-auth";
    std::uintmax_t outputOffset_ = 0;  // where this run's output starts in virtuoso.out
};

}  // namespace skillcell::kb::engine
