#pragma once
// The benchmarks' command lines, read by CLI11 as the skillcell binary's are: --help lists
// every option with its default, and a usage error exits 2 with CLI11's message.
#include <optional>

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

}  // namespace skillcell::bench
