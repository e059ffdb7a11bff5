#pragma once
// ComponentProcess: a skillcell component (`skillcell server ...`, `skillcell device ...`) as
// a process on loopback with a PKI directory of its own, for tests that run components as
// the cell does. Its URL is read from its READY line; it is stopped with SIGTERM (or
// kill()ed) and waited for. `binary` is the skillcell executable.
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

extern char** environ;  // NOLINT: POSIX

namespace skillcell::test {

class ComponentProcess {
public:
    /// `args` follow the binary (`server ...`, `device world ...`); the loopback, insecure and
    /// PKI options are added. `discovery`: announce by mDNS (the test must run in a private
    /// network namespace), else --no-discovery.
    ComponentProcess(const std::string& binary, std::vector<std::string> args,
                     bool discovery = false) {
        std::string dir =
            (std::filesystem::temp_directory_path() / "skillcell-pki-XXXXXX").string();
        if (::mkdtemp(dir.data()) == nullptr) return;
        pki_ = dir;
        name_ = args.size() > 1 ? args[0] + " " + args[1] : args.at(0);
        args.insert(args.begin(), binary);
        // --insecure: these tests are about the devices; security has tests of its own.
        for (const char* a : {"--port", "0", "--host", "127.0.0.1", "--insecure"}) {
            args.emplace_back(a);
        }
        if (!discovery) args.emplace_back("--no-discovery");
        args.emplace_back("--pki-dir");
        args.push_back(pki_.string());
        int fds[2];
        if (::pipe(fds) != 0) return;
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
        posix_spawn_file_actions_addclose(&actions, fds[0]);
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        if (posix_spawn(&pid_, binary.c_str(), &actions, nullptr, argv.data(), environ) != 0) {
            pid_ = 0;
        }
        posix_spawn_file_actions_destroy(&actions);
        ::close(fds[1]);
        FILE* out = ::fdopen(fds[0], "r");
        char line[256];
        // The READY line, or EOF if the process died: bounded by the process itself.
        while (out != nullptr && std::fgets(line, sizeof line, out) != nullptr) {
            const std::string l(line);
            output_.push_back(l.substr(0, l.find_last_not_of("\r\n") + 1));
            if (l.starts_with("READY ")) {
                url_ = l.substr(6, l.find_last_not_of("\r\n") - 5);
                break;
            }
        }
        if (out != nullptr) std::fclose(out);
    }
    ~ComponentProcess() {
        // A component stops cleanly on SIGTERM: exit status 0 (under the sanitizers, also no
        // leak and no report at exit).
        const int status = kill(SIGTERM);
        if (status != -1 && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
            ADD_FAILURE() << "component " << name_ << " did not exit 0 on SIGTERM (wait status "
                          << status << ")";
        }
        std::error_code ec;
        if (!pki_.empty()) std::filesystem::remove_all(pki_, ec);
    }
    ComponentProcess(const ComponentProcess&) = delete;
    ComponentProcess& operator=(const ComponentProcess&) = delete;

    /// Sends `signal` and waits for the process to end; its wait status (-1: none ran).
    int kill(int signal = SIGKILL) {
        if (pid_ <= 0) return -1;
        ::kill(pid_, signal);
        int status = 0;
        if (::waitpid(pid_, &status, 0) != pid_) status = -1;
        pid_ = 0;
        return status;
    }

    [[nodiscard]] const std::string& url() const { return url_; }
    /// 0 once it has been waited for.
    [[nodiscard]] pid_t pid() const { return pid_; }
    /// What it printed up to its READY line (one entry per line).
    [[nodiscard]] const std::vector<std::string>& output() const { return output_; }
    [[nodiscard]] const std::filesystem::path& pkiDir() const { return pki_; }

private:
    pid_t pid_ = 0;
    std::string name_;  // "device world", for messages
    std::string url_;
    std::vector<std::string> output_;
    std::filesystem::path pki_;
};

/// `skillcell device <kind> ...`.
struct DeviceProcess : ComponentProcess {
    DeviceProcess(const std::string& binary, std::vector<std::string> args, bool discovery = false)
        : ComponentProcess(binary, withDevice(std::move(args)), discovery) {}

private:
    static std::vector<std::string> withDevice(std::vector<std::string> args) {
        args.insert(args.begin(), "device");
        return args;
    }
};

}  // namespace skillcell::test
