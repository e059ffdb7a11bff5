// skillcell-component: the subcommands a cell's components run (server, lds, device <kind>),
// the same code as in `skillcell`, in a program that links only what they need. A cell
// starts its components from it (cell_runtime.cpp: programFor).
#include "program.hpp"

int main(int argc, char** argv) {
    return skillcell::apps::runProgram(
        argc, argv,
        "skillcell-component: the components of a skillcell work cell (what `skillcell server`, "
        "`skillcell lds` and `skillcell device` run)",
        skillcell::apps::componentSubcommands(),
        "the other commands are skillcell's (`skillcell --help`)");
}
