#pragma once
// NodePeer: node-opcua's server.js (tests/interop), started as the independent peer of an
// interop test or a benchmark, and its endpoint from its READY line.
#include <chrono>
#include <filesystem>
#include <string>

#include "common/expected.hpp"
#include "process/child_process.hpp"

namespace skillcell::test {

struct NodePeer {
    process::ChildProcess server;
    std::string url;
};

/// Starts `node server.js --port 0 [extra...]` from `interopDir`, its stderr appended to `log`
/// (ours when empty), and reads its READY line (node-opcua loads its standard nodeset first:
/// seconds). Fails with ErrorKind::Unavailable when node or node-opcua is not installed, and
/// with the reason when the server does not start.
inline Expected<NodePeer> startNodeServer(const std::filesystem::path& interopDir,
                                          const std::vector<std::string>& extra = {},
                                          const std::filesystem::path& log = {}) {
    using namespace std::chrono_literals;
    const auto modules = interopDir / "node_modules" / "node-opcua";
    if (process::findInPath("node").empty() || !std::filesystem::is_directory(modules)) {
        return Error{"node or " + modules.string() + " missing (npm ci in tests/interop)",
                     ErrorKind::Unavailable};
    }
    std::vector<std::string> argv{"node", (interopDir / "server.js").string(), "--port", "0"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    auto server = process::ChildProcess::start(argv, process::reportingChild(log));
    if (!server) return Error{server.error()};
    const auto ready = server->readLine(30s);
    if (!ready || !ready->starts_with("READY ")) {
        return Error{"server.js did not print READY within 30 s (got: '" +
                     ready.value_or("<nothing>") + "', " +
                     (server->running() ? "still running" : "it exited") +
                     (log.empty() ? std::string(")") : ", log: " + log.string() + ")")};
    }
    return NodePeer{std::move(*server), ready->substr(6)};
}

}  // namespace skillcell::test
