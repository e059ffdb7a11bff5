#pragma once
// Options that several benchmarks share; each reads its command line with
// skillcell::parseCommandLine (common/command_line.hpp), as the skillcell binary does.
#include <string>

#include <CLI/CLI.hpp>

#include "common/command_line.hpp"

namespace skillcell::bench {

/// What the benchmarks that start and stop `skillcell server` processes share (discovery,
/// skill detection): how many, how many of them are killed instead of stopped, the TTL they
/// announce, and the binary.
struct ProcessRun {
    int count = 30;
    int killed = 3;
    int ttl = 2;
    std::string skillcell;
};

inline void addProcessRunOptions(CLI::App& app, ProcessRun& run) {
    app.add_option("--count", run.count, "processes started and stopped")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--killed", run.killed, "of them, how many are killed instead of stopped")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--ttl", run.ttl, "the TTL they announce, in seconds")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--skillcell", run.skillcell,
                   "the program the components run (skillcell-component, or skillcell)")
        ->capture_default_str();
}

}  // namespace skillcell::bench
