#include "process/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>

extern char** environ;  // NOLINT: POSIX

namespace skillcell::process {
namespace {

using Clock = std::chrono::steady_clock;

// After SIGKILL the kernel ends a process promptly unless it sits in uninterruptible I/O;
// beyond this we report rather than hang.
constexpr std::chrono::milliseconds kKillBound{5000};
constexpr std::chrono::milliseconds kDestructorGrace{5000};
// Only without pidfd (old kernels): how often a waiting caller looks again.
constexpr int kFallbackPollMs = 10;

/// The executable argv[0] names; as given when PATH has none, so that execve reports
/// ENOENT with the name the caller gave.
std::string resolveProgram(const std::string& program) {
    std::string found = findInPath(program);
    return found.empty() ? program : found;
}

std::vector<std::string> childEnvironment(const ProcessOptions& options) {
    std::vector<std::string> env;
    for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
        const std::string_view entry(*e);
        const auto name = entry.substr(0, entry.find('='));
        const bool overridden = std::any_of(options.envAdd.begin(), options.envAdd.end(),
                                            [&](const auto& kv) { return kv.first == name; });
        if (!overridden) env.emplace_back(entry);
    }
    for (const auto& [name, value] : options.envAdd) {
        std::string entry = name;
        entry += "=";
        entry += value;
        env.push_back(std::move(entry));
    }
    return env;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
    std::vector<char*> result;
    result.reserve(strings.size() + 1);
    for (auto& s : strings) result.push_back(s.data());
    result.push_back(nullptr);
    return result;
}

/// The parent's side of one output stream: what the child dup2()s, and the read end of a
/// capture pipe.
struct SinkFds {
    UniqueFd childEnd;  // invalid: leave the child's descriptor as it is
    UniqueFd readEnd;
};

Expected<SinkFds> openSink(const OutputSink& sink, int target) {
    SinkFds fds;
    switch (sink.kind) {
        case OutputSink::Kind::OurStderr:
            if (target != STDERR_FILENO)
                fds.childEnd.reset(::fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3));
            break;
        case OutputSink::Kind::File:
            fds.childEnd.reset(
                ::open(sink.file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644));
            if (!fds.childEnd.valid()) {
                return Error{"cannot open " + sink.file.string() + ": " + errnoText(errno)};
            }
            break;
        case OutputSink::Kind::Discard:
            fds.childEnd.reset(::open("/dev/null", O_WRONLY | O_CLOEXEC));
            break;
        case OutputSink::Kind::Capture: {
            std::array<int, 2> p{};
            if (::pipe2(p.data(), O_CLOEXEC) != 0) return Error{"pipe: " + errnoText(errno)};
            fds.readEnd.reset(p[0]);
            fds.childEnd.reset(p[1]);
            ::fcntl(p[0], F_SETFL, ::fcntl(p[0], F_GETFL) | O_NONBLOCK);
            break;
        }
    }
    return fds;
}

/// What a child that failed before exec writes back: the step and its errno.
struct ChildFailure {
    int step;
    int err;
};
enum ChildStep : int { kDeathSignal = 1, kRedirect, kChdir, kNamespace, kExec };

/// What the child needs, prepared before it starts: it may not allocate.
struct ChildSetup {
    pid_t parent;
    int deathSignal;
    int niceness;
    const std::vector<int>* namespaces;
    int reportFd;
    int stdinFd;
    int stdoutFd;
    int stderrFd;
    const char* cwd;
    const char* path;
    char* const* argv;
    char* const* envp;
};

/// The kernel's sigaction (not libc's, whose layout differs): the child resets dispositions
/// with the system call itself, so that no wrapper (a sanitizer's, which keeps a table in the
/// memory the child shares with us) records anything.
struct KernelSigaction {
    void (*handler)(int);
    unsigned long flags;
    void (*restorer)();
    std::uint64_t mask;
};

// The child runs on a stack of its own in our memory until it execs: its frames, the
// sanitizers' included, are small.
constexpr std::size_t kChildStackBytes = std::size_t{256} * 1024;

/// Reports why the child could not become the program, and ends it.
[[noreturn, gnu::no_sanitize_address]] void failChild(const ChildSetup& c, int step) {
    const ChildFailure failure{step, errno};
    [[maybe_unused]] const auto n = ::write(c.reportFd, &failure, sizeof failure);
    ::_exit(127);
}

/// The child, in our memory until it execs (clone with CLONE_VM | CLONE_VFORK): system calls
/// only, and it writes nothing of ours but errno, which the thread that started it, stopped
/// until the exec, does not read. Not instrumented by AddressSanitizer, whose bookkeeping
/// of stacks would see a stack it does not know (this one's) and warn in every child.
[[noreturn, gnu::no_sanitize_address]] void execChild(const ChildSetup& c) {
    // Our handlers first, while every signal is still blocked (the parent blocked them
    // around the clone): none may run here, on our memory. Blocked or ignored signals
    // survive exec; an engine must see SIGTERM and SIGPIPE.
    const KernelSigaction dfl{SIG_DFL, 0, nullptr, 0};
    for (int sig = 1; sig < NSIG; ++sig) {
        if (sig != SIGKILL && sig != SIGSTOP) {
            (void)::syscall(SYS_rt_sigaction, sig, &dfl, nullptr, sizeof dfl.mask);
        }
    }
    const std::uint64_t none = 0;
    (void)::syscall(SYS_rt_sigprocmask, SIG_SETMASK, &none, nullptr, sizeof none);
    // Dies with the thread that started it; the check closes the race with a parent that
    // died before prctl.
    if (::prctl(PR_SET_PDEATHSIG, c.deathSignal) != 0) failChild(c, kDeathSignal);
    if (::getppid() != c.parent) ::_exit(127);
    if (::dup2(c.stdinFd, STDIN_FILENO) < 0) failChild(c, kRedirect);
    if (c.stdoutFd >= 0 && ::dup2(c.stdoutFd, STDOUT_FILENO) < 0) failChild(c, kRedirect);
    if (c.stderrFd >= 0 && ::dup2(c.stderrFd, STDERR_FILENO) < 0) failChild(c, kRedirect);
    if (c.cwd != nullptr && ::chdir(c.cwd) != 0) failChild(c, kChdir);
    // Only ever raised, which needs no privilege; a kernel that refused would leave the
    // child at our priority, which is no reason not to run it.
    if (c.niceness > 0)
        (void)::setpriority(PRIO_PROCESS, 0, ::getpriority(PRIO_PROCESS, 0) + c.niceness);
    for (const int ns : *c.namespaces) {  // reads the vector only: no allocation
        if (::setns(ns, 0) != 0) failChild(c, kNamespace);
    }
    ::execve(c.path, c.argv, c.envp);
    failChild(c, kExec);
    ::_exit(127);  // not reached: failChild() exits
}

[[gnu::no_sanitize_address]] int childEntry(void* setup) {
    execChild(*static_cast<const ChildSetup*>(setup));
}

}  // namespace

std::string findInPath(const std::string& program) {
    if (program.empty()) return {};
    if (program.find('/') != std::string::npos) {
        return ::access(program.c_str(), X_OK) == 0 ? program : std::string();
    }
    const char* path = std::getenv("PATH");  // NOLINT(concurrency-mt-unsafe)
    std::string_view dirs = path != nullptr ? path : "/usr/local/bin:/usr/bin:/bin";
    while (!dirs.empty()) {
        const auto colon = dirs.find(':');
        const std::string dir(dirs.substr(0, colon));
        dirs = colon == std::string_view::npos ? std::string_view{} : dirs.substr(colon + 1);
        std::string candidate = dir.empty() ? std::string(".") : dir;
        candidate += "/";
        candidate += program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return {};
}

std::string errnoText(int err) {
    return std::strerror(err);  // NOLINT(concurrency-mt-unsafe)
}

std::string tail(const std::string& text, std::size_t max) {
    return text.size() <= max ? text : "..." + text.substr(text.size() - max);
}

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
    if (this != &other) reset(std::exchange(other.fd_, -1));
    return *this;
}

void UniqueFd::reset(int fd) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
}

std::string ExitStatus::describe() const {
    if (signal != 0) {
        const char* abbrev = ::sigabbrev_np(signal);
        return "killed by signal " + std::to_string(signal) +
               (abbrev != nullptr ? std::string(" (SIG") + abbrev + ")" : std::string());
    }
    return "exit code " + std::to_string(code);
}

Expected<ChildProcess> ChildProcess::start(const std::vector<std::string>& argv,
                                           const ProcessOptions& options) {
    if (argv.empty() || argv[0].empty()) return Error{"cannot start a process: no program given"};
    const std::string name = std::filesystem::path(argv[0]).filename().string();
    auto failed = [&name](const std::string& why) {
        return Error{"cannot start " + name + ": " + why};
    };

    // Everything the child needs is prepared here: once started it may not allocate.
    const std::string path = resolveProgram(argv[0]);
    std::vector<std::string> args = argv;
    std::vector<std::string> env = childEnvironment(options);
    const std::vector<char*> argPtrs = pointers(args);
    const std::vector<char*> envPtrs = pointers(env);
    const std::string cwd = options.workingDir.string();

    const UniqueFd devNull(::open("/dev/null", O_RDONLY | O_CLOEXEC));
    if (!devNull.valid()) return failed("/dev/null: " + errnoText(errno));
    auto out = openSink(options.stdoutTo, STDOUT_FILENO);
    if (!out) return failed(out.error());
    auto err = openSink(options.stderrTo, STDERR_FILENO);
    if (!err) return failed(err.error());
    std::array<int, 2> report{};
    if (::pipe2(report.data(), O_CLOEXEC) != 0) return failed("pipe: " + errnoText(errno));
    UniqueFd reportRead(report[0]);
    UniqueFd reportWrite(report[1]);

    ChildSetup setup{::getpid(),          options.deathSignal, options.niceness,
                     &options.namespaces, reportWrite.get(),   devNull.get(),
                     out->childEnd.get(), err->childEnd.get(), cwd.empty() ? nullptr : cwd.c_str(),
                     path.c_str(),        argPtrs.data(),      envPtrs.data()};
    // As posix_spawn does (which cannot set a death signal, a niceness or namespaces): the
    // child shares our memory until it execs and we wait for that, so nothing of ours is
    // copied for it (a fork of a cell's demo took 0.6 ms more to the exec). Every signal
    // stays blocked until it has reset our handlers.
    // Not zeroed: the child touches only the top pages of it.
    const auto stack = std::make_unique_for_overwrite<std::byte[]>(kChildStackBytes);
    sigset_t all;
    sigset_t previous;
    sigfillset(&all);
    ::pthread_sigmask(SIG_SETMASK, &all, &previous);
    const pid_t pid = ::clone(&childEntry, stack.get() + kChildStackBytes,
                              CLONE_VM | CLONE_VFORK | SIGCHLD, &setup);
    const int cloneError = errno;
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    if (pid < 0) return failed("clone: " + errnoText(cloneError));
    reportWrite.reset();
    out->childEnd.reset();
    err->childEnd.reset();

    // EOF: exec succeeded (the CLOEXEC pipe closed); a record: the child failed before it.
    ChildFailure failure{};
    ssize_t n = 0;
    do {
        n = ::read(reportRead.get(), &failure, sizeof failure);
    } while (n < 0 && errno == EINTR);
    if (n > 0) {
        int status = 0;
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        switch (failure.step) {
            case kExec:
                return failed("exec " + path + ": " + errnoText(failure.err));
            case kChdir:
                return failed("working directory " + cwd + ": " + errnoText(failure.err));
            case kNamespace:
                return failed("entering its host's namespaces: " + errnoText(failure.err));
            default:
                return failed("child setup: " + errnoText(failure.err));
        }
    }

    ChildProcess child;
    child.pid_ = pid;
    child.name_ = name;
    child.pidfd_.reset(static_cast<int>(::syscall(SYS_pidfd_open, pid, 0)));
    child.outPipe_ = std::move(out->readEnd);
    child.errPipe_ = std::move(err->readEnd);
    spdlog::debug("started {} (pid {})", name, pid);
    return child;
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)),
      name_(std::move(other.name_)),
      pidfd_(std::move(other.pidfd_)),
      outPipe_(std::move(other.outPipe_)),
      errPipe_(std::move(other.errPipe_)),
      out_(std::move(other.out_)),
      err_(std::move(other.err_)),
      status_(std::exchange(other.status_, std::nullopt)) {}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
    if (this != &other) {
        release();
        pid_ = std::exchange(other.pid_, -1);
        name_ = std::move(other.name_);
        pidfd_ = std::move(other.pidfd_);
        outPipe_ = std::move(other.outPipe_);
        errPipe_ = std::move(other.errPipe_);
        out_ = std::move(other.out_);
        err_ = std::move(other.err_);
        status_ = std::exchange(other.status_, std::nullopt);
    }
    return *this;
}

ChildProcess::~ChildProcess() {
    release();
}

void ChildProcess::release() {
    if (pid_ <= 0 || status_) return;
    if (auto st = terminate(kDestructorGrace); !st) spdlog::error("{}", st.error());
}

bool ChildProcess::reap(bool block) {
    if (status_) return true;
    if (pid_ <= 0) return false;
    int raw = 0;
    pid_t r = 0;
    do {
        r = ::waitpid(pid_, &raw, block ? 0 : WNOHANG);
    } while (r < 0 && errno == EINTR);
    if (r == 0) return false;
    if (r < 0) {
        // ECHILD: someone else reaped it (SIGCHLD ignored); it has ended, how is unknown.
        status_ = ExitStatus{};
    } else if (WIFSIGNALED(raw)) {
        status_ = ExitStatus{-1, WTERMSIG(raw)};
    } else {
        status_ = ExitStatus{WEXITSTATUS(raw), 0};
    }
    pidfd_.reset();
    spdlog::debug("{} (pid {}) ended: {}", name_, pid_, status_->describe());
    return true;
}

void ChildProcess::drainCaptured() {
    std::array<char, 8192> buffer{};
    for (auto [fd, text] : {std::pair{&outPipe_, &out_}, std::pair{&errPipe_, &err_}}) {
        while (fd->valid()) {
            const ssize_t n = ::read(fd->get(), buffer.data(), buffer.size());
            if (n > 0) {
                text->append(buffer.data(), static_cast<std::size_t>(n));
            } else if (n < 0 && errno == EINTR) {
                continue;
            } else {
                // EOF or error: done; EAGAIN: nothing more for now (a grandchild may hold
                // the write end after the child has gone; we do not wait for it).
                if (n == 0 || errno != EAGAIN || status_) fd->reset();
                break;
            }
        }
    }
}

bool ChildProcess::running() {
    if (pid_ <= 0) return false;
    return !reap(false);
}

Expected<ExitStatus> ChildProcess::wait(Duration timeout) {
    if (pid_ <= 0) return Error{"no process to wait for"};
    const auto deadline = Clock::now() + timeout;
    for (;;) {
        if (reap(false)) {
            drainCaptured();
            return *status_;
        }
        const auto left =
            std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) {
            drainCaptured();
            return Error{name_ + " (pid " + std::to_string(pid_) + ") still running after " +
                         std::to_string(timeout.count()) + " ms"};
        }
        std::array<pollfd, 3> fds{};
        nfds_t count = 0;
        for (const UniqueFd* fd : {&pidfd_, &outPipe_, &errPipe_}) {
            if (fd->valid()) fds[count++] = pollfd{fd->get(), POLLIN, 0};
        }
        const int pollMs = pidfd_.valid()
                               ? static_cast<int>(std::min<long long>(left, 60'000))
                               : static_cast<int>(std::min<long long>(left, kFallbackPollMs));
        if (::poll(fds.data(), count, pollMs) > 0) drainCaptured();
    }
}

std::optional<std::string> ChildProcess::readLine(Duration timeout) {
    const auto deadline = Clock::now() + timeout;
    // Bounded: each pass returns, or reads what poll() saw, or waits at most until the
    // deadline.
    for (;;) {
        if (const auto nl = out_.find('\n'); nl != std::string::npos) {
            std::string line = out_.substr(0, nl);
            out_.erase(0, nl + 1);
            if (!line.empty() && line.back() == '\r') line.pop_back();
            return line;
        }
        if (!outPipe_.valid()) return std::nullopt;
        const auto left =
            std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) return std::nullopt;
        pollfd fd{outPipe_.get(), POLLIN, 0};
        const int ready = ::poll(&fd, 1, static_cast<int>(std::min<long long>(left, 60'000)));
        if (ready < 0 && errno != EINTR) return std::nullopt;
        if (ready <= 0) continue;
        std::array<char, 4096> buffer{};
        const ssize_t n = ::read(outPipe_.get(), buffer.data(), buffer.size());
        if (n > 0) {
            out_.append(buffer.data(), static_cast<std::size_t>(n));
        } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
            outPipe_.reset();  // the child closed its stdout (or it broke): what is left counts
        }
    }
}

Expected<ExitStatus> ChildProcess::terminate(Duration grace) {
    if (pid_ <= 0) return Error{"no process to terminate"};
    if (!running()) return *status_;
    ::kill(pid_, SIGTERM);
    if (auto st = wait(grace); st) return st;
    spdlog::warn("{} (pid {}) ignored SIGTERM for {} ms; killing it", name_, pid_, grace.count());
    return kill();
}

Expected<ExitStatus> ChildProcess::kill() {
    if (pid_ <= 0) return Error{"no process to kill"};
    if (!running()) return *status_;
    ::kill(pid_, SIGKILL);
    return wait(kKillBound);
}

Expected<RunResult> runToCompletion(const std::vector<std::string>& argv,
                                    std::chrono::milliseconds timeout, ProcessOptions options) {
    options.stdoutTo = OutputSink::capture();
    options.stderrTo = OutputSink::capture();
    auto child = ChildProcess::start(argv, options);
    if (!child) return Error{child.error()};
    auto status = child->wait(timeout);
    if (!status) {
        (void)child->kill();
        return Error{child->name() + " did not finish within " + std::to_string(timeout.count()) +
                     " ms and was killed; its output: " +
                     tail(child->capturedStdout() + child->capturedStderr())};
    }
    if (status->signal != 0) {
        return Error{child->name() + " was " + status->describe() +
                     "; its output: " + tail(child->capturedStdout() + child->capturedStderr())};
    }
    return RunResult{status->code, child->capturedStdout(), child->capturedStderr()};
}

}  // namespace skillcell::process
