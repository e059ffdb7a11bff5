#pragma once
// CellProcess: one component of a cell run by `skillcell demo`, as a child process of ours:
// the skillcell program with a subcommand (`lds`, `kb`, `device ur5`, ...), its log (stderr)
// in a file of its own, and what it reports on stdout before it serves ("SPARQL <url>", then
// "READY <url>"). It is stopped with SIGTERM when it goes (process::ChildProcess), so a
// demo that fails leaves no component behind.
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "kb/expected.hpp"
#include "process/child_process.hpp"

namespace skillcell::apps {

class CellProcess {
public:
    /// Starts `argv` (argv[0] the skillcell program) with `env` added to its environment and
    /// its stderr appended to `log`, and reads its stdout until the READY line, at most
    /// `timeout`. The error says why it did not come (and where the log is). It runs in the
    /// `namespaces` given (open fds; a host of its own, CellHosts), else in ours.
    [[nodiscard]] static kb::Expected<CellProcess> start(
        std::string name, const std::vector<std::string>& argv,
        const std::vector<std::pair<std::string, std::string>>& env,
        const std::filesystem::path& log, std::chrono::milliseconds timeout,
        const std::vector<int>& namespaces = {});

    [[nodiscard]] const std::string& name() const { return name_; }
    /// The endpoint of its READY line.
    [[nodiscard]] const std::string& url() const { return url_; }
    /// The value of a "KEY value" line it printed before READY ("SPARQL"), or empty.
    [[nodiscard]] std::string reported(const std::string& key) const;
    [[nodiscard]] pid_t pid() const { return process_.pid(); }

    /// True until it has ended (then reaped: ended() says how).
    [[nodiscard]] bool running() { return process_.running(); }
    /// How it ended, once running() is false.
    [[nodiscard]] kb::Expected<process::ExitStatus> ended() { return process_.wait({}); }
    /// Readable by poll() when it ends; -1 when the kernel cannot say (then poll running()).
    [[nodiscard]] int exitFd() const { return process_.exitFd(); }

    /// SIGTERM, at most `grace` to end, then SIGKILL; how it ended.
    kb::Expected<process::ExitStatus> stop(std::chrono::milliseconds grace);

private:
    CellProcess(std::string name, process::ChildProcess process)
        : name_(std::move(name)), process_(std::move(process)) {}

    std::string name_;
    process::ChildProcess process_;
    std::string url_;
    std::map<std::string, std::string> reported_;
};

}  // namespace skillcell::apps
