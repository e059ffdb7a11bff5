#include "program.hpp"

#include <malloc.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include "common/command_line.hpp"

namespace skillcell::apps {
namespace {

// The command line's first two words after the global option (--log-level VALUE): each
// empty when there is none, or an option comes first (`--help`).
std::pair<std::string_view, std::string_view> firstWords(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view word = argv[i];
        if (word == "--log-level") {
            ++i;
            continue;
        }
        if (word.rfind("--log-level=", 0) == 0) continue;
        if (word.rfind('-', 0) == 0) return {};
        const std::string_view next = i + 1 < argc ? argv[i + 1] : "";
        return {word, next.rfind('-', 0) == 0 ? std::string_view{} : next};
    }
    return {};
}

}  // namespace

std::span<const Subcommand> componentSubcommands() {
    static constexpr std::array kComponents{
        Subcommand{"server", one<addServerCommand>},
        Subcommand{"lds", one<addLdsCommand>},
        Subcommand{"device", addDeviceCommands},
    };
    return kComponents;
}

int runProgram(int argc, char** argv, std::string_view description,
               std::span<const Subcommand> subcommands, std::string_view elsewhere) {
    // Blocks up to 8 MB come from the heap, not from a mapping of their own: glibc maps every
    // block above 128 kB afresh and unmaps it when it is freed, and the page faults of the
    // few such blocks of a start (a NodeSet's document, the address space's tables as they
    // grow) were 0.6 ms of the 15.5 ms to READY. An idle component's memory is the same either
    // way (4.1 MB anonymous); under the sanitizers this is a no-op.
    mallopt(M_MMAP_THRESHOLD, 8 * 1024 * 1024);
    CLI::App app{std::string(description)};
    app.require_subcommand(1);
    std::string logLevel = "info";
    app.add_option("--log-level", logLevel, "trace, debug, info, warn, error, off")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
        ->capture_default_str();

    // Only the subcommand named on the command line is built: building all of them (some
    // hundred CLI11 options) was 1.5 ms of every component's start, which counts in the time
    // a plugged component takes to be READY.
    std::vector<Command> commands;
    // Not a structured binding: clang 14 (clang-tidy's) cannot capture one in a lambda.
    const auto words = firstWords(argc, argv);
    const std::string_view word = words.first;
    const std::string_view next = words.second;
    const auto only = std::find_if(subcommands.begin(), subcommands.end(),
                                   [&](const Subcommand& s) { return s.name == word; });
    if (only != subcommands.end()) {
        commands = only->add(app, next);
    } else if (!word.empty()) {
        // Not one of ours: say which are, and where the others are (CLI11 would only say that
        // a subcommand is required).
        std::string names;
        for (const auto& s : subcommands)
            names += (names.empty() ? "" : ", ") + std::string(s.name);
        std::fprintf(stderr, "%s: no command '%.*s'; it has: %s%s%s\n",
                     std::filesystem::path(argv[0]).filename().c_str(),
                     static_cast<int>(word.size()), word.data(), names.c_str(),
                     elsewhere.empty() ? "" : "; ", std::string(elsewhere).c_str());
        return 2;
    } else {
        for (const auto& s : subcommands) {
            for (auto& c : s.add(app, {})) commands.push_back(std::move(c));
        }
    }

    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;

    // Logs go to stderr: stdout carries the commands' output (READY lines, browse trees).
    auto logger = spdlog::stderr_color_mt("skillcell");
    spdlog::set_default_logger(logger);
    spdlog::set_level(spdlog::level::from_str(logLevel));

    for (const auto& command : commands) {
        if (command.cli->parsed()) return command.run();
    }
    return 2;
}

}  // namespace skillcell::apps
