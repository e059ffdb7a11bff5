#pragma once
// ChildProcess: a helper program (the node-opcua peer, a node benchmark client) started
// with posix_spawn, its stdout on a pipe that is read line by line with a bounded wait, and
// stopped with SIGTERM, then SIGKILL, when it outlives its grace period. The destructor
// stops a child that is still running, so a failing test or benchmark never leaks one.
//
// Shared by bench/ and tests/interop/ (compiled into both); it depends on POSIX only.
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace skillcell::bench {

class ChildProcess {
public:
    /// Starts argv[0] (looked up in PATH when it has no '/'). stdin is /dev/null, stdout a
    /// pipe read by readLine(), stderr goes to `stderrPath` (created/truncated) or, when
    /// empty, is inherited. Throws std::runtime_error when the program cannot be started.
    explicit ChildProcess(const std::vector<std::string>& argv, const std::string& stderrPath = {});
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;
    /// stop() with a 5 s grace period when the child still runs.
    ~ChildProcess();

    /// The next line of the child's stdout (without '\n'); std::nullopt when the child
    /// closed stdout (exited) or no full line arrived within `timeout`.
    std::optional<std::string> readLine(std::chrono::milliseconds timeout);
    /// Waits up to `timeout` for the child to exit; its wait status (see waitpid), or
    /// std::nullopt when it is still running.
    std::optional<int> waitExit(std::chrono::milliseconds timeout);
    /// SIGTERM, up to `grace` for the child to exit, then SIGKILL and reap. The wait
    /// status; repeated calls return the first one.
    int stop(std::chrono::milliseconds grace = std::chrono::seconds(5));

    [[nodiscard]] pid_t pid() const { return pid_; }
    [[nodiscard]] bool exited() const { return exitStatus_.has_value(); }

private:
    bool reap(bool block);

    pid_t pid_ = -1;
    int stdoutFd_ = -1;
    int pidFd_ = -1;  // pidfd_open(2) when the kernel has it: pollable exit
    std::string buffer_;
    bool stdoutEof_ = false;
    std::optional<int> exitStatus_;
};

/// The absolute path of `program` found in PATH, or empty.
[[nodiscard]] std::string findInPath(const std::string& program);

/// A human-readable form of a waitpid status ("exit 1", "signal 9").
[[nodiscard]] std::string describeWaitStatus(int status);

}  // namespace skillcell::bench
