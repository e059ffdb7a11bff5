// skillcell: one program, one subcommand per component and tool (server, lds, device <kind>,
// kb, mes, dashboard; browse, discover, skill, detect, run, cell, demo ...). Every component
// takes --port N for its OPC UA port. A cell starts its servers, LDS and devices from
// skillcell-component (component_main.cpp) when it is installed beside this program.
#include <array>

#include "program.hpp"

namespace {

using namespace skillcell::apps;

constexpr std::array kSubcommands{
    Subcommand{"server", one<addServerCommand>},
    Subcommand{"browse", one<addBrowseCommand>},
    Subcommand{"lds", one<addLdsCommand>},
    Subcommand{"discover", one<addDiscoverCommand>},
    Subcommand{"skill", one<addSkillCommand>},
    Subcommand{"check", one<addCheckCommand>},
    Subcommand{"detect", one<addDetectCommand>},
    Subcommand{"pki", one<addPkiCommand>},
    Subcommand{"user", one<addUserCommand>},
    Subcommand{"nodeset2owl", one<addNodeset2OwlCommand>},
    Subcommand{"kb", one<addKbCommand>},
    Subcommand{"mes", one<addMesCommand>},
    Subcommand{"run", one<addRunCommand>},
    Subcommand{"demo", one<addDemoCommand>},
    Subcommand{"cell", one<addCellCommand>},
    Subcommand{"process", one<addProcessCommand>},
    Subcommand{"dashboard", one<addDashboardCommand>},
    Subcommand{"orders", one<addOrdersCommand>},
    Subcommand{"device", addDeviceCommands},
};

}  // namespace

int main(int argc, char** argv) {
    return runProgram(argc, argv,
                      "skillcell: a Plug & Produce system for robot work cells built on OPC UA "
                      "skills",
                      kSubcommands);
}
