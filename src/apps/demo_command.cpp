// `skillcell demo`: the paper's whole work cell on one machine, in one command (docs/demo.md).
//
// Every component is a process of its own, started by the demo as a plant engineer would
// start them, with security on (a cell CA issues every certificate; users with roles): the
// Local Discovery Server, the knowledge base (Virtuoso + Konclude, with the paper's
// process), the world model, the UR5, the tool changer (which powers the Robotiq and Schmalz
// adapters as it attaches them), the pick-and-place composite and the semantic MES. They find
// each other by mDNS inside a private network namespace (nothing reaches the machine's real
// network), and the demo does not tell any of them where another one is except the world
// model (the devices' physics) and the MES's knowledge base.
//
// Then, as in the paper's evaluation (section VIII-C):
//  1. detection: each measured component is started --runs times; each time, the demo's own
//     SkillDetector (what any other component runs) clocks the time from the start of the
//     process to the arrival of its skills. The gripper adapters start like the paper's
//     microcontroller boards (--boot-profile tinyua) unless told otherwise;
//  2. the process: an operator hands the MES the paper's process (`skillcell run`, a client
//     like any other) and the demo shows its progress;
//  3. the evidence: the world model's boxes and mounted tool, the MES's journal, and the
//     detection times beside the paper's figures.
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "application_identity.hpp"
#include "cell/cell_file.hpp"
#include "cell/device_arguments.hpp"
#include "cell_process.hpp"
#include "client_security_options.hpp"
#include "commands.hpp"
#include "devices/common/frame.hpp"
#include "devices/world/world_link.hpp"
#include "mes/journal.hpp"
#include "private_network.hpp"
#include "skill_detection_clock.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/server/user_database.hpp"

namespace skillcell::apps {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr const char* kProcessIri = "http://skillcell.dev/demo#pickAndPlaceTwoBoxes";

struct DemoOptions {
    std::string cellFile = SKILLCELL_DEFAULT_CELL;  // examples/cells/paper.toml of the source tree
    double speed = 0;                               // 0: the cell file's robot speed
    std::string bootProfile = "tinyua";
    int runs = 5;
    bool keepRunning = false;
    bool swap = false;
    std::string workDir;
    double processTimeoutSeconds = 900;
};

/// How the demo's table calls an adapter, and the paper's detection time for it
/// (section VIII-C; 0: the paper has none).
struct AdapterFigure {
    std::string_view model;
    const char* label;
    double paperMs;
};
constexpr AdapterFigure kAdapterFigures[] = {{"robotiq-2f85", "Robotiq adapter", 8422},
                                             {"schmalz-ecbpi", "Schmalz adapter", 9635},
                                             {"dh-ag95", "AG-95 adapter", 0}};

/// What the demo needs of a cell file: the paper's process runs on a tool changer that moves
/// a UR5, the pick-and-place composite, and the KB and MES; empty when the cell has them.
std::string whatTheDemoLacks(const cell::CellFile& c) {
    std::string lacks;
    auto need = [&](bool has, const char* what) {
        if (!has) lacks += (lacks.empty() ? "" : ", ") + std::string(what);
    };
    need(c.lds, "[lds]");
    need(c.kb.has_value(), "[kb]");
    need(c.mes.has_value(), "[mes]");
    need(c.robots.size() == 1 && c.robots[0].model == "ur5", "one [[robot]] of model ur5");
    need(c.toolChanger.has_value(), "[toolchanger]");
    need(!c.tools.empty(), "[[tool]]");
    need(c.pickAndPlace.has_value(), "[pickplace]");
    need(c.security.enabled && c.security.ca.empty() && c.security.users.empty(),
         "[security] enabled, with the CA and users generated");
    return lacks;
}

/// --swap: a shelf beside the cell with the other parallel gripper (a DH AG-95, 1 cm longer),
/// and a free place for the Robotiq when it is taken out. The world model gets its docks and
/// tool, the changer's table the AG-95's coding resistor and adapter; nothing else in the cell
/// (not the process, not the MES) hears of it. In the cell file's terms, so that it becomes
/// command lines by the same code as the file.
cell::CellFile swapShelf() {
    constexpr double kPi = 3.141592653589793;
    cell::CellFile shelf;
    shelf.docks = {{"shelf1", {0.1, -0.6, 0.35, kPi, 0, 0}},
                   {"shelf2", {0.0, -0.6, 0.35, kPi, 0, 0}}};
    shelf.tools = {{"ag95", "shelf1", "dh-ag95", {0, 0, 0.16}, {3.0, 3.5}}};
    return shelf;
}

/// A component whose detection time the paper reports.
struct MeasuredComponent {
    std::string name;            // the demo's name for it (logs, output)
    std::string label;           // as the table shows it
    std::string applicationUri;  // how the detector knows it
    double paperMs = 0;          // Profanter et al., section VIII-C
    bool staysForTheProcess = false;
    std::vector<std::string> args;  // after the skillcell program
    std::vector<double> samplesMs;  // start -> skills detected
    std::vector<double> readyMs;    // start -> READY (listening), the part the process takes
};

double milliseconds(Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

/// SIGINT/SIGTERM are blocked in every thread of the demo (its children unblock them): the
/// demo notices them between its bounded waits and stops its cell in order, the tool changer
/// first, instead of dying with its components orphaned.
class Interruption {
public:
    Interruption() {
        sigemptyset(&set_);
        sigaddset(&set_, SIGINT);
        sigaddset(&set_, SIGTERM);
        pthread_sigmask(SIG_BLOCK, &set_, &previous_);
    }
    ~Interruption() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
    Interruption(const Interruption&) = delete;
    Interruption& operator=(const Interruption&) = delete;

    /// True once SIGINT or SIGTERM came (it stays pending; it is not consumed).
    [[nodiscard]] bool requested() const {
        sigset_t pending;
        sigpending(&pending);
        return sigismember(&pending, SIGINT) == 1 || sigismember(&pending, SIGTERM) == 1;
    }
    /// Waits for SIGINT or SIGTERM, and takes it.
    void wait() const {
        int sig = 0;
        sigwait(&set_, &sig);
    }

private:
    sigset_t set_{};
    sigset_t previous_{};
};

/// The demo's working directory: kept when given (--work-dir), else a new one that is removed
/// at the end unless the demo failed (its logs tell why).
class WorkDirectory {
public:
    static std::optional<WorkDirectory> create(const std::string& given, std::string* error) {
        WorkDirectory w;
        std::error_code ec;
        if (!given.empty()) {
            w.path_ = fs::absolute(given, ec);
            fs::create_directories(w.path_, ec);
            w.keep_ = true;
        } else {
            std::string pattern = (fs::temp_directory_path(ec) / "skillcell-demo-XXXXXX").string();
            if (::mkdtemp(pattern.data()) == nullptr) {
                *error = "cannot create a directory in " + fs::temp_directory_path(ec).string();
                return std::nullopt;
            }
            w.path_ = pattern;
        }
        if (ec) {
            *error = "cannot create " + w.path_.string() + ": " + ec.message();
            return std::nullopt;
        }
        fs::create_directories(w.path_ / "logs", ec);
        return w;
    }
    WorkDirectory(WorkDirectory&& other) noexcept
        : path_(std::move(other.path_)), keep_(std::exchange(other.keep_, true)) {}
    WorkDirectory& operator=(WorkDirectory&&) = delete;
    WorkDirectory(const WorkDirectory&) = delete;
    WorkDirectory& operator=(const WorkDirectory&) = delete;
    ~WorkDirectory() {
        std::error_code ec;
        if (!keep_ && !path_.empty()) fs::remove_all(path_, ec);
    }

    [[nodiscard]] const fs::path& path() const { return path_; }
    [[nodiscard]] fs::path log(const std::string& name) const {
        return path_ / "logs" / (name + ".log");
    }
    void keep() { keep_ = true; }

private:
    WorkDirectory() = default;
    fs::path path_;
    bool keep_ = false;
};

/// Writes `text` and a newline to `file`, readable by us only (a password).
bool writeSecret(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::trunc);
    out << text << '\n';
    std::error_code ec;
    fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write, ec);
    return static_cast<bool>(out);
}

/// The cell's security: a CA that issues every component's certificate, and the users: the
/// operator who hands the MES a process, "cell", whom the components act as, and the engineer
/// who changes the cell's setup (--swap).
bool prepareSecurity(const fs::path& dir, std::string* error) {
    ua::pki::CaOptions ca;
    ca.name = "skillcell demo cell CA";
    if (!ua::pki::createCertificateAuthority(dir / "ca", ca, error)) return false;
    std::string why;
    auto users = ua::UserDatabase::load(dir / "users", &why);
    if (!users) {
        *error = why;
        return false;
    }
    const std::pair<const char*, ua::Role> roles[] = {{"operator", ua::Role::Operator},
                                                      {"cell", ua::Role::Operator},
                                                      {"engineer", ua::Role::Engineer}};
    for (const auto& [name, role] : roles) {
        const std::string password = std::string(name) + "-" + std::to_string(::getpid());
        if (users->setPassword(name, ua::RoleSet{role}, password).isBad() ||
            !writeSecret(dir / (std::string(name) + ".pw"), password)) {
            *error = std::string("cannot create the user ") + name;
            return false;
        }
    }
    if (users->save(dir / "users", &why).isBad()) {
        *error = why;
        return false;
    }
    return true;
}

class DemoCell {
public:
    DemoCell(const DemoOptions& o, const cell::CellFile& cell, WorkDirectory& work,
             std::string skillcell)
        : o_(o), cell_(cell), work_(work), skillcell_(std::move(skillcell)) {}
    DemoCell(const DemoCell&) = delete;
    DemoCell& operator=(const DemoCell&) = delete;
    /// The tool changer first: it powers its tools off as it stops.
    ~DemoCell() { stopAll(); }

    int run(const Interruption& interruption);

private:
    [[nodiscard]] fs::path dir() const { return work_.path(); }
    [[nodiscard]] std::vector<std::pair<std::string, std::string>> environment() const {
        return {{"SKILLCELL_CA_DIR", (dir() / "ca").string()}};
    }
    /// What every component takes: loopback, quick mDNS, its PKI, the users, whom it acts as.
    [[nodiscard]] std::vector<std::string> componentArgs(const std::string& name,
                                                         bool actsAsCell) const;
    [[nodiscard]] std::string adapterCommand(const std::string& kind,
                                             const std::string& extra) const;
    kb::Expected<CellProcess> startProcess(const std::string& name, std::vector<std::string> args,
                                           std::chrono::milliseconds timeout);
    /// The component's certificate, issued by the cell CA into its PKI directory.
    [[nodiscard]] std::optional<ApplicationIdentity> commission(const std::string& name,
                                                                const std::string& applicationUri,
                                                                std::string* error) const;
    bool startInfrastructure();
    bool measure(MeasuredComponent& m, const Interruption& interruption);
    int runProcess(const Interruption& interruption);
    /// A session with the world model as `user` (its password file in the work directory),
    /// with the demo's certificate; nullptr after saying why on stderr.
    std::unique_ptr<devices::WorldLink> connectWorld(const std::string& user);
    /// --swap: an engineer takes the Robotiq gripper out of its dock and puts a DH AG-95 in.
    bool swapParallelGripper();
    void showWorld();
    void showJournal();
    /// What the cell refuses: returns false when something it must refuse got through.
    bool showSecurity();
    void showDetectionTable(const std::vector<MeasuredComponent>& measured) const;
    void stopAll();

    /// --speed, else the cell file's robot speed: for the robot and the grippers alike.
    [[nodiscard]] double speed() const {
        return o_.speed > 0 ? o_.speed : cell_.robots.front().speed;
    }

    const DemoOptions& o_;
    const cell::CellFile& cell_;
    WorkDirectory& work_;
    std::string skillcell_;
    std::optional<ApplicationIdentity> identity_;  // the demo's own, from the cell CA
    std::unique_ptr<SkillDetectionClock> clock_;
    std::vector<CellProcess> running_;  // in start order
    std::string worldUrl_;
    std::string sparqlUrl_;
    std::string mesUrl_;
};

std::vector<std::string> DemoCell::componentArgs(const std::string& name, bool actsAsCell) const {
    std::vector<std::string> a = {"--port",
                                  "0",
                                  "--host",
                                  "127.0.0.1",
                                  "--mdns-ttl",
                                  "5",
                                  "--mdns-query-period",
                                  "1",
                                  "--pki-dir",
                                  (dir() / ("pki-" + name)).string(),
                                  "--users",
                                  (dir() / "users").string()};
    if (actsAsCell) {
        a.insert(a.end(),
                 {"--client-user", "cell", "--client-password-file", (dir() / "cell.pw").string()});
    }
    return a;
}

std::string DemoCell::adapterCommand(const std::string& kind, const std::string& extra) const {
    std::string cmd = skillcell_ + " device " + kind + " --world " + worldUrl_;
    for (const auto& a : componentArgs(kind, true)) cmd += " " + a;
    cmd += " --speed " + std::to_string(speed()) + " --boot-profile " + o_.bootProfile;
    if (!extra.empty()) cmd += " " + extra;
    return cmd;
}

kb::Expected<CellProcess> DemoCell::startProcess(const std::string& name,
                                                 std::vector<std::string> args,
                                                 std::chrono::milliseconds timeout) {
    args.insert(args.begin(), skillcell_);
    return CellProcess::start(name, args, environment(), work_.log(name), timeout);
}

std::optional<ApplicationIdentity> DemoCell::commission(const std::string& name,
                                                        const std::string& applicationUri,
                                                        std::string* error) const {
    const fs::path pki = dir() / ("pki-" + name);
    std::error_code ec;
    fs::create_directories(pki, ec);
    if (!fs::exists(pki / "cell-ca"))
        fs::create_directory_symlink(dir() / "ca", pki / "cell-ca", ec);
    if (ec) {
        *error = "cannot link " + pki.string() + "/cell-ca: " + ec.message();
        return std::nullopt;
    }
    auto identity = ApplicationIdentity::load(pki, applicationUri, "skillcell " + name, error);
    if (!identity) return std::nullopt;
    return std::move(*identity);
}

bool DemoCell::startInfrastructure() {
    auto keep = [this](kb::Expected<CellProcess> p, const std::string& extra = {}) {
        if (!p) {
            std::cerr << "demo: " << p.error() << "\n";
            return false;
        }
        std::printf("  %-14s %s%s\n", p->name().c_str(), p->url().c_str(), extra.c_str());
        running_.push_back(std::move(*p));
        return true;
    };
    auto args = [this](std::vector<std::string> head, const std::string& name, bool actsAsCell) {
        auto tail = componentArgs(name, actsAsCell);
        head.insert(head.end(), tail.begin(), tail.end());
        return head;
    };
    if (!keep(startProcess("lds", args({"lds"}, "lds", false), 30s))) return false;
    // Virtuoso's first start creates its database and Konclude checks every model: minutes
    // on a slow machine, seconds on a fast one.
    auto kb = startProcess(
        "kb",
        args({"kb", "--demo-process", "--http-port", "0", "--data-dir", (dir() / "kb").string()},
             "kb", true),
        300s);
    if (kb) sparqlUrl_ = kb->reported("SPARQL");
    if (!keep(std::move(kb), "  SPARQL " + sparqlUrl_)) return false;
    std::vector<std::string> scene = {"device", "world"};
    const auto fromCell = cell::worldArguments(cell_);  // docks, tools, boxes
    scene.insert(scene.end(), fromCell.begin(), fromCell.end());
    if (o_.swap) {
        const auto shelf = cell::worldArguments(swapShelf());
        scene.insert(scene.end(), shelf.begin(), shelf.end());
    }
    auto world = startProcess("world", args(std::move(scene), "world", false), 30s);
    if (world) worldUrl_ = world->url();
    return keep(std::move(world));
}

bool DemoCell::measure(MeasuredComponent& m, const Interruption& interruption) {
    std::printf("  %-16s", m.label.c_str());
    std::fflush(stdout);
    for (int run = 1; run <= o_.runs; ++run) {
        if (interruption.requested()) return false;
        const auto t0 = Clock::now();
        auto p = startProcess(m.name, m.args, 120s);
        if (!p) {
            std::printf("\n");
            std::cerr << "demo: " << p.error() << "\n";
            return false;
        }
        m.readyMs.push_back(milliseconds(Clock::now() - t0));
        const auto detected = clock_->waitAppeared(m.applicationUri, t0, 60s);
        if (!detected) {
            std::printf("\n");
            std::cerr << "demo: the skills of " << m.name
                      << " were not detected within 60 s of its start; see "
                      << work_.log(m.name).string() << "\n";
            return false;
        }
        m.samplesMs.push_back(milliseconds(*detected - t0));
        std::printf(" %8.0f", m.samplesMs.back());
        std::fflush(stdout);
        if (m.staysForTheProcess && run == o_.runs) {
            running_.push_back(std::move(*p));
            break;
        }
        if (auto s = p->stop(10s); !s || !s->success()) {
            std::printf("\n");
            std::cerr << "demo: " << m.name << " did not stop cleanly ("
                      << (s ? s->describe() : s.error()) << "); see " << work_.log(m.name).string()
                      << "\n";
            return false;
        }
        // The next start must be detected afresh: its skills must have left first.
        if (!clock_->waitGone(m.applicationUri, 30s)) {
            std::printf("\n");
            std::cerr << "demo: the skills of " << m.name << " were still listed 30 s after it "
                      << "stopped\n";
            return false;
        }
    }
    std::printf("  ms\n");
    return true;
}

int DemoCell::runProcess(const Interruption& interruption) {
    std::vector<std::string> argv = {skillcell_,
                                     "run",
                                     kProcessIri,
                                     "--mes",
                                     mesUrl_,
                                     "--pki-dir",
                                     (dir() / "pki-operator").string(),
                                     "--user",
                                     "operator",
                                     "--password-file",
                                     (dir() / "operator.pw").string(),
                                     "--timeout",
                                     std::to_string(o_.processTimeoutSeconds)};
    process::ProcessOptions options = process::reportingChild(work_.log("run"));
    options.envAdd = environment();
    auto child = process::ChildProcess::start(argv, options);
    if (!child) {
        std::cerr << "demo: " << child.error() << "\n";
        return 1;
    }
    const auto t0 = Clock::now();
    std::string outcome;
    // Bounded: `skillcell run` halts the process after --timeout and ends; one more minute
    // covers its connection and cleanup.
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(o_.processTimeoutSeconds + 60));
    while (Clock::now() < deadline && !interruption.requested()) {
        auto line = child->readLine(1s);
        if (!line) {
            if (!child->running()) break;
            continue;
        }
        const double s = milliseconds(Clock::now() - t0) / 1000;
        if (line->starts_with("PROGRESS ")) {
            std::printf("  [%6.1f s] %s\n", s, line->substr(9).c_str());
        } else if (line->starts_with("OUTCOME ")) {
            outcome = line->substr(8);
            std::printf("  [%6.1f s] outcome: %s\n", s, outcome.c_str());
        } else {
            std::printf("  %s\n", line->c_str());
        }
        std::fflush(stdout);
    }
    auto status = child->terminate(10s);
    if (outcome.empty()) {
        std::cerr << "demo: `skillcell run` ended without an outcome ("
                  << (status ? status->describe() : status.error()) << "); see "
                  << work_.log("run").string() << "\n";
        return 1;
    }
    return status && status->success() ? 0 : 1;
}

std::unique_ptr<devices::WorldLink> DemoCell::connectWorld(const std::string& user) {
    std::string error;
    ClientUserOptions credentials;
    credentials.name = user;
    credentials.passwordFile = (dir() / (user + ".pw")).string();
    auto security = componentClientSecurity(*identity_, credentials, false, &error);
    if (!security) {
        std::cerr << "demo: " << error << "\n";
        return nullptr;
    }
    ua::ClientConfig config;
    config.applicationUri = "urn:skillcell:demo";
    config.sessionName = user;
    config.security = *security;
    auto world = devices::WorldLink::connect(worldUrl_, std::move(config));
    if (!world) {
        std::cerr << "demo: the " << user
                  << " cannot reach the world model: " << ua::statusName(world.status()) << "\n";
        return nullptr;
    }
    return std::move(*world);
}

bool DemoCell::swapParallelGripper() {
    auto world = connectWorld("engineer");
    if (!world) return false;
    for (const auto& [tool, dock] : {std::pair{"parallel", "shelf2"}, std::pair{"ag95", "dockP"}}) {
        if (const auto s = world->moveTool(tool, dock); s.isBad()) {
            std::cerr << "demo: moving " << tool << " to " << dock << ": " << ua::statusName(s)
                      << " (see " << work_.log("world").string() << ")\n";
            return false;
        }
        std::printf("  %s -> %s\n", tool, dock);
    }
    return true;
}

// The first status name in `text` ("BadCertificateUntrusted"), or the text's first line.
std::string statusIn(const std::string& text) {
    const auto at = text.find("Bad");
    if (at != std::string::npos) {
        auto end = at;
        while (end < text.size() && std::isalnum(static_cast<unsigned char>(text[end])) != 0) {
            ++end;
        }
        return text.substr(at, end - at);
    }
    return text.substr(0, text.find('\n'));
}

bool DemoCell::showSecurity() {
    bool held = true;
    auto show = [&held](const char* what, bool refused, const std::string& answer) {
        std::printf("  %-62s %s\n", what, refused ? answer.c_str() : "NOT REFUSED");
        held = held && refused;
    };
    // A role without the right: rearranging the tools is the engineer's task.
    auto world = connectWorld("operator");
    if (!world) return false;
    const auto moved = world->moveTool("vacuum", "dockV");
    show("the operator moving a tool (World.MoveTool, an engineer's task)", moved.isBad(),
         std::string(ua::statusName(moved)));
    // A client without security: no signature, no user.
    ua::ClientConfig plain;
    plain.applicationUri = "urn:skillcell:demo";
    auto anonymous = devices::WorldLink::connect(worldUrl_, std::move(plain));
    show("a client without security (SecurityPolicy None, anonymous)", !anonymous,
         anonymous ? std::string() : std::string(ua::statusName(anonymous.status())));
    // A certificate the cell's CA did not issue: `skillcell browse` with a PKI directory that
    // trusts the cell's CA (so that the refusal is the server's, not the client's) but makes
    // its own, self-signed certificate; with the operator's valid password.
    const fs::path strangerPki = dir() / "pki-stranger";
    std::error_code ec;
    std::string error;
    auto ca = ua::pki::loadCertificateAuthority(dir() / "ca", &error);
    if (!ca || ua::pki::installCertificateAuthority(*ca, strangerPki, &error).isBad()) {
        std::cerr << "demo: the stranger's trust list: " << error << "\n";
        return false;
    }
    auto stranger = process::runToCompletion(
        {skillcell_, "browse", worldUrl_, "--pki-dir", strangerPki.string(), "--user", "operator",
         "--password-file", (dir() / "operator.pw").string()},
        60s);
    // The server's refusal, not the client's: the world model keeps the certificate in its
    // rejected/ folder, for an operator to trust or not.
    const fs::path rejected = dir() / "pki-world" / "rejected" / "certs";
    const bool rejectedByTheServer = fs::is_directory(rejected, ec) && !fs::is_empty(rejected, ec);
    const bool strangerRefused = stranger && stranger->exitCode != 0 && rejectedByTheServer;
    show("a client whose certificate the cell's CA did not issue", strangerRefused,
         stranger
             ? statusIn(stranger->err + stranger->out) + " (kept in the world model's rejected/)"
             : stranger.error());
    return held;
}

void DemoCell::showWorld() {
    auto world = connectWorld("operator");
    if (!world) return;
    for (const char* box : {"boxA", "boxB"}) {
        const auto pose = world->objectPose(box);
        std::printf("  World/Objects/%s/Pose = %s\n", box,
                    pose ? ("3DFrame" + devices::describe(*pose)).c_str()
                         : ua::statusName(pose.status()).data());
    }
    const auto tool = world->mountedTool();
    std::printf("  World/MountedTool = %s\n",
                tool ? ("\"" + *tool + "\"").c_str() : ua::statusName(tool.status()).data());
}

std::string shortIri(const std::string& iri) {
    const auto cut = iri.find_last_of("/#");
    return cut == std::string::npos ? iri : iri.substr(cut + 1);
}

void DemoCell::showJournal() {
    auto journal = mes::Journal::open((dir() / "journal.sqlite").string());
    if (!journal) {
        std::cerr << "demo: " << journal.error() << "\n";
        return;
    }
    auto run = (*journal)->latestRun(kProcessIri);
    if (!run || !*run) {
        std::cerr << "demo: the journal has no run of the process" << (run ? "" : ": ")
                  << run.error() << "\n";
        return;
    }
    const auto& r = **run;
    std::printf("  run %lld: %s%s%s\n", static_cast<long long>(r.id), mes::toString(r.state),
                r.reason.empty() ? "" : " - ", r.reason.c_str());
    std::printf("  %4s %7s %-9s %-24s %-40s %7s\n", "step", "attempt", "state", "skill type",
                "component", "ms");
    for (const auto& s : r.steps) {
        std::printf("  %4d %7d %-9s %-24s %-40s %7lld\n", s.index, s.attempt,
                    mes::toString(s.state), shortIri(s.skillTypeIri).c_str(),
                    s.componentUri.c_str(),
                    static_cast<long long>(s.endedMs > 0 ? s.endedMs - s.startedMs : 0));
    }
}

double mean(const std::vector<double>& v) {
    return v.empty() ? 0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

void DemoCell::showDetectionTable(const std::vector<MeasuredComponent>& measured) const {
    std::printf("  %-16s %10s %8s %8s %5s %11s %10s\n", "component", "mean (ms)", "min", "max",
                "runs", "READY (ms)", "paper (ms)");
    for (const auto& m : measured) {
        if (m.samplesMs.empty()) continue;
        const auto [lo, hi] = std::minmax_element(m.samplesMs.begin(), m.samplesMs.end());
        std::printf("  %-16s %10.0f %8.0f %8.0f %5zu %11.0f %10.0f\n", m.label.c_str(),
                    mean(m.samplesMs), *lo, *hi, m.samplesMs.size(), mean(m.readyMs), m.paperMs);
    }
    std::printf(
        "  (from the start of the component's process to its skills in another component's "
        "SkillDetector; READY: until\n   the process listens, its part of it; gripper adapters "
        "with boot profile '%s'; the paper: PCs and\n   ESP32 boards on a real network)\n",
        o_.bootProfile.c_str());
}

void DemoCell::stopAll() {
    // The tool changer powers its tools off when it stops: it goes first; then the others, the
    // last started first.
    std::stable_partition(running_.begin(), running_.end(), [this](const CellProcess& p) {
        return p.name() == cell_.toolChanger->name;
    });
    for (auto& p : running_) {
        if (auto s = p.stop(10s); !s) std::cerr << "demo: " << s.error() << "\n";
    }
    running_.clear();
}

int DemoCell::run(const Interruption& interruption) {
    std::string error;
    if (!prepareSecurity(dir(), &error)) {
        std::cerr << "demo: the cell's security: " << error << "\n";
        return 1;
    }
    // The demo's own detector: a client of the cell like any component, with a certificate of
    // the cell CA, acting as "cell".
    identity_ = commission("demo", "urn:skillcell:demo", &error);
    const auto& identity = identity_;
    if (!identity) {
        std::cerr << "demo: " << error << "\n";
        return 1;
    }
    ClientUserOptions user;
    user.name = "cell";
    user.passwordFile = (dir() / "cell.pw").string();
    auto security = componentClientSecurity(*identity, user, false, &error);
    if (!security) {
        std::cerr << "demo: " << error << "\n";
        return 1;
    }
    skills::SkillDetectorConfig detector;
    detector.applicationUri = "urn:skillcell:demo";
    detector.security = *security;
    ua::mdns::MdnsConfig mdns;
    mdns.queryPeriod = 1s;
    clock_ = SkillDetectionClock::start(detector, mdns, &error);
    if (!clock_) {
        std::cerr << "demo: mDNS: " << error << "\n";
        return 1;
    }

    // Commissioning: every component gets its certificate from the cell CA before it first
    // starts, as a device gets it before it joins a plant. Else its first start would make
    // an RSA key and count that in its detection time.
    const std::string robot = cell_.robots.front().name;
    const std::string changer = cell_.toolChanger->name;
    const std::string pickplace = cell_.pickAndPlace->name;
    std::vector<std::pair<std::string, std::string>> components = {
        {"lds", "urn:skillcell:lds"},
        {"kb", "urn:skillcell:kb"},
        {"world", "urn:skillcell:device:world"},
        {changer, "urn:skillcell:device:kelvin-toolchanger"},
        {robot, "urn:skillcell:device:ur5"},
        {pickplace, "urn:skillcell:device:pick-and-place"},
        {"mes", "urn:skillcell:mes"}};
    // Every adapter model: --swap powers one that the cell file does not have in a dock.
    for (const auto& m : cell::adapterModelTable()) {
        components.emplace_back(std::string(m.command), std::string(m.applicationUri));
    }
    for (const auto& [name, uri] : components) {
        if (!commission(name, uri, &error)) {
            std::cerr << "demo: the certificate of " << name << ": " << error << "\n";
            return 1;
        }
    }

    std::printf("== the cell's infrastructure (each component a process; security on)\n");
    if (!startInfrastructure()) return 1;

    const std::string speedText = std::to_string(speed());
    const std::string detectionTimeout = std::to_string(o_.bootProfile == "none" ? 20'000 : 60'000);
    std::vector<MeasuredComponent> measured;
    // The tool table and the adapters the changer powers come from the cell file's tools.
    const auto powerCommand = [this](const cell::Tool& tool, const cell::AdapterModel& model) {
        return adapterCommand(std::string(model.command),
                              "--grip-offset " + cell::vectorArgument(tool.gripOffset));
    };
    std::vector<std::string> changerArgs = {
        "device", "toolchanger", "--world", worldUrl_, "--detection-timeout-ms", detectionTimeout};
    const auto table = cell::toolTableArguments(cell_, powerCommand);
    changerArgs.insert(changerArgs.end(), table.begin(), table.end());
    if (o_.swap) {
        const auto shelf = cell::toolTableArguments(swapShelf(), powerCommand);
        changerArgs.insert(changerArgs.end(), shelf.begin(), shelf.end());
    }
    // name, label, application URI, the paper's figure, stays up for the process; arguments.
    auto add = [&](const std::string& name, const std::string& label, const std::string& uri,
                   double paperMs, bool stays, std::vector<std::string> head) {
        MeasuredComponent m;
        m.name = name;
        m.label = label;
        m.applicationUri = uri;
        m.paperMs = paperMs;
        m.staysForTheProcess = stays;
        auto tail = componentArgs(m.name, /*actsAsCell=*/true);
        head.insert(head.end(), tail.begin(), tail.end());
        m.args = std::move(head);
        measured.push_back(std::move(m));
    };
    // Each tool's adapter, started on its own here (in the process, the changer powers it).
    for (const auto& tool : cell_.tools) {
        const cell::AdapterModel& model = *cell::findAdapterModel(tool.adapter);
        std::string label = std::string(model.command) + " adapter";
        double paperMs = 0;
        for (const auto& f : kAdapterFigures) {
            if (f.model == model.name) {
                label = f.label;
                paperMs = f.paperMs;
            }
        }
        add(std::string(model.command), label, std::string(model.applicationUri), paperMs, false,
            {"device", std::string(model.command), "--world", worldUrl_, "--speed", speedText,
             "--boot-profile", o_.bootProfile, "--grip-offset",
             cell::vectorArgument(tool.gripOffset)});
    }
    add(changer, "tool changer", "urn:skillcell:device:kelvin-toolchanger", 253, true, changerArgs);
    add(robot, "UR5", "urn:skillcell:device:ur5", 313, true,
        {"device", "ur5", "--world", worldUrl_, "--speed", speedText});
    add(pickplace, "pick-and-place", "urn:skillcell:device:pick-and-place", 211, true,
        {"device", "pickplace", "--world", worldUrl_, "--detection-timeout-ms", detectionTimeout});

    std::printf(
        "\n== detection: each component started %d times; ms from its start until the demo's "
        "SkillDetector has its skills\n",
        o_.runs);
    for (auto& m : measured) {
        if (!measure(m, interruption)) return interruption.requested() ? 130 : 1;
    }

    auto mes = startProcess(
        "mes",
        [&] {
            std::vector<std::string> a = {"mes", "--kb", sparqlUrl_, "--journal",
                                          (dir() / "journal.sqlite").string()};
            auto tail = componentArgs("mes", true);
            a.insert(a.end(), tail.begin(), tail.end());
            return a;
        }(),
        30s);
    if (!mes) {
        std::cerr << "demo: " << mes.error() << "\n";
        return 1;
    }
    mesUrl_ = mes->url();
    std::printf("  %-14s %s\n", "mes", mesUrl_.c_str());
    running_.push_back(std::move(*mes));

    std::printf("\n== the operator hands the MES the paper's process %s\n", kProcessIri);
    int outcome = runProcess(interruption);
    if (interruption.requested()) return 130;
    if (o_.swap && outcome == 0) {
        std::printf(
            "\n== Plug & Produce: an engineer takes the Robotiq 2F-85 out of dockP and puts a DH "
            "AG-95 in;\n   the operator runs the same process again (no change to it or to the "
            "MES)\n");
        const auto swapped = Clock::now();
        if (!swapParallelGripper()) return 1;
        outcome = runProcess(interruption);
        if (interruption.requested()) return 130;
        const std::string uri(cell::findAdapterModel("dh-ag95")->applicationUri);
        const auto ag95 = clock_->waitAppeared(uri, swapped, 0ms);
        std::printf(
            "  the parallel gripper of this run: %s\n",
            ag95 ? ("the DH AG-95 (" + uri + "), powered by the tool changer and detected").c_str()
                 : "NOT the DH AG-95: its skills never appeared");
        if (!ag95) outcome = 1;
    }

    std::printf("\n== the world model afterwards: where the boxes are, which tool is mounted\n");
    showWorld();
    std::printf("\n== the MES's journal\n");
    showJournal();
    std::printf("\n== security: what the cell refuses\n");
    if (!showSecurity()) outcome = 1;
    std::printf(
        "\n== time from starting a component to the detection of its skills by the others, beside "
        "the paper's (section VIII-C, averaged over 5 runs)\n");
    showDetectionTable(measured);

    if (o_.keepRunning) {
        std::printf(
            "\n== the cell keeps running for inspection (Ctrl-C stops it); work directory %s\n",
            dir().string().c_str());
        for (const auto& p : running_) {
            std::printf("  %-14s %s\n", p.name().c_str(), p.url().c_str());
        }
        std::printf("  operator: --pki-dir %s --user operator --password-file %s\n",
                    (dir() / "pki-operator").string().c_str(),
                    (dir() / "operator.pw").string().c_str());
        std::fflush(stdout);
        interruption.wait();
    }
    return outcome;
}

/// Where the running skillcell program is: every component is started from the same one.
std::string ownExecutable() {
    std::error_code ec;
    const auto path = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : path.string();
}

int runDemo(const DemoOptions& o) {
    // The network first, while this is the only thread: a namespace is per thread. Without
    // root, a network that is private already will do.
    if (const auto why = enterPrivateNetwork(); !why.empty() && !multicastOnlyOnLoopback()) {
        std::cerr << "demo: the cell's mDNS must stay off your network, in a private network "
                     "namespace, and "
                  << why << "\n";
        return 2;
    }
    const std::string skillcell = ownExecutable();
    if (skillcell.empty()) {
        std::cerr << "demo: cannot find the skillcell program (/proc/self/exe)\n";
        return 2;
    }
    // The cell file before anything starts: every problem in it, or nothing happens.
    const auto read = cell::readCellFile(o.cellFile);
    if (!read.cell) {
        for (const auto& p : read.problems) std::cerr << p.describe() << "\n";
        std::cerr << "demo: the cell file " << o.cellFile << " has " << read.problems.size()
                  << " problem(s); nothing started\n";
        return 2;
    }
    if (const auto lacks = whatTheDemoLacks(*read.cell); !lacks.empty()) {
        std::cerr << "demo: " << o.cellFile << ": the demo runs the paper's process, which needs "
                  << lacks << " in the cell file\n";
        return 2;
    }
    // --swap takes the parallel gripper out of the paper's dockP (swapParallelGripper).
    const auto& tools = read.cell->tools;
    if (o.swap && std::none_of(tools.begin(), tools.end(), [](const cell::Tool& t) {
            return t.name == "parallel" && t.dock == "dockP";
        })) {
        std::cerr << "demo: --swap needs the paper's tool 'parallel' in dock 'dockP'; "
                  << o.cellFile << " has no such tool\n";
        return 2;
    }
    std::string error;
    auto work = WorkDirectory::create(o.workDir, &error);
    if (!work) {
        std::cerr << "demo: " << error << "\n";
        return 2;
    }
    const Interruption interruption;  // before any thread: they inherit the mask
    std::printf("skillcell demo: the work cell of %s, every component a process (logs in %s)\n",
                o.cellFile.c_str(), (work->path() / "logs").string().c_str());
    int rc = 0;
    {
        DemoCell cell(o, *read.cell, *work, skillcell);
        rc = cell.run(interruption);
        if (rc != 0) std::printf("\n== stopping the cell\n");
    }
    if (rc != 0) {
        work->keep();
        std::cerr << "demo: failed; the logs stay in " << work->path().string() << "/logs\n";
    }
    return rc;
}

}  // namespace

Command addDemoCommand(CLI::App& app) {
    auto o = std::make_shared<DemoOptions>();
    auto* cmd = app.add_subcommand(
        "demo",
        "Run the paper's work cell on this machine: LDS, knowledge base, world model, UR5, tool "
        "changer with Robotiq and Schmalz adapters, pick-and-place and MES, each a process, "
        "security on, inside a private network namespace (needs root unless this is one "
        "already). Measures the time from starting each component to the detection of its "
        "skills, runs the paper's process through the MES with its progress, and prints the "
        "world state, the MES's journal and the detection times beside the paper's. Exit code "
        "0 when the process completed, 1 when it or the cell failed (the logs are kept), 2 "
        "when the demo cannot run here, 130 when interrupted.");
    cmd->add_option("--cell", o->cellFile,
                    "the cell file: the scene, the robot, the tools and their adapters "
                    "(docs/cells.md)")
        ->capture_default_str();
    cmd->add_option("--speed", o->speed,
                    "simulated seconds per real second for the robot and the grippers "
                    "(default: the cell file's robot speed)")
        ->check(CLI::Range(0.1, 1000.0));
    cmd->add_option("--boot-profile", o->bootProfile,
                    "how the gripper adapters start: tinyua, like the paper's Wi-Fi "
                    "microcontroller boards (8-10 s); none, at once")
        ->check(CLI::IsMember({"none", "tinyua"}))
        ->capture_default_str();
    cmd->add_option("--runs", o->runs, "starts of each component for the detection times")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    cmd->add_flag("--swap", o->swap,
                  "Plug & Produce: after the process, swap the Robotiq gripper in its dock for a "
                  "DH AG-95 and run the same process again");
    cmd->add_flag("--keep-running", o->keepRunning,
                  "keep the cell running after the process, for inspection, until Ctrl-C");
    cmd->add_option("--work-dir", o->workDir,
                    "directory for the cell's CA, users, PKI, KB data, journal and logs (kept; "
                    "default: a new temporary one, removed unless the demo fails)");
    cmd->add_option("--process-timeout", o->processTimeoutSeconds,
                    "seconds the process may take before it is halted")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    return {cmd, [o] { return runDemo(*o); }};
}

}  // namespace skillcell::apps
