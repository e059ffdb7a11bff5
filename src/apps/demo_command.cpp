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
//  2. the process: an operator hands the MES the cell's process ([demo] process of the cell
//     file; the paper's for examples/cells/paper.toml) (`skillcell run`, a client
//     like any other) and the demo shows its progress;
//  3. the evidence: the world model's boxes and mounted tool, the MES's journal, and the
//     detection times beside the paper's figures.
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "application_identity.hpp"
#include "cell/cell_file.hpp"
#include "cell/device_arguments.hpp"
#include "cell/paper_figures.hpp"
#include "cell_process.hpp"
#include "cell_runtime.hpp"
#include "cell_supervisor.hpp"
#include "client_security_options.hpp"
#include "commands.hpp"
#include "devices/common/frame.hpp"
#include "devices/world/world_link.hpp"
#include "interruption.hpp"
#include "mes/journal.hpp"
#include "mes/process_description.hpp"
#include "process/cpu_time.hpp"
#include "skill_detection_clock.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/server/user_database.hpp"
#include "work_directory.hpp"

namespace skillcell::apps {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

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

/// What the demo needs of a cell file: the process it names, run on a tool changer that moves
/// a robot, the pick-and-place composite, and the KB and MES; empty when the cell has them.
std::string whatTheDemoLacks(const cell::CellFile& c) {
    std::string lacks;
    auto need = [&](bool has, const char* what) {
        if (!has) lacks += (lacks.empty() ? "" : ", ") + std::string(what);
    };
    need(!c.demoProcess.empty(), "[demo] process (the process to run)");
    need(c.lds, "[lds]");
    need(c.kb.has_value(), "[kb]");
    need(c.mes.has_value(), "[mes]");
    need(c.robots.size() == 1, "one [[robot]]");
    need(c.toolChangers.size() == 1, "one [toolchanger]");
    need(!c.tools.empty(), "[[tool]]");
    need(c.pickAndPlaces.size() == 1, "one [pickplace]");
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
    shelf.tools = {{"ag95", "shelf1", "dh-ag95", {0, 0, 0.16}, {3.0, 3.5}, {}}};
    return shelf;
}

/// A component whose detection time the paper reports.
struct MeasuredComponent {
    ComponentLaunch launch;  // its name (logs, output), application URI and command line
    std::string label;       // as the table shows it
    double paperMs = 0;      // Profanter et al., section VIII-C
    bool staysForTheProcess = false;
    std::vector<double> samplesMs;  // start -> skills detected
    std::vector<double> readyMs;    // start -> READY (listening), the part the process takes
    int unsettledStarts = 0;        // starts into a cell that was not quiet within the bound
};

double milliseconds(Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

class DemoCell {
public:
    DemoCell(const DemoOptions& o, const cell::CellFile& cell, const CellHosts& hosts,
             WorkDirectory& work, const std::string& skillcell)
        : o_(o),
          cell_(cell),
          work_(work),
          runtime_(cell, work, skillcell, runtimeOptions(o, hosts)),
          skillcell_(skillcell) {}
    DemoCell(const DemoCell&) = delete;
    DemoCell& operator=(const DemoCell&) = delete;
    /// The tool changer first: it powers its tools off as it stops.
    ~DemoCell() { stopAll(); }

    int run(const Interruption& interruption);

private:
    static CellRuntimeOptions runtimeOptions(const DemoOptions& o, const CellHosts& hosts) {
        CellRuntimeOptions r;
        r.hosts = &hosts;
        r.speed = o.speed;
        r.bootProfile = o.bootProfile;
        r.selfName = "demo";
        r.keepPorts = true;  // a component restarted during the demo comes back where it was
        if (o.swap) r.shelf = swapShelf();
        return r;
    }
    [[nodiscard]] fs::path dir() const { return work_.path(); }
    /// Starts the component and keeps it running until the demo ends; says why not on stderr.
    bool keep(const std::string& name);
    bool startInfrastructure();
    bool measure(MeasuredComponent& m, const Interruption& interruption);
    /// Waits until the cell's processes are quiet; false when they were not within the bound.
    bool waitForQuietCell(const Interruption& interruption) const;
    /// `onProgress` hears each PROGRESS line as it comes (the --swap during a run).
    int runProcess(const Interruption& interruption,
                   const std::function<void(const std::string&)>& onProgress = {});
    /// A session with the world model as `user` (its password file in the work directory),
    /// with the demo's certificate, reading `robot`'s flange; nullptr after saying why on
    /// stderr.
    std::unique_ptr<devices::WorldLink> connectWorld(const std::string& user,
                                                     const std::string& robot = {});
    /// --swap: an engineer takes the Robotiq gripper out of its dock and puts a DH AG-95 in.
    bool swapParallelGripper();
    void showWorld();
    void showJournal();
    /// What the cell refuses: returns false when something it must refuse got through.
    bool showSecurity();
    void showDetectionTable(const std::vector<MeasuredComponent>& measured) const;
    void stopAll();

    const DemoOptions& o_;
    const cell::CellFile& cell_;
    WorkDirectory& work_;
    CellRuntime runtime_;
    std::string skillcell_;
    std::unique_ptr<SkillDetectionClock> clock_;
    /// The components that stay up for the process, watched and restarted as `cell up`
    /// does; the tool changer stops first.
    CellSupervisor supervisor_{runtime_};
};

bool DemoCell::keep(const std::string& name) {
    auto launch = runtime_.launch(name);
    if (!launch) {
        std::cerr << "demo: " << launch.error() << "\n";
        return false;
    }
    auto p = runtime_.start(*launch);
    if (!p) {
        std::cerr << "demo: " << p.error() << "\n";
        return false;
    }
    std::string extra;
    if (name == "kb") extra = "  SPARQL " + runtime_.sparqlUrl();
    if (name == "dashboard") extra = "  PAGE " + runtime_.dashboardUrl();
    std::printf("  %-14s %s%s\n", p->name().c_str(), p->url().c_str(), extra.c_str());
    supervisor_.adopt(std::move(*p));
    return true;
}

bool DemoCell::startInfrastructure() {
    if (!keep("lds") || !keep("kb") || !keep("world")) return false;
    if (!cell_.dashboard) return true;
    // First of the rest, so that its page shows every component arrive.
    if (!keep("dashboard")) return false;
    std::printf("  the dashboard: log in as observer (password in %s) or operator\n",
                runtime_.passwordFile("observer").string().c_str());
    return true;
}

bool DemoCell::waitForQuietCell(const Interruption& interruption) const {
    // A component is plugged into a running cell, not into one still answering the unplug
    // of the run before (the knowledge base forgetting that component, the MES and the
    // dashboard dropping it): the clock of each run starts once the cell's processes (ours
    // and theirs, Virtuoso included) have together used under a tenth of a core over a
    // sampling window. The window is how idleness is measured, not a wait for an event.
    constexpr auto kWindow = std::chrono::milliseconds(50);
    constexpr auto kQuiet = std::chrono::microseconds(5000);  // 10 % of one core per window
    constexpr auto kBound = std::chrono::seconds(3);
    const pid_t self = ::getpid();
    // Each process's CPU with what its reaped children used (the knowledge base's reasoner
    // runs for a fraction of a window and is gone): a window's work is the growth of each
    // process seen at both ends, and all of one that appeared. One that ended took its time
    // with it, but not what its parent reaped.
    const auto cellCpu = [self] {
        std::map<pid_t, std::chrono::nanoseconds> cpu;
        for (const pid_t pid : process::descendantsOf(self)) {
            cpu[pid] = process::cpuTimeWithReapedChildren(pid);
        }
        return cpu;
    };
    const auto deadline = Clock::now() + kBound;
    auto before = cellCpu();
    while (Clock::now() < deadline && !interruption.requested()) {
        std::this_thread::sleep_for(kWindow);
        auto now = cellCpu();
        std::chrono::nanoseconds used{0};
        for (const auto& [pid, cpu] : now) {
            const auto it = before.find(pid);
            used += it == before.end() ? cpu : std::max(cpu - it->second, decltype(cpu){0});
        }
        if (used < kQuiet) return true;
        before = std::move(now);
    }
    return false;
}

bool DemoCell::measure(MeasuredComponent& m, const Interruption& interruption) {
    std::printf("  %-16s", m.label.c_str());
    std::fflush(stdout);
    for (int run = 1; run <= o_.runs; ++run) {
        if (interruption.requested()) return false;
        if (!waitForQuietCell(interruption)) ++m.unsettledStarts;
        const auto t0 = Clock::now();
        auto p = runtime_.start(m.launch);
        if (!p) {
            std::printf("\n");
            std::cerr << "demo: " << p.error() << "\n";
            return false;
        }
        m.readyMs.push_back(milliseconds(Clock::now() - t0));
        const auto detected = clock_->waitAppeared(m.launch.applicationUri, t0, 60s);
        if (!detected) {
            std::printf("\n");
            std::cerr << "demo: the skills of " << m.launch.name
                      << " were not detected within 60 s of its start; see "
                      << work_.log(m.launch.name).string() << "\n";
            return false;
        }
        m.samplesMs.push_back(milliseconds(*detected - t0));
        std::printf(" %8.0f", m.samplesMs.back());
        std::fflush(stdout);
        if (m.staysForTheProcess && run == o_.runs) {
            supervisor_.adopt(std::move(*p));
            break;
        }
        if (auto s = p->stop(10s); !s || !s->success()) {
            std::printf("\n");
            std::cerr << "demo: " << m.launch.name << " did not stop cleanly ("
                      << (s ? s->describe() : s.error()) << "); see "
                      << work_.log(m.launch.name).string() << "\n";
            return false;
        }
        // The next start must be detected afresh: its skills must have left first.
        if (!clock_->waitGone(m.launch.applicationUri, 30s)) {
            std::printf("\n");
            std::cerr << "demo: the skills of " << m.launch.name
                      << " were still listed 30 s after it "
                      << "stopped\n";
            return false;
        }
    }
    std::printf("  ms\n");
    return true;
}

int DemoCell::runProcess(const Interruption& interruption,
                         const std::function<void(const std::string&)>& onProgress) {
    std::vector<std::string> argv = {skillcell_,
                                     "run",
                                     cell_.demoProcess,
                                     "--mes",
                                     runtime_.endpoint("mes"),
                                     "--pki-dir",
                                     runtime_.pkiDir("operator").string(),
                                     "--user",
                                     "operator",
                                     "--password-file",
                                     runtime_.passwordFile("operator").string(),
                                     "--timeout",
                                     std::to_string(o_.processTimeoutSeconds)};
    process::ProcessOptions options = process::reportingChild(work_.log("run"));
    options.envAdd = runtime_.environment();
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
        supervisor_.check();  // a component that died during the process is restarted
        auto line = child->readLine(1s);
        if (!line) {
            if (!child->running()) break;
            continue;
        }
        const double s = milliseconds(Clock::now() - t0) / 1000;
        if (line->starts_with("PROGRESS ")) {
            std::printf("  [%6.1f s] %s\n", s, line->substr(9).c_str());
            if (onProgress) onProgress(line->substr(9));
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

std::unique_ptr<devices::WorldLink> DemoCell::connectWorld(const std::string& user,
                                                           const std::string& robot) {
    std::string error;
    ClientUserOptions credentials;
    credentials.name = user;
    credentials.passwordFile = runtime_.passwordFile(user).string();
    auto security = componentClientSecurity(runtime_.identity(), credentials, false, &error);
    if (!security) {
        std::cerr << "demo: " << error << "\n";
        return nullptr;
    }
    ua::ClientConfig config;
    config.applicationUri = "urn:skillcell:demo";
    config.sessionName = user;
    config.security = *security;
    auto world = devices::WorldLink::connect(runtime_.endpoint("world"), std::move(config), robot);
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
    auto anonymous = devices::WorldLink::connect(runtime_.endpoint("world"), std::move(plain));
    show("a client without security (SecurityPolicy None, anonymous)", !anonymous,
         anonymous ? std::string() : std::string(ua::statusName(anonymous.status())));
    // A certificate the cell's CA did not issue: `skillcell browse` with a PKI directory that
    // trusts the cell's CA (so that the refusal is the server's, not the client's) but makes
    // its own, self-signed certificate; with the operator's valid password.
    const fs::path strangerPki = dir() / "pki-stranger";
    std::error_code ec;
    std::string error;
    auto ca =
        ua::pki::loadCertificateAuthority(dir() / "ca", &error);  // generated: see whatTheDemoLacks
    if (!ca || ua::pki::installCertificateAuthority(*ca, strangerPki, &error).isBad()) {
        std::cerr << "demo: the stranger's trust list: " << error << "\n";
        return false;
    }
    auto stranger = process::runToCompletion(
        {skillcell_, "browse", runtime_.endpoint("world"), "--pki-dir", strangerPki.string(),
         "--user", "operator", "--password-file", runtime_.passwordFile("operator").string()},
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
    for (const auto& object : cell_.objects) {
        const std::string& id = object.name;
        const auto pose = world->objectPose(id);
        std::printf("  World/Objects/%s/Pose = %s\n", id.c_str(),
                    pose ? ("3DFrame" + devices::describe(*pose)).c_str()
                         : ua::statusName(pose.status()).data());
        if (object.kind == cell::WorldObject::Kind::Fuse) {
            const auto seat = world->fuseSeat(id);
            if (!seat) {
                std::printf("    in a slot: %s\n", ua::statusName(seat.status()).data());
            } else if (seat->empty()) {
                std::printf("    in no slot\n");
            } else {
                std::printf("    seated in slot %s\n", seat->c_str());
            }
        }
        if (object.kind != cell::WorldObject::Kind::TerminalBlock) continue;
        const auto mount = world->railMount(id);
        if (!mount) {
            std::printf("    on a rail: %s\n", ua::statusName(mount.status()).data());
        } else if (!*mount) {
            std::printf("    on no rail\n");
        } else {
            std::printf("    on rail %s at %.1f mm\n", (*mount)->rail.c_str(),
                        (*mount)->position * 1000);
        }
    }
    for (const auto& robot : cell_.robots) {
        auto flange = connectWorld("operator", robot.name);
        if (!flange) return;
        const auto tool = flange->mountedTool();
        std::printf("  World/Robots/%s/MountedTool = %s\n", robot.name.c_str(),
                    tool ? ("\"" + *tool + "\"").c_str() : ua::statusName(tool.status()).data());
    }
}

void DemoCell::showJournal() {
    auto journal = mes::Journal::open(runtime_.journal().string());
    if (!journal) {
        std::cerr << "demo: " << journal.error() << "\n";
        return;
    }
    auto run = (*journal)->latestRun(cell_.demoProcess);
    if (!run || !*run) {
        std::cerr << "demo: the journal has no run of the process" << (run ? "" : ": ")
                  << run.error() << "\n";
        return;
    }
    const auto& r = **run;
    std::printf("  run %lld: %s%s%s\n", static_cast<long long>(r.id), mes::toString(r.state),
                r.reason.empty() ? "" : " - ", r.reason.c_str());
    std::printf("  %4s %7s %-9s %-28s %-40s %7s\n", "step", "attempt", "state", "skill type",
                "component", "ms");
    for (const auto& s : r.steps) {
        std::printf("  %4d %7d %-9s %-28s %-40s %7lld\n", s.index, s.attempt,
                    mes::toString(s.state), mes::shortName(s.skillTypeIri).c_str(),
                    s.componentUri.c_str(),
                    static_cast<long long>(s.endedMs > 0 ? s.endedMs - s.startedMs : 0));
    }
}

double mean(const std::vector<double>& v) {
    return v.empty() ? 0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// The median (of an even count, the lower middle: a time that was measured).
double median(std::vector<double> v) {
    if (v.empty()) return 0;
    const auto middle = v.begin() + static_cast<std::ptrdiff_t>((v.size() - 1) / 2);
    std::nth_element(v.begin(), middle, v.end());
    return *middle;
}

void DemoCell::showDetectionTable(const std::vector<MeasuredComponent>& measured) const {
    std::printf("  %-16s %9s %10s %8s %8s %5s %11s %10s\n", "component", "p50 (ms)", "mean", "min",
                "max", "runs", "READY (ms)", "paper (ms)");
    for (const auto& m : measured) {
        if (m.samplesMs.empty()) continue;
        const auto [lo, hi] = std::minmax_element(m.samplesMs.begin(), m.samplesMs.end());
        // A part the paper did not measure (the iiwa of its fuse demonstrator) has no figure.
        const std::string paper = m.paperMs > 0 ? fmt::format("{:.0f}", m.paperMs) : "-";
        std::printf("  %-16s %9.0f %10.0f %8.0f %8.0f %5zu %11.0f %10s\n", m.label.c_str(),
                    median(m.samplesMs), mean(m.samplesMs), *lo, *hi, m.samplesMs.size(),
                    mean(m.readyMs), paper.c_str());
    }
    std::printf(
        "  (from the start of the component's process to its skills in another component's "
        "SkillDetector; READY: until\n   the process listens, its part of it; each start into "
        "a quiet cell, its processes under a tenth of a core;\n   gripper adapters with boot "
        "profile '%s'; the paper: PCs and ESP32 boards on a real network)\n",
        o_.bootProfile.c_str());
    const int unsettled =
        std::accumulate(measured.begin(), measured.end(), 0,
                        [](int n, const MeasuredComponent& m) { return n + m.unsettledStarts; });
    if (unsettled > 0) {
        std::printf("  (%d of the starts began in a cell still busy after 3 s of waiting)\n",
                    unsettled);
    }
}

void DemoCell::stopAll() {
    supervisor_.stopAll();
}

int DemoCell::run(const Interruption& interruption) {
    std::string error;
    // The cell's CA and users, and every component's certificate (commissioning).
    if (!runtime_.prepare(&error)) {
        std::cerr << "demo: the cell's security: " << error << "\n";
        return 1;
    }
    // The demo's own detector: a client of the cell like any component, with a certificate of
    // the cell CA, acting as the cell's components do.
    const ClientUserOptions user = runtime_.componentUser();
    auto security = componentClientSecurity(runtime_.identity(), user, false, &error);
    if (!security) {
        std::cerr << "demo: " << error << "\n";
        return 1;
    }
    skills::SkillDetectorConfig detector;
    detector.applicationUri = runtime_.selfUri();
    detector.security = *security;
    ua::mdns::MdnsConfig mdns;
    mdns.queryPeriod = std::chrono::seconds(cell_.network.mdnsQueryPeriodSeconds);
    clock_ = SkillDetectionClock::start(detector, mdns, &error);
    if (!clock_) {
        std::cerr << "demo: mDNS: " << error << "\n";
        return 1;
    }
    supervisor_.showSkillsOf(*clock_);

    std::printf("== the cell's infrastructure (each component a process; security on)\n");
    if (!startInfrastructure()) return 1;

    std::vector<MeasuredComponent> measured;
    auto add = [&](kb::Expected<ComponentLaunch> launch, const std::string& label, double paperMs,
                   bool stays) {
        if (!launch) {
            std::cerr << "demo: " << launch.error() << "\n";
            return false;
        }
        MeasuredComponent m;
        m.launch = std::move(*launch);
        m.label = label;
        m.paperMs = paperMs;
        m.staysForTheProcess = stays;
        measured.push_back(std::move(m));
        return true;
    };
    // Each tool's adapter, started on its own here (in the process, the changer powers it).
    for (const auto& tool : cell_.tools) {
        const cell::AdapterModel& model = *cell::findAdapterModel(tool.adapter);
        const auto* paper = cell::paperDetection(model.applicationUri);
        const std::string label =
            paper != nullptr ? std::string(paper->label) : std::string(model.command) + " adapter";
        if (!add(runtime_.adapterLaunch(tool), label, paper != nullptr ? paper->ms : 0, false)) {
            return 1;
        }
    }
    // The paper's other parts, with its figures (cell/paper_figures.hpp).
    for (const std::string& name : {cell_.toolChangers.front().name, cell_.robots.front().name,
                                    cell_.pickAndPlaces.front().name}) {
        const auto* paper = cell::paperDetection(runtime_.applicationUri(name));
        if (!add(runtime_.launch(name), paper != nullptr ? std::string(paper->label) : name,
                 paper != nullptr ? paper->ms : 0, true)) {
            return 1;
        }
    }

    std::printf(
        "\n== detection: each component started %d times; ms from its start until the demo's "
        "SkillDetector has its skills\n",
        o_.runs);
    for (auto& m : measured) {
        if (!measure(m, interruption)) return interruption.requested() ? 130 : 1;
    }

    if (!keep("mes")) return 1;

    std::printf("\n== the operator hands the MES the cell's process %s\n",
                cell_.demoProcess.c_str());
    int outcome = runProcess(interruption);
    if (interruption.requested()) return 130;
    if (o_.swap && outcome == 0) {
        std::printf(
            "\n== Plug & Produce: the operator runs the same process again; once the MES has "
            "begun the run,\n   before the robot reaches dockP, an engineer takes the Robotiq "
            "2F-85 out of dockP and puts a\n   DH AG-95 in (no change to the process or to the "
            "MES): step 1 mounts the AG-95, step 2 picks with it\n");
        auto swapped = Clock::now();
        bool swappedOk = false;
        bool swapDone = false;
        // Once, at the run's first progress (the MES reads the process and checks the cell):
        // the order is under way, and the tool change of step 1 has not reached dockP.
        auto swapDuringTheRun = [&](const std::string& progress) {
            if (swapDone || !progress.starts_with("step 0/")) return;
            swapDone = true;
            swapped = Clock::now();
            std::printf("  -- the swap, the run under way:\n");
            swappedOk = swapParallelGripper();
        };
        outcome = runProcess(interruption, swapDuringTheRun);
        if (interruption.requested()) return 130;
        if (!swapDone || !swappedOk) {
            std::cerr << "demo: the gripper was not swapped during the run\n";
            return 1;
        }
        const std::string uri(cell::findAdapterModel("dh-ag95")->applicationUri);
        const auto ag95 = clock_->waitAppeared(uri, swapped, 0ms);
        std::printf(
            "  the parallel gripper of this run: %s\n",
            ag95 ? ("the DH AG-95 (" + uri + "), powered by the tool changer and detected").c_str()
                 : "NOT the DH AG-95: its skills never appeared");
        if (!ag95) outcome = 1;
    }

    std::printf("\n== the world model afterwards: where the objects are, which tool is mounted\n");
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
        for (const auto& name : runtime_.components()) {
            std::printf("  %-14s %s\n", name.c_str(), runtime_.endpoint(name).c_str());
        }
        std::printf("  operator: --pki-dir %s --user operator --password-file %s\n",
                    runtime_.pkiDir("operator").string().c_str(),
                    runtime_.passwordFile("operator").string().c_str());
        std::fflush(stdout);
        // Supervised as `cell up` supervises, and reachable by `cell status --work-dir`.
        if (!supervisor_.listen() || supervisor_.supervise(interruption) != 0) outcome = 1;
    }
    return outcome;
}

int runDemo(const DemoOptions& o) {
    const std::string skillcell = skillcellProgram();
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
        std::cerr << "demo: " << o.cellFile << ": the demo runs the cell's process, which needs "
                  << lacks << " in the cell file\n";
        return 2;
    }
    // The network next, while this is the only thread: a namespace is per thread.
    const auto hosts = enterCellNetwork(*read.cell);
    if (!hosts) {
        std::cerr << "demo: " << hosts.error() << "\n";
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
    auto work = WorkDirectory::create(o.workDir, "skillcell-demo", &error);
    if (!work) {
        std::cerr << "demo: " << error << "\n";
        return 2;
    }
    const Interruption interruption;  // before any thread: they inherit the mask
    std::printf("skillcell demo: the work cell of %s, every component a process (logs in %s)\n",
                o.cellFile.c_str(), (work->path() / "logs").string().c_str());
    int rc = 0;
    {
        DemoCell cell(o, *read.cell, *hosts, *work, skillcell);
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
        "skills, runs the cell's process ([demo] process) through the MES with its progress, and "
        "prints the "
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
                  "Plug & Produce: run the process a second time, and once that run is under "
                  "way, swap the Robotiq gripper in its dock for a DH AG-95: the run mounts the "
                  "AG-95 and picks with it, with no change to the process or the MES");
    cmd->add_flag("--keep-running", o->keepRunning,
                  "keep the cell running after the process, supervised, for inspection, until "
                  "Ctrl-C or `skillcell cell down --work-dir DIR` (`cell status --work-dir "
                  "DIR` shows it)");
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
