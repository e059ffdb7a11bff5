#pragma once
// ChildProcess: another program run as a child of ours: the knowledge base's engines
// (virtuoso-t, isql-vt, Konclude), the demo's components, the tool changer's tool adapters.
// Their life is tied to ours: the kernel signals the child when the thread that started it
// dies (PR_SET_PDEATHSIG: SIGKILL, or SIGTERM for a child that should say goodbye), and we
// stop it when the object goes away. Waits are bounded and use a pidfd, so no polling
// interval decides how fast we notice an exit. The one launcher of the project's code.
#include <sys/types.h>

#include <csignal>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/expected.hpp"

namespace skillcell::process {

/// An owned file descriptor; closed on destruction.
class UniqueFd {
public:
    UniqueFd() = default;
    explicit UniqueFd(int fd) : fd_(fd) {}
    ~UniqueFd() { reset(); }
    UniqueFd(UniqueFd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
    UniqueFd& operator=(UniqueFd&& other) noexcept;
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;

    [[nodiscard]] int get() const { return fd_; }
    [[nodiscard]] bool valid() const { return fd_ >= 0; }
    void reset(int fd = -1);

private:
    int fd_ = -1;
};

/// Where one of the child's output streams goes.
struct OutputSink {
    enum class Kind { OurStderr, File, Capture, Discard };
    Kind kind = Kind::OurStderr;
    std::filesystem::path file;  // Kind::File: appended to, created if missing

    static OutputSink ourStderr() { return {}; }
    static OutputSink toFile(std::filesystem::path path) { return {Kind::File, std::move(path)}; }
    /// Into a string (captured()): drained only while someone waits, so for short runs.
    static OutputSink capture() { return {Kind::Capture, {}}; }
    static OutputSink discard() { return {Kind::Discard, {}}; }
};

struct ProcessOptions {
    std::filesystem::path workingDir;                         // empty: ours
    std::vector<std::pair<std::string, std::string>> envAdd;  // set in the child's environment
    OutputSink stdoutTo = OutputSink::ourStderr();  // never our stdout: it may be a protocol
    OutputSink stderrTo = OutputSink::ourStderr();
    /// What the kernel sends the child when the thread that started it ends: SIGKILL for an
    /// engine; SIGTERM for a child that must say goodbye on the network (a tool's adapter).
    int deathSignal = SIGKILL;
    /// Namespaces (open /proc/.../ns/* files, borrowed) the child enters before it runs: a
    /// component of a cell on a host of its own (apps/cell_hosts.hpp). Empty: ours.
    std::vector<int> namespaces;
    /// Added to the child's nice value (setpriority): a batch job, such as a reasoner's run,
    /// yields the cores to the latency-bound work of the cell while both want them.
    int niceness = 0;
};

/// Options for a child that reports on its stdout while it runs (a component's or a peer's
/// READY line, read with ChildProcess::readLine) and logs on its stderr: appended to `log`,
/// or to our stderr when `log` is empty.
[[nodiscard]] inline ProcessOptions reportingChild(const std::filesystem::path& log = {}) {
    ProcessOptions options;
    options.stdoutTo = OutputSink::capture();
    if (!log.empty()) options.stderrTo = OutputSink::toFile(log);
    return options;
}

/// The executable `program` names: as given when it has a '/', else the first match in PATH;
/// empty when there is none.
[[nodiscard]] std::string findInPath(const std::string& program);

/// How a process ended: an exit code, or the signal that ended it.
struct ExitStatus {
    int code = -1;   // exit code; -1 when a signal ended the process
    int signal = 0;  // the terminating signal; 0 when it exited

    [[nodiscard]] bool success() const { return code == 0; }
    [[nodiscard]] std::string describe() const;
    friend bool operator==(const ExitStatus&, const ExitStatus&) = default;
};

class ChildProcess {
public:
    using Duration = std::chrono::milliseconds;

    /// Starts argv[0] (searched in PATH when it has no '/') with stdin from /dev/null. Fails
    /// with the program's name and the reason when it cannot be executed.
    static Expected<ChildProcess> start(const std::vector<std::string>& argv,
                                        const ProcessOptions& options = {});

    ChildProcess(ChildProcess&& other) noexcept;
    ChildProcess& operator=(ChildProcess&& other) noexcept;
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;
    /// A process still running is terminated (SIGTERM, then SIGKILL after 5 s).
    ~ChildProcess();

    [[nodiscard]] pid_t pid() const { return pid_; }
    [[nodiscard]] const std::string& name() const { return name_; }
    /// True until the process has ended (reaps it when it has).
    [[nodiscard]] bool running();
    /// A descriptor that poll() reports readable when the process ends (its pidfd), for a
    /// supervisor that waits for many at once; -1 on a kernel without pidfd_open.
    [[nodiscard]] int exitFd() const { return pidfd_.get(); }
    /// Waits at most `timeout` for the end; fails (naming the program) if it is still running.
    Expected<ExitStatus> wait(Duration timeout);
    /// SIGTERM, at most `grace` to end, then SIGKILL.
    Expected<ExitStatus> terminate(Duration grace);
    /// SIGKILL and reap: the crash a supervisor must survive.
    Expected<ExitStatus> kill();

    /// The next line the child wrote to a captured stdout (OutputSink::capture()), without
    /// its '\n', taken out of capturedStdout(): for children that report on stdout while they
    /// run (a component's READY line). Nothing when no whole line came within `timeout` or
    /// the child closed its stdout.
    [[nodiscard]] std::optional<std::string> readLine(Duration timeout);

    /// Output captured so far (OutputSink::capture()); complete once wait() has succeeded.
    [[nodiscard]] const std::string& capturedStdout() const { return out_; }
    [[nodiscard]] const std::string& capturedStderr() const { return err_; }

private:
    ChildProcess() = default;
    void drainCaptured();
    bool reap(bool block);
    void release();

    pid_t pid_ = -1;
    std::string name_;  // for messages: the program's file name
    UniqueFd pidfd_;    // invalid: kernel without pidfd_open, wait by polling
    UniqueFd outPipe_;  // capture pipes, read ends, non-blocking
    UniqueFd errPipe_;
    std::string out_;
    std::string err_;
    std::optional<ExitStatus> status_;
};

/// strerror's text for `err`, for messages.
[[nodiscard]] std::string errnoText(int err);
/// The last `max` characters of a program's output, marked as cut when they are not all.
[[nodiscard]] std::string tail(const std::string& text, std::size_t max = 2000);

/// What a short tool printed and how it ended.
struct RunResult {
    int exitCode = 0;
    std::string out;
    std::string err;
};

/// Runs a short tool to its end with stdout and stderr captured; kills it after `timeout`.
/// A non-zero exit is a result (the caller knows what it means); death by a signal, a
/// timeout or a failure to start are errors.
Expected<RunResult> runToCompletion(const std::vector<std::string>& argv,
                                    std::chrono::milliseconds timeout, ProcessOptions options = {});

}  // namespace skillcell::process
