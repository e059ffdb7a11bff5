// `skillcell cell`: a whole work cell from its cell file (docs/cells.md). `cell check FILE`
// reads the file and lists every problem in it with file:line:column, or what the cell has.
// Exit 0 when the file is good, 1 when it has problems, 2 on usage errors.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "cell/cell_file.hpp"
#include "commands.hpp"
#include "devices/common/frame.hpp"

namespace skillcell::apps {
namespace {

/// What the cell consists of, one line per part, in the order `cell up` would start them.
void printSummary(const cell::CellFile& c) {
    std::printf("cell %s (%s)\n", c.name.c_str(), c.path.string().c_str());
    const bool host = c.network.kind == cell::Network::Kind::Host;
    std::string network = host ? "host" : "a private network namespace";
    if (host && !c.network.interfaces.empty()) {
        network += ", interfaces";
        for (const auto& i : c.network.interfaces) network += " " + i;
    }
    std::printf("  network:   %s; mDNS TTL %d s, query period %d s\n", network.c_str(),
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
    if (!c.docks.empty() || !c.objects.empty()) component("world", "world model");
    for (const auto& d : c.docks) {
        std::printf("    dock     %-12s %s\n", d.name.c_str(), devices::describe(d.pose).c_str());
    }
    for (const auto& o : c.objects) {
        std::printf("    object   %-12s %.3f x %.3f x %.3f m at %s\n", o.name.c_str(), o.size[0],
                    o.size[1], o.size[2], devices::describe(o.pose).c_str());
    }
    for (const auto& r : c.robots) {
        char speed[32];
        std::snprintf(speed, sizeof speed, "%g", r.speed);
        component(r.name, "robot " + r.model + ", speed " + speed);
    }
    if (c.toolChanger)
        component(c.toolChanger->name, "tool changer (" + c.toolChanger->model + ")");
    for (const auto& t : c.tools) {
        std::printf("    tool     %-12s in %s, adapter %s, pin %.2f-%.2f V\n", t.name.c_str(),
                    t.dock.c_str(), t.adapter.c_str(), t.pinVoltage[0], t.pinVoltage[1]);
    }
    if (c.pickAndPlace) component(c.pickAndPlace->name, "pick-and-place composite");
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
    return {cmd, [file] {
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
