#pragma once
// ComponentProcess: a skillcell component (`skillcell server ...`, `skillcell device ...`) as
// a process on loopback with a PKI directory of its own, for tests that run components as
// the cell does. Its URL is read from its READY line; it is stopped with SIGTERM (or
// kill()ed) and waited for. `binary` is the skillcell executable.
#include <gtest/gtest.h>
#include <sys/types.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "process/child_process.hpp"

namespace skillcell::test {

class ComponentProcess {
public:
    /// `args` follow the binary (`server ...`, `device world ...`); the loopback, insecure and
    /// PKI options are added. `discovery`: announce by mDNS (the test must run in a private
    /// network namespace), else --no-discovery. `insecure` false: security is the test's own
    /// (it gives --users).
    ComponentProcess(const std::string& binary, std::vector<std::string> args,
                     bool discovery = false, bool insecure = true) {
        std::string dir =
            (std::filesystem::temp_directory_path() / "skillcell-pki-XXXXXX").string();
        if (::mkdtemp(dir.data()) == nullptr) return;
        pki_ = dir;
        name_ = args.size() > 1 ? args[0] + " " + args[1] : args.at(0);
        args.insert(args.begin(), binary);
        // --insecure: these tests are about the devices; security has tests of its own.
        // Any free port, unless the test gives one (a component started again where it was).
        if (std::find(args.begin(), args.end(), "--port") == args.end()) {
            args.insert(args.end(), {"--port", "0"});
        }
        args.insert(args.end(), {"--host", "127.0.0.1"});
        if (insecure) args.emplace_back("--insecure");
        if (!discovery) args.emplace_back("--no-discovery");
        args.emplace_back("--pki-dir");
        args.push_back(pki_.string());
        auto started = process::ChildProcess::start(args, process::reportingChild());
        if (!started) {
            ADD_FAILURE() << started.error();
            return;
        }
        child_.emplace(std::move(*started));
        // The READY line, or the end of its output if the process died; bounded, for a
        // component that hangs: under the sanitizers on a loaded machine a start takes seconds.
        using Clock = std::chrono::steady_clock;
        const auto deadline = Clock::now() + kReadyTimeout;
        for (auto now = Clock::now(); now < deadline; now = Clock::now()) {
            const auto line = child_->readLine(
                std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now));
            if (!line) break;
            output_.push_back(*line);
            if (line->starts_with("READY ")) {
                url_ = line->substr(6);
                break;
            }
        }
    }
    ~ComponentProcess() {
        // A component stops cleanly on SIGTERM: exit status 0 (under the sanitizers, also no
        // leak and no report at exit).
        const auto ended = kill(SIGTERM);
        if (ended && !ended->success()) {
            ADD_FAILURE() << "component " << name_
                          << " did not exit 0 on SIGTERM: " << ended->describe();
        }
        std::error_code ec;
        if (!pki_.empty()) std::filesystem::remove_all(pki_, ec);
    }
    ComponentProcess(const ComponentProcess&) = delete;
    ComponentProcess& operator=(const ComponentProcess&) = delete;

    /// Sends `signal` and waits, bounded, for the process to end; how it ended (nothing when
    /// none ran, or it outlived the bound and was killed).
    std::optional<process::ExitStatus> kill(int signal = SIGKILL) {
        if (!child_) return std::nullopt;
        ::kill(child_->pid(), signal);
        auto ended = child_->wait(kStopTimeout);
        if (!ended) {
            ADD_FAILURE() << "component " << name_ << ": " << ended.error();
            (void)child_->kill();
        }
        child_.reset();
        return ended ? std::optional(*ended) : std::nullopt;
    }

    [[nodiscard]] const std::string& url() const { return url_; }
    /// 0 once it has been waited for.
    [[nodiscard]] pid_t pid() const { return child_ ? child_->pid() : 0; }
    /// What it printed up to its READY line (one entry per line).
    [[nodiscard]] const std::vector<std::string>& output() const { return output_; }
    [[nodiscard]] const std::filesystem::path& pkiDir() const { return pki_; }

private:
    static constexpr std::chrono::seconds kReadyTimeout{120};
    static constexpr std::chrono::seconds kStopTimeout{60};

    std::optional<process::ChildProcess> child_;
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
