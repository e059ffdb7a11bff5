#include "devices/toolchanger/tool_power_supply.hpp"

#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>

extern char** environ;  // NOLINT: POSIX

namespace skillcell::devices::toolchanger {
namespace {

/// The program's path, resolved before fork() (the child may only call async-signal-safe
/// functions, and execvp's PATH search is not one).
std::string resolveProgram(const std::string& program) {
    if (program.find('/') != std::string::npos) return program;
    const char* path = std::getenv("PATH");
    std::string_view dirs = path != nullptr ? path : "/usr/bin:/bin";
    while (!dirs.empty()) {
        const auto colon = dirs.find(':');
        const std::string dir(dirs.substr(0, colon));
        const std::filesystem::path candidate = std::filesystem::path(dir) / program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
        dirs = colon == std::string_view::npos ? std::string_view{} : dirs.substr(colon + 1);
    }
    return {};
}

/// Waits for `pid` up to `timeout`; its exit status, or nullopt if it still runs. A pidfd
/// becomes readable when the process exits: no SIGCHLD handler (which would take other
/// children's statuses from their owners), no polling.
std::optional<int> reap(int pid, std::chrono::milliseconds timeout) {
    const int fd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
    if (fd >= 0) {
        pollfd p{fd, POLLIN, 0};
        int ready = 0;
        do {
            ready = ::poll(&p, 1, static_cast<int>(timeout.count()));
        } while (ready < 0 && errno == EINTR);
        ::close(fd);
        if (ready == 0) return std::nullopt;
    }
    int status = 0;
    pid_t r = 0;
    do {
        r = ::waitpid(pid, &status, fd >= 0 ? 0 : WNOHANG);
    } while (r < 0 && errno == EINTR);
    if (r == 0) return std::nullopt;  // no pidfd and still running
    if (r != pid) return -1;          // not ours any more
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

ToolPowerSupply::~ToolPowerSupply() {
    offAll();
}

void ToolPowerSupply::offAll() {
    std::vector<std::string> ids;
    {
        std::lock_guard guard(mutex_);
        for (const auto& [id, pid] : children_) ids.push_back(id);
    }
    for (const auto& id : ids) off(id);
}

ua::StatusCode ToolPowerSupply::on(const std::string& toolId, const std::vector<std::string>& argv,
                                   std::string* why) {
    if (argv.empty()) return ua::status::BadInvalidArgument;
    std::lock_guard guard(mutex_);
    if (children_.contains(toolId)) return ua::status::Good;
    const std::string program = resolveProgram(argv.front());
    if (program.empty()) {
        if (why != nullptr) *why = "no program " + argv.front() + " on the PATH";
        return ua::status::BadResourceUnavailable;
    }
    std::vector<std::string> args = argv;
    std::vector<char*> cargs;
    cargs.reserve(args.size() + 1);
    for (auto& a : args) cargs.push_back(a.data());
    cargs.push_back(nullptr);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        if (why != nullptr) *why = std::string("fork: ") + std::strerror(errno);
        return ua::status::BadResourceUnavailable;
    }
    if (pid == 0) {
        // The child: async-signal-safe calls only.
        ::prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (::getppid() != parent) ::_exit(127);  // the changer died before prctl
        sigset_t none;
        sigemptyset(&none);
        ::sigprocmask(SIG_SETMASK, &none, nullptr);  // the parent may block signals
        // A tool's output goes to the changer's log (stderr), never into its stdout, which
        // scripts read (the READY line).
        ::dup2(2, 1);
        ::execve(program.c_str(), cargs.data(), environ);
        ::_exit(127);
    }
    children_[toolId] = pid;
    spdlog::info("tool changer: powered tool {} (pid {}: {})", toolId, pid, program);
    return ua::status::Good;
}

int ToolPowerSupply::off(const std::string& toolId) {
    int pid = 0;
    {
        std::lock_guard guard(mutex_);
        const auto it = children_.find(toolId);
        if (it == children_.end()) return -1;
        pid = it->second;
        children_.erase(it);
    }
    ::kill(pid, SIGTERM);
    auto status = reap(pid, stopTimeout_);
    if (!status) {
        spdlog::warn("tool changer: tool {} (pid {}) ignored SIGTERM for {} ms: SIGKILL", toolId,
                     pid, stopTimeout_.count());
        ::kill(pid, SIGKILL);
        status = reap(pid, std::chrono::seconds(5));
    }
    spdlog::info("tool changer: tool {} powered off (exit status {})", toolId, status.value_or(-1));
    return status.value_or(-1);
}

bool ToolPowerSupply::powered(const std::string& toolId) {
    std::lock_guard guard(mutex_);
    return children_.contains(toolId);
}

}  // namespace skillcell::devices::toolchanger
