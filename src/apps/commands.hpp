#pragma once
// The subcommands of the `skillcell` program. Each adds itself to the CLI and returns the
// exit code when it was chosen.
#include <CLI/CLI.hpp>
#include <functional>
#include <string_view>
#include <vector>

namespace skillcell::apps {

struct Command {
    CLI::App* cli = nullptr;   // the subcommand, to ask whether it was chosen
    std::function<int()> run;  // its body; returns the process exit code
};

Command addServerCommand(CLI::App& app);
Command addBrowseCommand(CLI::App& app);
Command addLdsCommand(CLI::App& app);
Command addDiscoverCommand(CLI::App& app);
Command addSkillCommand(CLI::App& app);
Command addCheckCommand(CLI::App& app);
Command addDetectCommand(CLI::App& app);
Command addPkiCommand(CLI::App& app);
Command addUserCommand(CLI::App& app);
/// `skillcell nodeset2owl`: NodeSet2 files to OWL ontologies (src/kb/owl).
Command addNodeset2OwlCommand(CLI::App& app);
/// `skillcell kb`: the knowledge base (src/kb).
Command addKbCommand(CLI::App& app);
/// `skillcell mes`: the semantic MES; `skillcell run`: hand it a process (src/mes).
Command addMesCommand(CLI::App& app);
Command addRunCommand(CLI::App& app);
Command addOrdersCommand(CLI::App& app);
/// `skillcell demo`: the paper's whole work cell, its process and its evaluation table.
Command addDemoCommand(CLI::App& app);
/// `skillcell dashboard`: the cell's live view in a browser (src/dashboard).
Command addDashboardCommand(CLI::App& app);
/// `skillcell cell check FILE`: a cell file read and checked (src/cell).
Command addCellCommand(CLI::App& app);
/// `skillcell process check|list`: processes checked against the skill models.
Command addProcessCommand(CLI::App& app);
/// `skillcell device <kind>`: one Command per kind (world, ur5, iiwa, robotiq, ag95, schmalz,
/// toolchanger, pickplace); only `kind`'s when it names one (the word after `device` on the
/// command line), every kind's otherwise (--help, a typo).
std::vector<Command> addDeviceCommands(CLI::App& app, std::string_view kind);

}  // namespace skillcell::apps
