#pragma once
// Reading a command line with CLI11, the one way `skillcell` and the benchmarks answer it:
// --help exits 0; every usage error exits 2, the usual code that scripts (and `skillcell
// check`'s contract) expect, instead of CLI11's own 100+ codes.
#include <optional>

#include <CLI/CLI.hpp>

namespace skillcell {

/// Parses argv into `app`'s options. Nothing when the program is to go on; otherwise the exit
/// code, after CLI11 printed the help or the error.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    return std::nullopt;
}

}  // namespace skillcell
