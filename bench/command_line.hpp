#pragma once
// The benchmarks' command lines, read by CLI11 as the skillcell binary's are: --help lists
// every option with its default, and a usage error exits 2 with CLI11's message.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace skillcell::bench {

/// Parses argv into `app`'s options. Nothing when the benchmark is to run; otherwise the
/// exit code: 0 after --help, 2 for a usage error (as `skillcell` itself answers).
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    return std::nullopt;
}

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
    app.add_option("--skillcell", run.skillcell, "the skillcell binary")->capture_default_str();
}

}  // namespace skillcell::bench
