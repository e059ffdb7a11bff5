#include "kb/engine/virtuoso_instance.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

namespace skillcell::kb::engine {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

constexpr const char* kIni = "virtuoso.ini";
constexpr const char* kLog = "virtuoso.log";
// virtuoso-t's stdout and stderr: a copy of its log plus what it prints before the log is
// open (ini errors, "Failed to start listening"). Error messages quote its tail.
constexpr const char* kConsole = "virtuoso.out";
constexpr const char* kPassword = "admin-password";
constexpr int kStartAttempts = 3;  // with picked ports: another process may take one first
constexpr milliseconds kReadyProbeInterval{100};
constexpr milliseconds kKillGrace{5000};
// An orphan is sent SIGKILL, so only uninterruptible I/O can keep it longer than this.
constexpr milliseconds kOrphanExitBound{10'000};
constexpr const char* kLockFile = "virtuoso.lck";

long long msSince(Clock::time_point t0) {
    return std::chrono::duration_cast<milliseconds>(Clock::now() - t0).count();
}

/// Free ports on 127.0.0.1, all distinct: the sockets stay bound until every port is known.
Expected<std::vector<std::uint16_t>> pickFreePorts(std::size_t count) {
    std::vector<process::UniqueFd> sockets;
    std::vector<std::uint16_t> ports;
    for (std::size_t i = 0; i < count; ++i) {
        process::UniqueFd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t len = sizeof addr;
        auto* any = reinterpret_cast<sockaddr*>(&addr);  // NOLINT: the sockets API
        if (!fd.valid() || ::bind(fd.get(), any, len) != 0 ||
            ::getsockname(fd.get(), any, &len) != 0) {
            return Error{"cannot pick a free port on 127.0.0.1: " + process::errnoText(errno)};
        }
        ports.push_back(ntohs(addr.sin_port));
        sockets.push_back(std::move(fd));
    }
    return ports;
}

/// Whether something accepts TCP connections on 127.0.0.1:port (answered at once on loopback).
bool acceptsConnections(std::uint16_t port) {
    const process::UniqueFd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(port);
    return fd.valid() &&
           ::connect(fd.get(), reinterpret_cast<const sockaddr*>(&addr),  // NOLINT: sockets API
                     sizeof addr) == 0;
}

std::string randomSecret(std::size_t length) {
    static constexpr std::string_view kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    std::random_device device;  // getrandom(2) on Linux
    std::uniform_int_distribution<std::size_t> pick(0, kAlphabet.size() - 1);
    std::string secret;
    for (std::size_t i = 0; i < length; ++i) secret += kAlphabet[pick(device)];
    return secret;
}

/// Writes `text` to `path` through a temporary file and rename, so a crash leaves the old
/// file or the new one, never half of one.
Status writeFileAtomically(const fs::path& path, const std::string& text, mode_t mode) {
    const fs::path tmp = path.string() + ".tmp";
    const process::UniqueFd fd(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode));
    if (!fd.valid())
        return Error{"cannot write " + tmp.string() + ": " + process::errnoText(errno)};
    ::fchmod(fd.get(), mode);  // the umask may have narrowed or the file existed
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd.get(), text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return Error{"cannot write " + tmp.string() + ": " + process::errnoText(errno)};
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd.get()) != 0 || ::rename(tmp.c_str(), path.c_str()) != 0) {
        return Error{"cannot write " + path.string() + ": " + process::errnoText(errno)};
    }
    return Done{};
}

std::string iniText(const fs::path& dir, std::uint16_t sqlPort, std::uint16_t httpPort) {
    const std::string d = dir.string();
    // Durability: TransactionFile is the write-ahead log; a commit is written to it before
    // isql or /sparql acknowledge it, and start-up rolls it forward ("N transactions
    // replayed"), which is what makes `kill -9` safe (tested). CheckpointSyncMode 2 (full
    // sync) puts a checkpoint on disk before the log it replaces is reused; that matters for
    // a machine crash, not for a killed process, and is not tested here.
    // MaxQueryExecutionTime 0: Virtuoso's "anytime" queries would silently return partial
    // results at the limit; a wrong answer is worse for a knowledge base than a slow one.
    return fmt::format(R"([Database]
DatabaseFile       = {0}/virtuoso.db
ErrorLogFile       = {0}/{3}
LockFile           = {0}/{4}
TransactionFile    = {0}/virtuoso.trx
xa_persistent_file = {0}/virtuoso.pxa
ErrorLogLevel      = 7
FileExtend         = 200
MaxCheckpointRemap = 2000
Striping           = 0
TempStorage        = TempDatabase

[TempDatabase]
DatabaseFile       = {0}/virtuoso-temp.db
TransactionFile    = {0}/virtuoso-temp.trx
MaxCheckpointRemap = 2000
Striping           = 0

[Parameters]
ServerPort           = 127.0.0.1:{1}
DisableUnixSocket    = 1
DisableTcpSocket     = 0
MaxClientConnections = 20
CheckpointInterval   = 60
CheckpointSyncMode   = 2
CheckpointAuditTrail = 0
CaseMode             = 2
DirsAllowed          = {0}
AllowOSCalls         = 0
NumberOfBuffers      = 10000
MaxDirtyBuffers      = 6000
ThreadsPerQuery      = 2

[HTTPServer]
ServerPort           = 127.0.0.1:{2}
ServerRoot           = {0}/www
MaxClientConnections = 10
ServerThreads        = 10
EnabledDavVSP        = 0
Charset              = UTF-8

[Client]
SQL_PREFETCH_ROWS  = 100
SQL_PREFETCH_BYTES = 16000

[SPARQL]
ResultSetMaxRows           = 1000000
MaxQueryExecutionTime      = 0
MaxQueryCostEstimationTime = 400
DefaultQuery               = SELECT * WHERE {{ ?s ?p ?o }} LIMIT 10
)",
                       d, sqlPort, httpPort, kLog, kLockFile);
}

}  // namespace

VirtuosoInstance::VirtuosoInstance(VirtuosoConfig config) : config_(std::move(config)) {}

VirtuosoInstance::~VirtuosoInstance() {
    if (auto st = stop(); !st) spdlog::error("{}", st.error());
}

std::string VirtuosoInstance::sparqlUrl() const {
    return "http://127.0.0.1:" + std::to_string(httpPort_) + "/sparql-auth";
}
fs::path VirtuosoInstance::logPath() const {
    return config_.dataDir / kLog;
}
fs::path VirtuosoInstance::passwordPath() const {
    return config_.dataDir / kPassword;
}

bool VirtuosoInstance::running() {
    return process_ && process_->running();
}

std::string VirtuosoInstance::howItEnded() {
    if (!process_) return "not started";
    auto ended = process_->wait(std::chrono::milliseconds(0));
    return ended ? ended->describe() : "still running";
}

Status VirtuosoInstance::prepareDataDir() {
    if (config_.dataDir.empty()) return Error{"Virtuoso: no data directory configured"};
    std::error_code ec;
    config_.dataDir = fs::absolute(config_.dataDir, ec);
    const fs::path& dir = config_.dataDir;
    if (fs::create_directories(dir, ec)) {
        fs::permissions(dir, fs::perms::owner_all, ec);
    }
    if (ec || !fs::is_directory(dir)) {
        return Error{"cannot create Virtuoso data directory " + dir.string() + ": " +
                     (ec ? ec.message() : "not a directory")};
    }
    fs::create_directories(dir / "www", ec);  // the HTTP root: empty, nothing to serve
    if (ec) return Error{"cannot create " + (dir / "www").string() + ": " + ec.message()};

    if (fs::exists(passwordPath())) {
        std::ifstream in(passwordPath());
        std::getline(in, password_);
        if (password_.empty()) {
            return Error{"Virtuoso admin password file " + passwordPath().string() + " is empty"};
        }
        return Done{};
    }
    // Written before the database learns it: a crash in between leaves a password we know
    // and a database still on dba/dba, which the next start completes.
    password_ = randomSecret(32);
    return writeFileAtomically(passwordPath(), password_ + "\n", 0600);
}

namespace {

/// Whether `pid` is a virtuoso-t on `dir`, ours since we start it there. Its name (comm)
/// stays until it is reaped; its working directory goes late in its exit, after its locks,
/// so one that cannot be read any more belongs to a Virtuoso that is ending. Anything else
/// (a reused pid, another Virtuoso) is not ours to stop.
bool isVirtuosoOn(pid_t pid, const fs::path& dir) {
    const fs::path proc = "/proc/" + std::to_string(pid);
    std::ifstream commFile(proc / "comm");
    std::string comm;
    std::getline(commFile, comm);
    if (comm.rfind("virtuoso", 0) != 0) return false;
    std::error_code ec;
    const fs::path cwd = fs::read_symlink(proc / "cwd", ec);
    if (ec) return true;
    return fs::equivalent(cwd, dir, ec) && !ec;
}

}  // namespace

pid_t VirtuosoInstance::lockHolder() const {
    std::ifstream in(config_.dataDir / kLockFile);
    std::string line;
    constexpr std::string_view kKey = "VIRT_PID=";
    while (std::getline(in, line)) {
        if (line.rfind(kKey, 0) != 0) continue;
        try {
            const long pid = std::stol(line.substr(kKey.size()));
            return pid > 0 ? static_cast<pid_t>(pid) : 0;
        } catch (const std::exception&) {
            return 0;
        }
    }
    return 0;
}

Status VirtuosoInstance::stopOrphan() {
    const pid_t pid = lockHolder();
    if (pid == 0) return Done{};
    // A pidfd names this process and no later one with the same pid: no race with reuse.
    const process::UniqueFd pidfd(static_cast<int>(::syscall(SYS_pidfd_open, pid, 0)));
    // Gone, or a reused pid: virtuoso-t locks the file itself, with a lock its holder's exit
    // releases, so a stale file does not stop it (tried: a dead or an unrelated pid in it).
    if (!pidfd.valid() || !isVirtuosoOn(pid, config_.dataDir)) return Done{};
    spdlog::warn(
        "Virtuoso (pid {}) of an earlier knowledge base still runs on data dir {}: "
        "stopping it before starting ours",
        pid, config_.dataDir.string());
    // SIGKILL, as PR_SET_PDEATHSIG would have: the transaction log makes it safe (tested).
    if (::syscall(SYS_pidfd_send_signal, pidfd.get(), SIGKILL, nullptr, 0) != 0 && errno != ESRCH) {
        return Error{"cannot stop the earlier Virtuoso (pid " + std::to_string(pid) +
                     ") on data dir " + config_.dataDir.string() + ": " +
                     process::errnoText(errno)};
    }
    // A pidfd polls readable once the process has exited, its files and their locks released.
    pollfd fd{pidfd.get(), POLLIN, 0};
    int ready = 0;
    do {
        ready = ::poll(&fd, 1, static_cast<int>(kOrphanExitBound.count()));
    } while (ready < 0 && errno == EINTR);
    if (ready <= 0) {
        return Error{"the earlier Virtuoso (pid " + std::to_string(pid) + ") on data dir " +
                     config_.dataDir.string() + " did not end within " +
                     std::to_string(kOrphanExitBound.count()) + " ms of SIGKILL"};
    }
    spdlog::info("the earlier Virtuoso (pid {}) has ended", pid);
    return Done{};
}

Status VirtuosoInstance::start() {
    if (running()) return Done{};
    const auto t0 = Clock::now();
    if (auto st = prepareDataDir(); !st) return st;
    if (auto st = stopOrphan(); !st) return st;
    const bool pickPorts = config_.httpPort == 0 || config_.sqlPort == 0;
    const auto deadline = t0 + config_.startTimeout;
    for (int attempt = 1;; ++attempt) {
        // Picked ports are kept across restarts, so a client's sparqlUrl() stays valid.
        if (pickPorts && (attempt > 1 || httpPort_ == 0 || sqlPort_ == 0)) {
            auto ports = pickFreePorts(2);
            if (!ports) return Error{ports.error()};
            httpPort_ = config_.httpPort != 0 ? config_.httpPort : (*ports)[0];
            sqlPort_ = config_.sqlPort != 0 ? config_.sqlPort : (*ports)[1];
        } else if (!pickPorts) {
            httpPort_ = config_.httpPort;
            sqlPort_ = config_.sqlPort;
        }
        if (auto st = launch(); !st) return st;
        auto ready = waitUntilReady(deadline);
        if (ready) break;
        const bool exited = !process_->running();
        if (!exited) (void)process_->terminate(kKillGrace);
        process_.reset();
        const bool portTaken = ready.error().find("Failed to start listening") != std::string::npos;
        // Only when we chose both ports can we choose again (virtuoso-t names no port we
        // could tell apart from a fixed one reliably).
        const bool bothPicked = config_.httpPort == 0 && config_.sqlPort == 0;
        if (!(exited && portTaken && bothPicked && attempt < kStartAttempts)) return ready;
        spdlog::warn("Virtuoso in {}: a picked port was taken meanwhile; trying others",
                     config_.dataDir.string());
    }
    spdlog::info("Virtuoso started (pid {}) in {} ms: data dir {}, SQL 127.0.0.1:{}, {}",
                 process_->pid(), msSince(t0), config_.dataDir.string(), sqlPort_, sparqlUrl());
    return Done{};
}

Status VirtuosoInstance::launch() {
    const fs::path& dir = config_.dataDir;
    if (auto st = writeFileAtomically(dir / kIni, iniText(dir, sqlPort_, httpPort_), 0600); !st) {
        return st;
    }
    std::error_code ec;
    outputOffset_ = fs::exists(dir / kConsole) ? fs::file_size(dir / kConsole, ec) : 0;
    process::ProcessOptions options;
    options.workingDir = dir;
    options.stdoutTo = process::OutputSink::toFile(dir / kConsole);
    options.stderrTo = process::OutputSink::toFile(dir / kConsole);
    auto child = process::ChildProcess::start(
        {config_.virtuosoBinary, "+foreground", "+configfile", (dir / kIni).string()}, options);
    if (!child) return Error{child.error()};
    process_.emplace(std::move(*child));
    spdlog::info("starting Virtuoso (pid {}): data dir {}, SQL port {}, HTTP port {}",
                 process_->pid(), dir.string(), sqlPort_, httpPort_);
    return Done{};
}

Status VirtuosoInstance::waitUntilReady(Clock::time_point deadline) {
    std::string lastProbe;
    for (;;) {
        if (!process_->running()) {
            return Error{"virtuoso-t (data dir " + config_.dataDir.string() +
                         ") exited during start, " + process_->wait(milliseconds{0})->describe() +
                         "; its output:\n" + outputTail()};
        }
        if (Clock::now() >= deadline) {
            return Error{"virtuoso-t (data dir " + config_.dataDir.string() +
                         ") did not answer on SQL port " + std::to_string(sqlPort_) + " within " +
                         std::to_string(config_.startTimeout.count()) + " ms" +
                         (lastProbe.empty() ? "" : " (isql: " + lastProbe + ")") +
                         "; its output:\n" + outputTail()};
        }
        // Both listeners open means start-up is over: the SQL one opens last.
        if (acceptsConnections(httpPort_) && acceptsConnections(sqlPort_)) {
            auto probe = isqlAs(password_, "select 1;");
            if (probe) return closeAnonymousAccess();
            if (probe.error().find("Bad login") != std::string::npos) return firstTimeSetup();
            lastProbe = probe.error();
        }
        // The pause between probes is a bounded wait for the process, which ends it early
        // if virtuoso-t exits.
        (void)process_->wait(kReadyProbeInterval);
    }
}

Status VirtuosoInstance::firstTimeSetup() {
    if (auto probe = isqlAs("dba", "select 1;"); !probe) {
        return Error{"Virtuoso in " + config_.dataDir.string() +
                     " accepts neither the password in " + passwordPath().string() +
                     " nor the default one: " + probe.error()};
    }
    if (auto set = isqlAs("dba", "user_set_password('dba', '" + password_ + "');"); !set) {
        return Error{"Virtuoso: cannot set the admin password: " + set.error()};
    }
    if (auto check = closeAnonymousAccess(); !check) {
        return Error{"Virtuoso: after setting the admin password: " + check.error()};
    }
    spdlog::info("Virtuoso in {}: admin password set (in {})", config_.dataDir.string(),
                 passwordPath().string());
    return Done{};
}

Status VirtuosoInstance::closeAnonymousAccess() {
    // dav/dav is the other well-known account (WebDAV over HTTP). Nobody here needs it, so it
    // gets a password nobody knows, at every start: a new database lists it in SYS_USERS
    // before user_set_password knows it (SR286), so the first start may have to leave it.
    auto dav = isqlAs(password_, "select user_set_password(U_NAME, '" + randomSecret(32) +
                                     "') from SYS_USERS where U_NAME = 'dav';");
    if (!dav && dav.error().find("SR286") == std::string::npos) return Error{dav.error()};

    // The KB's own SQL user, with a password that only this object knows (kept across its
    // restarts of the engine, so that a store made for it stays valid): SPARQL 1.1 Query,
    // Update and Graph Store, over HTTP Digest on loopback.
    if (sparqlPassword_.empty()) sparqlPassword_ = randomSecret(32);
    auto exists = isqlAs(password_, std::string("select count(*) from SYS_USERS where U_NAME = '") +
                                        kSparqlUser + "';");
    if (!exists) return Error{exists.error()};
    const bool known = exists->find('1') != std::string::npos;
    const std::string setUser =
        known
            ? std::string("user_set_password('") + kSparqlUser + "', '" + sparqlPassword_ + "');"
            : std::string("DB.DBA.USER_CREATE('") + kSparqlUser + "', '" + sparqlPassword_ + "');";
    if (auto set = isqlAs(password_, setUser); !set) {
        return Error{std::string("cannot set up the SQL user ") + kSparqlUser + ": " + set.error()};
    }
    // U0013: granted already; U0014: not granted (a database whose anonymous user had
    // SPARQL Update, as skillcell gave it before).
    auto grant = isqlAs(password_, std::string("GRANT SPARQL_UPDATE TO \"") + kSparqlUser + "\";");
    if (!grant && grant.error().find("U0013") == std::string::npos) return Error{grant.error()};
    // The anonymous user "SPARQL" may neither update nor read: Virtuoso re-creates some of
    // its anonymous HTTP paths at every start, which are removed below only once it answers.
    for (const char* role : {"SPARQL_UPDATE", "SPARQL_SELECT"}) {
        auto revoke = isqlAs(password_, std::string("REVOKE ") + role + " FROM \"SPARQL\";");
        if (!revoke && revoke.error().find("U0014") == std::string::npos) {
            return Error{revoke.error()};
        }
    }

    // Every HTTP path but the two that demand a user goes: /sparql and /sparql-graph-crud
    // (anonymous SPARQL), /proxy (fetches any URL), /URIQA (writes), /DAV, /SOAP, /XMLA ...
    auto paths =
        isqlAs(password_, "select HP_HOST, HP_LISTEN_HOST, HP_LPATH from DB.DBA.HTTP_PATH;");
    if (!paths) return Error{paths.error()};
    std::istringstream rows(*paths);
    std::string host;
    std::string listen;
    std::string path;
    std::string removals;
    int removed = 0;
    while (rows >> host >> listen >> path) {
        if (path == kSparqlPath || path == kGraphStorePath) continue;
        for (const auto* v : {&host, &listen, &path}) {
            if (v->find('\'') != std::string::npos) return Error{"a quote in " + *v};
        }
        removals += fmt::format("DB.DBA.VHOST_REMOVE(vhost=>'{}', lhost=>'{}', lpath=>'{}');", host,
                                listen, path);
        ++removed;
    }
    if (!removals.empty()) {
        if (auto r = isqlAs(password_, removals); !r) return Error{r.error()};
        spdlog::info("Virtuoso in {}: {} HTTP paths removed; SPARQL only at {} and {}, as {}",
                     config_.dataDir.string(), removed, kSparqlPath, kGraphStorePath, kSparqlUser);
    }
    return Done{};
}

Status VirtuosoInstance::stop() {
    if (!process_) return Done{};
    if (!process_->running()) {
        spdlog::warn("Virtuoso (data dir {}) had already ended: {}", config_.dataDir.string(),
                     process_->wait(milliseconds{0})->describe());
        process_.reset();
        return Done{};
    }
    const auto t0 = Clock::now();
    const pid_t pid = process_->pid();
    // `shutdown` checkpoints first, so the next start has no log to roll forward.
    auto asked = isqlAs(password_, "shutdown;");
    auto ended = process_->wait(config_.stopTimeout);
    if (!ended) {
        spdlog::warn("Virtuoso (pid {}) did not shut down within {} ms{}; terminating it", pid,
                     config_.stopTimeout.count(), asked ? "" : " (" + asked.error() + ")");
        ended = process_->terminate(kKillGrace);
    }
    process_.reset();
    if (!ended)
        return Error{"Virtuoso (pid " + std::to_string(pid) + ") would not stop: " + ended.error()};
    spdlog::info("Virtuoso stopped (pid {}, {}) in {} ms: data dir {}", pid, ended->describe(),
                 msSince(t0), config_.dataDir.string());
    return Done{};
}

void VirtuosoInstance::kill() {
    if (!process_) return;
    const pid_t pid = process_->pid();
    auto ended = process_->kill();
    process_.reset();
    spdlog::warn("Virtuoso (pid {}) killed: {}", pid, ended ? ended->describe() : ended.error());
}

Expected<std::string> VirtuosoInstance::isql(const std::string& sql) const {
    if (sqlPort_ == 0 || password_.empty()) return Error{"isql: Virtuoso has not been started"};
    return isqlAs(password_, sql);
}

Expected<std::string> VirtuosoInstance::isqlAs(const std::string& password,
                                               const std::string& sql) const {
    // The password is an argument: isql-vt reads it nowhere else. Loopback tool runs only.
    auto run = process::runToCompletion(
        {config_.isqlBinary, "127.0.0.1:" + std::to_string(sqlPort_), "dba", password,
         "VERBOSE=OFF", "BANNER=OFF", "PROMPT=OFF", "ECHO=OFF", "EXEC=" + sql},
        config_.isqlTimeout);
    if (!run) return Error{run.error()};
    // isql-vt goes on after a failed statement and may still exit 0: its stderr decides.
    if (run->exitCode != 0 || run->err.find("*** Error") != std::string::npos) {
        std::string why = run->err.empty() ? run->out : run->err;
        while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
        return Error{"isql (exit code " + std::to_string(run->exitCode) + "): " + why};
    }
    return std::move(run->out);
}

std::string VirtuosoInstance::outputTail() const {
    constexpr std::uintmax_t kTail = 3000;
    std::ifstream in(config_.dataDir / kConsole, std::ios::binary);
    if (!in) return "(no output)";
    in.seekg(0, std::ios::end);
    const auto size = static_cast<std::uintmax_t>(in.tellg());
    const std::uintmax_t from = std::max(outputOffset_, size > kTail ? size - kTail : 0);
    in.seekg(static_cast<std::streamoff>(from));
    std::ostringstream text;
    text << in.rdbuf();
    return text.str().empty() ? "(no output)" : text.str();
}

}  // namespace skillcell::kb::engine
