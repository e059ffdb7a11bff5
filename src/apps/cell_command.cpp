// `skillcell cell`: a whole work cell from its cell file (docs/cells.md).
//  - `cell check FILE` reads the file and lists every problem in it with file:line:column, or
//    what the cell has. Exit 0 when the file is good, 1 when it has problems.
//  - `cell up FILE` starts and supervises every component (CellSupervisor) until Ctrl-C or
//    `cell down`.
//  - `cell status [CELL]` and `cell down [CELL]` ask a running `cell up` through its control
//    socket, found in the cell's work directory.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cell/cell_file.hpp"
#include "cell_control.hpp"
#include "cell_runtime.hpp"
#include "cell_supervisor.hpp"
#include "commands.hpp"
#include "devices/common/frame.hpp"
#include "interruption.hpp"
#include "work_directory.hpp"

namespace skillcell::apps {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// Where running cells keep their work directories unless --work-dir says otherwise:
/// $SKILLCELL_STATE_DIR, else $XDG_STATE_HOME/skillcell/cells, else
/// ~/.local/state/skillcell/cells.
fs::path cellStateRoot() {
    if (const char* d = std::getenv("SKILLCELL_STATE_DIR"); d != nullptr && *d != '\0') return d;
    if (const char* d = std::getenv("XDG_STATE_HOME"); d != nullptr && *d != '\0') {
        return fs::path(d) / "skillcell" / "cells";
    }
    if (const char* h = std::getenv("HOME"); h != nullptr && *h != '\0') {
        return fs::path(h) / ".local" / "state" / "skillcell" / "cells";
    }
    return fs::temp_directory_path() / ("skillcell-cells-" + std::to_string(::getuid()));
}

/// The work directory of the cell `cell` names (a cell file, or a cell's name), or of the
/// only cell up when it is empty; `workDir` wins when given. Empty, with `error`, when
/// there is no such cell or several that could be meant.
fs::path cellDirectory(const std::string& cell, const std::string& workDir, std::string* error) {
    if (!workDir.empty()) return workDir;
    const fs::path root = cellStateRoot();
    std::error_code ec;
    if (!cell.empty()) {
        if (cell.ends_with(".toml") || fs::is_regular_file(cell, ec)) {
            auto read = cell::readCellFile(cell);
            if (!read.cell) {
                *error = read.problems.front().describe();
                return {};
            }
            return root / read.cell->name;
        }
        return root / cell;
    }
    std::vector<fs::path> up;
    for (const auto& entry : fs::directory_iterator(root, ec)) {
        if (fs::exists(controlSocketPath(entry.path()), ec)) up.push_back(entry.path());
    }
    if (up.size() == 1) return up.front();
    if (up.empty()) {
        *error = "no cell is up (none has a control socket in " + root.string() + ")";
    } else {
        *error = "several cells are up; name one:";
        for (const auto& p : up) *error += " " + p.filename().string();
    }
    return {};
}

struct UpOptions {
    std::string file;
    std::string workDir;
    double speed = 0;
    std::string bootProfile = "none";
    std::vector<std::string> hosts;  // COMPONENT=HOST
};

int cellUp(const UpOptions& o) {
    auto read = cell::readCellFile(o.file);
    if (!read.cell) {
        for (const auto& p : read.problems) std::cerr << p.describe() << "\n";
        std::cerr << "cell: " << read.problems.size() << " problem(s) in " << o.file
                  << "; nothing started\n";
        return 2;
    }
    for (const auto& placement : o.hosts) {
        const auto eq = placement.find('=');
        const std::string why =
            eq == std::string::npos
                ? "expected COMPONENT=HOST"
                : cell::placeOnHost(*read.cell, placement.substr(0, eq), placement.substr(eq + 1));
        if (!why.empty()) {
            std::cerr << "cell: --host " << placement << ": " << why << "; nothing started\n";
            return 2;
        }
    }
    const cell::CellFile& c = *read.cell;
    // Said at once: what comes before the first component (the network, the work directory,
    // the CA and a certificate per component) takes seconds, more on a loaded machine.
    std::printf("cell %s: preparing its network, work directory and certificates\n",
                c.name.c_str());
    std::fflush(stdout);
    // The network first, while this is the only thread: a namespace is per thread, and the
    // components inherit it.
    const bool privateNetwork = c.network.kind == cell::Network::Kind::PrivateNamespace;
    auto hosts = enterCellNetwork(c);
    if (!hosts) {
        std::cerr << "cell: " << hosts.error() << "\n";
        return 2;
    }
    const std::string skillcell = skillcellProgram();
    if (skillcell.empty()) {
        std::cerr << "cell: cannot find the skillcell program (/proc/self/exe)\n";
        return 2;
    }
    std::string error;
    const std::string dir = o.workDir.empty() ? (cellStateRoot() / c.name).string() : o.workDir;
    auto work = WorkDirectory::create(dir, "skillcell-cell", &error);
    if (!work) {
        std::cerr << "cell: " << error << "\n";
        return 2;
    }
    if (controlRequest(controlSocketPath(work->path()), "ping", 2s)) {
        std::cerr << "cell: a cell is up already in " << work->path().string()
                  << " (`skillcell cell down --work-dir " << work->path().string()
                  << "` stops it)\n";
        return 1;
    }
    const Interruption interruption;  // before any thread: they inherit the mask
    CellRuntimeOptions options;
    options.speed = o.speed;
    options.bootProfile = o.bootProfile;
    options.keepPorts = true;
    options.selfName = "cell-up";
    options.hosts = &*hosts;
    CellRuntime runtime(c, *work, skillcell, options);
    if (!runtime.prepare(&error)) {
        std::cerr << "cell: the cell's security: " << error << "\n";
        return 1;
    }
    std::printf("cell %s: starting %zu components (work directory %s)\n", c.name.c_str(),
                runtime.components().size(), work->path().string().c_str());
    std::fflush(stdout);
    CellSupervisor supervisor(runtime);
    if (!supervisor.start(interruption)) {
        std::printf("\ncell: stopping what started\n");
        supervisor.stopAll();
        if (interruption.requested()) return 130;
        std::cerr << "cell: " << c.name << " did not come up; the logs are in "
                  << (work->path() / "logs").string() << "\n";
        return 1;
    }
    std::printf("\ncell %s is up. Users (passwords in files readable by you only):\n",
                c.name.c_str());
    for (const auto& u : runtime.credentials()) {
        std::printf("  %-10s %-9s %s\n", u.user.c_str(), u.role.c_str(),
                    u.passwordFile.string().c_str());
    }
    if (!runtime.secure()) std::printf("  none: security is off (anonymous, no certificates)\n");
    if (runtime.componentUser().applicationCertificate) {
        std::printf(
            "The components act on each other as the users cell-NAME (Operator), by their "
            "certificates.\n");
    }
    if (!runtime.dashboardUrl().empty()) {
        std::printf("The dashboard: %s%s\n", runtime.dashboardUrl().c_str(),
                    runtime.secure() ? " (log in as one of these users; its certificate is issued "
                                       "by the cell CA)"
                                     : "");
    }
    const std::string enter =
        privateNetwork ? "nsenter --net=/proc/" + std::to_string(::getpid()) + "/ns/net " : "";
    if (privateNetwork) {
        std::printf(
            "The cell has a private network: its endpoints are reached from inside it, e.g.\n");
    } else {
        std::printf("For example:\n");
    }
    if (c.mes && runtime.secure()) {
        std::printf(
            "  %sskillcell run PROCESS-IRI --mes %s --pki-dir %s --user operator "
            "--password-file %s\n",
            enter.c_str(), runtime.endpoint("mes").c_str(),
            runtime.pkiDir("operator").string().c_str(),
            runtime.passwordFile("operator").string().c_str());
    }
    std::printf("  %sskillcell detect%s\n", enter.c_str(),
                runtime.secure() ? (" --pki-dir " + runtime.pkiDir("operator").string() +
                                    " --user observer --password-file " +
                                    runtime.passwordFile("observer").string())
                                       .c_str()
                                 : " --insecure");
    std::printf(
        "`skillcell cell status %s` shows the components and their skills; Ctrl-C or "
        "`skillcell cell down %s` stops the cell.\n",
        c.name.c_str(), c.name.c_str());
    std::fflush(stdout);
    return supervisor.supervise(interruption);
}

int cellStatus(const std::string& cellName, const std::string& workDir, bool json) {
    std::string error;
    const fs::path dir = cellDirectory(cellName, workDir, &error);
    if (dir.empty()) {
        std::cerr << "cell status: " << error << "\n";
        return 2;
    }
    auto answer = controlRequest(controlSocketPath(dir), "status", 10s);
    if (!answer) {
        std::cerr << "cell status: " << answer.error() << "\n";
        return 2;
    }
    if (json) {
        std::printf("%s\n", answer->c_str());
        return 0;
    }
    const auto j = nlohmann::json::parse(*answer, nullptr, false);
    if (j.is_discarded() || !j.contains("components")) {
        std::cerr << "cell status: the cell answered what is not a status: " << *answer << "\n";
        return 2;
    }
    std::printf("cell %s (%s), supervisor pid %d, work directory %s\n", j.value("cell", "").c_str(),
                j.value("file", "").c_str(), j.value("supervisor", 0),
                j.value("workDirectory", "").c_str());
    std::printf("  %-34s %-10s %7s %8s  %s\n", "component", "state", "pid", "restarts", "endpoint");
    bool allUp = true;
    for (const auto& e : j["components"]) {
        const std::string state = e.value("state", "");
        allUp = allUp && (state == "up" || state == "detected");
        const std::string host = e.contains("host") ? "  on host " + e.value("host", "") +
                                                          " (link " + e.value("link", "") + ")"
                                                    : std::string();
        std::printf("  %-34s %-10s %7d %8d  %s%s\n", e.value("name", "").c_str(), state.c_str(),
                    e.value("pid", 0), e.value("restarts", 0), e.value("endpoint", "").c_str(),
                    host.c_str());
        if (!e.value("lastEnd", "").empty() && state != "up") {
            std::printf("      last end: %s; see %s\n", e.value("lastEnd", "").c_str(),
                        e.value("log", "").c_str());
        }
        for (const auto& s : e["skills"]) {
            std::printf("      skill %-30s %s\n", s.value("path", "").c_str(),
                        s.value("type", "").c_str());
        }
    }
    return allUp ? 0 : 1;
}

int cellDown(const std::string& cellName, const std::string& workDir) {
    std::string error;
    const fs::path dir = cellDirectory(cellName, workDir, &error);
    if (dir.empty()) {
        std::cerr << "cell down: " << error << "\n";
        return 2;
    }
    // Every component has 10 s to say goodbye and end.
    auto answer = controlRequest(controlSocketPath(dir), "down", 180s);
    if (!answer) {
        std::cerr << "cell down: " << answer.error() << "\n";
        return 2;
    }
    std::printf("cell in %s stopped\n", dir.string().c_str());
    return 0;
}

/// What the cell consists of, one line per part, in the order `cell up` would start them.
void printSummary(const cell::CellFile& c) {
    std::printf("cell %s (%s)\n", c.name.c_str(), c.path.string().c_str());
    const bool host = c.network.kind == cell::Network::Kind::Host;
    std::string network = host ? "host" : "a private network namespace";
    if (host && !c.network.interfaces.empty()) {
        network += ", interfaces";
        for (const auto& i : c.network.interfaces) network += " " + i;
    }
    std::printf("  network:   %s; mDNS TTL %d s, longest query interval %d s\n", network.c_str(),
                c.network.mdnsTtlSeconds, c.network.mdnsQueryPeriodSeconds);
    if (!c.security.enabled) {
        std::printf("  security:  off (no certificates, no users: for tests on loopback)\n");
    } else {
        std::printf("  security:  CA %s; users %s\n",
                    c.security.ca.empty() ? "generated" : c.security.ca.string().c_str(),
                    c.security.users.empty() ? "generated (operator, engineer, observer)"
                                             : c.security.users.string().c_str());
    }
    // One line per component: its name, then what it is.
    const auto component = [](const std::string& name, const std::string& what) {
        std::printf("  %-13s %s\n", name.c_str(), what.c_str());
    };
    if (c.lds) component("lds", "local discovery server (LDS-ME)");
    if (c.kb) {
        component("kb", c.kb->sparqlUrl.empty() ? "knowledge base, with its own Virtuoso"
                                                : "knowledge base, store " + c.kb->sparqlUrl);
        for (const auto& p : c.kb->processes) std::printf("    process  %s\n", p.string().c_str());
    }
    if (c.mes) {
        component("mes",
                  "semantic MES, step timeout " + std::to_string(c.mes->stepTimeoutMs) + " ms");
    }
    if (!c.docks.empty() || !c.objects.empty() || !c.rails.empty() || !c.fuseSlots.empty()) {
        component("world", "world model");
    }
    for (const auto& d : c.docks) {
        std::printf("    dock     %-12s %s\n", d.name.c_str(), devices::describe(d.pose).c_str());
    }
    for (const auto& r : c.rails) {
        std::printf("    rail     %-12s TS35, %.1f mm long from %s\n", r.name.c_str(),
                    r.length * 1000, devices::describe(r.pose).c_str());
    }
    for (const auto& f : c.fuseSlots) {
        std::printf("    slot     %-12s ATO fuse slot at %s%s\n", f.name.c_str(),
                    devices::describe(f.pose).c_str(),
                    f.misalignment != std::array<double, 3>{} ? " (made out of tolerance)" : "");
    }
    for (const auto& o : c.objects) {
        char mass[32] = "";
        if (o.mass) std::snprintf(mass, sizeof mass, ", %g kg", *o.mass);
        const char* kind = o.kind == cell::WorldObject::Kind::TerminalBlock ? "block"
                           : o.kind == cell::WorldObject::Kind::Fuse        ? "fuse"
                                                                            : "object";
        std::printf("    %-8s %-12s %.4g x %.4g x %.4g m%s at %s\n", kind, o.name.c_str(),
                    o.size[0], o.size[1], o.size[2], mass, devices::describe(o.pose).c_str());
    }
    for (const auto& r : c.robots) {
        char speed[32];
        std::snprintf(speed, sizeof speed, "%g", r.speed);
        component(r.name, "robot " + r.model + ", speed " + speed);
    }
    for (const auto& changer : c.toolChangers) {
        component(changer.name, "tool changer (" + changer.model + ") on " + changer.robot);
        for (const auto& t : c.tools) {
            if (t.changer != changer.name) continue;
            std::printf("    tool     %-12s in %s, adapter %s, pin %.2f-%.2f V\n", t.name.c_str(),
                        t.dock.c_str(), t.adapter.c_str(), t.pinVoltage[0], t.pinVoltage[1]);
        }
    }
    for (const auto& p : c.pickAndPlaces) component(p.name, "pick-and-place composite");
}

}  // namespace

Command addCellCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    CLI::App* cmd =
        app.add_subcommand("cell", "A whole work cell from its cell file (docs/cells.md)");
    cmd->require_subcommand(1);
    CLI::App* check = cmd->add_subcommand(
        "check",
        "Read a cell file and list every problem in it (FILE:LINE:COLUMN: what is wrong), or "
        "what the cell consists of. Exit 0 when it is good, 1 when it has problems.");
    check->add_option("FILE", *file, "the cell file (TOML), e.g. examples/cells/paper.toml")
        ->required();

    auto up = std::make_shared<UpOptions>();
    CLI::App* upCmd = cmd->add_subcommand(
        "up",
        "Start every component of a cell file and supervise them until Ctrl-C or `cell down`: "
        "a component that ends is reported with its log's last lines and restarted as its "
        "restart policy says. Prints the endpoints and the users. Exit 0 after a clean stop, 1 "
        "when the cell did not come up or a component was given up, 2 for a bad cell file or "
        "where the cell cannot run.");
    upCmd->add_option("FILE", up->file, "the cell file (TOML), e.g. examples/cells/paper.toml")
        ->required();
    upCmd->add_option("--work-dir", up->workDir,
                      "the cell's CA, users, PKI, KB data, journal, logs and control socket, "
                      "kept for the next start (default: $SKILLCELL_STATE_DIR/<cell name>, else "
                      "~/.local/state/skillcell/cells/<cell name>)");
    upCmd
        ->add_option("--speed", up->speed,
                     "simulated seconds per real second for robots and grippers (default: "
                     "each robot's speed in the cell file)")
        ->check(CLI::Range(0.1, 1000.0));
    upCmd
        ->add_option("--boot-profile", up->bootProfile,
                     "how gripper adapters start: none (at once) or tinyua (like the paper's "
                     "microcontroller boards, 8-10 s)")
        ->check(CLI::IsMember({"none", "tinyua"}))
        ->capture_default_str();
    upCmd->add_option("--host", up->hosts,
                      "COMPONENT=HOST: run a component on a host of its own, as its `host` key in "
                      "the cell file would (a network namespace beside the cell's, linked to it "
                      "by v-HOST; a private network only); repeatable");

    auto cellName = std::make_shared<std::string>();
    auto workDir = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    CLI::App* status = cmd->add_subcommand(
        "status",
        "Show each component of a running cell: up or down, its pid, restarts, endpoint and "
        "its skills as the cell detects them. Exit 0 when all are up, 1 when some are not, 2 "
        "when no cell answers.");
    CLI::App* down = cmd->add_subcommand(
        "down", "Stop a running cell (as Ctrl-C on its `cell up` does) and wait until it has.");
    for (CLI::App* sub : {status, down}) {
        sub->add_option("CELL", *cellName,
                        "the cell's name or its cell file (default: the only cell that is up)");
        sub->add_option("--work-dir", *workDir, "the work directory `cell up` was given");
    }
    status->add_flag("--json", *json, "print the status as JSON");
    return {cmd, [=] {
                if (upCmd->parsed()) return cellUp(*up);
                if (status->parsed()) return cellStatus(*cellName, *workDir, *json);
                if (down->parsed()) return cellDown(*cellName, *workDir);
                auto result = cell::readCellFile(*file);
                if (!result.cell) {
                    for (const auto& p : result.problems) {
                        std::fprintf(stderr, "%s\n", p.describe().c_str());
                    }
                    std::fprintf(stderr, "%zu problem%s; nothing would start\n",
                                 result.problems.size(), result.problems.size() == 1 ? "" : "s");
                    return 1;
                }
                printSummary(*result.cell);
                return 0;
            }};
}

}  // namespace skillcell::apps
