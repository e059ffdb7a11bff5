#pragma once
// What both programs do with a command line: `skillcell` (every subcommand) and
// `skillcell-component` (only what a cell's components run: server, lds, device), which
// links none of the libraries the others need (SQLite, cpp-httplib, toml++, serd), so that a
// component loads and relocates less at every start and maps less for as long as it runs.
#include <span>
#include <string_view>
#include <vector>

#include "commands.hpp"

namespace skillcell::apps {

/// A subcommand by the name it is invoked with, and what adds it (some add several). `add`
/// is given the command line's next word after the name (empty when there is none, or it is
/// an option), for subcommands that build only what it names.
struct Subcommand {
    std::string_view name;
    std::vector<Command> (*add)(CLI::App&, std::string_view next);
};

template <Command (*Add)(CLI::App&)>
std::vector<Command> one(CLI::App& app, std::string_view /*next*/) {
    return {Add(app)};
}

/// What a cell's components run (server, lds, device <kind>): skillcell-component's
/// subcommands, and the ones a cell starts from it (cell_runtime.cpp: programFor).
[[nodiscard]] std::span<const Subcommand> componentSubcommands();

/// Parses the command line against `subcommands`, sets up the log, runs the one chosen;
/// the process's exit code. A first word that names none of them exits 2 with the names,
/// and `elsewhere` (where the others are) when given.
int runProgram(int argc, char** argv, std::string_view description,
               std::span<const Subcommand> subcommands, std::string_view elsewhere = {});

}  // namespace skillcell::apps
