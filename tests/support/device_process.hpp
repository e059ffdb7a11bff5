#pragma once
// DeviceProcess: a `skillcell device ...` process on loopback with its own PKI directory,
// for tests that run the cell's components as the cell does. Its URL is read from its READY
// line; it is stopped with SIGTERM and waited for. `binary` is the skillcell executable.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

extern char** environ;  // NOLINT: POSIX

namespace skillcell::test {

class DeviceProcess {
public:
    /// `args` follow `skillcell device` (the kind first). `discovery`: announce by mDNS
    /// (the test must run in a private network namespace), else --no-discovery.
    DeviceProcess(const std::string& binary, std::vector<std::string> args, bool discovery = false)
        : pki_(std::filesystem::temp_directory_path() /
               ("skillcell-device-" + std::to_string(::getpid()) + "-" + args.at(0))) {
        args.insert(args.begin(), {binary, "device"});
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
            if (l.starts_with("READY ")) {
                url_ = l.substr(6, l.find_last_not_of("\r\n") - 5);
                break;
            }
        }
        if (out != nullptr) std::fclose(out);
    }
    ~DeviceProcess() {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            int status = 0;
            ::waitpid(pid_, &status, 0);
        }
        std::error_code ec;
        std::filesystem::remove_all(pki_, ec);
    }
    DeviceProcess(const DeviceProcess&) = delete;
    DeviceProcess& operator=(const DeviceProcess&) = delete;

    [[nodiscard]] const std::string& url() const { return url_; }
    [[nodiscard]] const std::filesystem::path& pkiDir() const { return pki_; }

private:
    pid_t pid_ = 0;
    std::string url_;
    std::filesystem::path pki_;
};

}  // namespace skillcell::test
