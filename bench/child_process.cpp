#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

extern char** environ;  // NOLINT: POSIX

namespace skillcell::bench {
namespace {

using Clock = std::chrono::steady_clock;

int remainingMs(Clock::time_point deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 60'000));
}

/// posix_spawn_file_actions_t with RAII.
class FileActions {
public:
    FileActions() { ::posix_spawn_file_actions_init(&actions_); }
    ~FileActions() { ::posix_spawn_file_actions_destroy(&actions_); }
    FileActions(const FileActions&) = delete;
    FileActions& operator=(const FileActions&) = delete;
    posix_spawn_file_actions_t* get() { return &actions_; }

private:
    posix_spawn_file_actions_t actions_{};
};

}  // namespace

std::string findInPath(const std::string& program) {
    if (program.find('/') != std::string::npos) {
        return ::access(program.c_str(), X_OK) == 0 ? program : std::string();
    }
    const char* path = std::getenv("PATH");
    std::string_view rest = path ? path : "/usr/local/bin:/usr/bin:/bin";
    while (!rest.empty()) {
        const auto colon = rest.find(':');
        std::string dir(rest.substr(0, colon));
        rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
        if (dir.empty()) dir = ".";
        std::string candidate = dir + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return {};
}

std::string describeWaitStatus(int status) {
    if (WIFEXITED(status)) return "exit " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
    return "status " + std::to_string(status);
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& stderrPath) {
    if (argv.empty()) throw std::runtime_error("ChildProcess: empty argv");
    const std::string program = findInPath(argv[0]);
    if (program.empty()) throw std::runtime_error("ChildProcess: '" + argv[0] + "' not found");

    std::array<int, 2> pipeFds{-1, -1};
    if (::pipe2(pipeFds.data(), O_CLOEXEC) != 0) {
        throw std::runtime_error(std::string("pipe2: ") + std::strerror(errno));
    }
    FileActions actions;
    ::posix_spawn_file_actions_addopen(actions.get(), STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    // dup2 clears FD_CLOEXEC on the child's stdout; both pipe ends close on exec.
    ::posix_spawn_file_actions_adddup2(actions.get(), pipeFds[1], STDOUT_FILENO);
    if (!stderrPath.empty()) {
        ::posix_spawn_file_actions_addopen(actions.get(), STDERR_FILENO, stderrPath.c_str(),
                                           O_WRONLY | O_CREAT | O_TRUNC, 0644);
    }
    std::vector<char*> args;
    args.reserve(argv.size() + 1);
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);

    const int rc =
        ::posix_spawn(&pid_, program.c_str(), actions.get(), nullptr, args.data(), environ);
    ::close(pipeFds[1]);
    if (rc != 0) {
        ::close(pipeFds[0]);
        throw std::runtime_error("posix_spawn " + program + ": " + std::strerror(rc));
    }
    stdoutFd_ = pipeFds[0];
#ifdef SYS_pidfd_open
    pidFd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
#endif
}

ChildProcess::~ChildProcess() {
    if (pid_ > 0 && !exitStatus_) stop();
    if (stdoutFd_ >= 0) ::close(stdoutFd_);
    if (pidFd_ >= 0) ::close(pidFd_);
}

std::optional<std::string> ChildProcess::readLine(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    // Bounded: every pass either returns or consumes input, and poll() waits at most until
    // the deadline.
    for (;;) {
        if (const auto nl = buffer_.find('\n'); nl != std::string::npos) {
            std::string line = buffer_.substr(0, nl);
            buffer_.erase(0, nl + 1);
            if (!line.empty() && line.back() == '\r') line.pop_back();
            return line;
        }
        if (stdoutEof_) return std::nullopt;
        pollfd p{stdoutFd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, remainingMs(deadline));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) return std::nullopt;  // timeout (or a poll failure)
        std::array<char, 4096> chunk{};
        const auto got = ::read(stdoutFd_, chunk.data(), chunk.size());
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) {
            stdoutEof_ = true;
            continue;
        }
        buffer_.append(chunk.data(), static_cast<std::size_t>(got));
    }
}

bool ChildProcess::reap(bool block) {
    if (exitStatus_) return true;
    int status = 0;
    pid_t r = -1;
    do {
        r = ::waitpid(pid_, &status, block ? 0 : WNOHANG);
    } while (r < 0 && errno == EINTR);
    if (r == pid_) {
        exitStatus_ = status;
        return true;
    }
    if (r < 0) {  // ECHILD: somebody else reaped it; treat as gone
        exitStatus_ = -1;
        return true;
    }
    return false;
}

std::optional<int> ChildProcess::waitExit(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (!reap(false)) {
        const int left = remainingMs(deadline);
        if (left == 0) return std::nullopt;
        if (pidFd_ >= 0) {
            // The pidfd becomes readable when the child exits: no polling interval.
            pollfd p{pidFd_, POLLIN, 0};
            const int ready = ::poll(&p, 1, left);
            if (ready < 0 && errno != EINTR) return std::nullopt;
        } else {
            // Kernels without pidfd_open: check again every 5 ms until the deadline.
            ::poll(nullptr, 0, std::min(left, 5));
        }
    }
    return exitStatus_;
}

int ChildProcess::stop(std::chrono::milliseconds grace) {
    if (exitStatus_) return *exitStatus_;
    ::kill(pid_, SIGTERM);
    if (auto s = waitExit(grace)) return *s;
    ::kill(pid_, SIGKILL);
    reap(true);
    return *exitStatus_;
}

}  // namespace skillcell::bench
