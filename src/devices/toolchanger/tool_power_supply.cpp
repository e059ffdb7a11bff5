#include "devices/toolchanger/tool_power_supply.hpp"

#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <optional>
#include <utility>

namespace skillcell::devices::toolchanger {

ToolPowerSupply::ToolPowerSupply(std::chrono::milliseconds stopTimeout)
    : stopTimeout_(stopTimeout), wakeFd_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
    if (!wakeFd_.valid()) {
        spdlog::warn("tool changer: no eventfd ({}): a crashed tool adapter is not restarted",
                     std::strerror(errno));
        return;
    }
    watchdog_ = std::thread([this] { watch(); });
}

ToolPowerSupply::~ToolPowerSupply() {
    offAll();
    {
        std::lock_guard guard(mutex_);
        stopping_ = true;
    }
    wake();
    if (watchdog_.joinable()) watchdog_.join();
}

void ToolPowerSupply::wake() {
    if (!wakeFd_.valid()) return;
    const std::uint64_t one = 1;
    (void)::write(wakeFd_.get(), &one, sizeof one);
}

Expected<process::ChildProcess> ToolPowerSupply::start(const std::vector<std::string>& argv) {
    process::ProcessOptions options;
    // SIGTERM when the changer dies, not SIGKILL: the adapter says goodbye on the network, as
    // a board with a supervisor does on a power-fail warning. Its output goes to the changer's
    // log (stderr), never into its stdout, which scripts read (the READY line).
    options.deathSignal = SIGTERM;
    return process::ChildProcess::start(argv, options);
}

void ToolPowerSupply::offAll() {
    std::vector<std::string> ids;
    {
        std::lock_guard guard(mutex_);
        for (const auto& [id, powered] : children_) ids.push_back(id);
    }
    for (const auto& id : ids) off(id);
}

ua::StatusCode ToolPowerSupply::on(const std::string& toolId, const std::vector<std::string>& argv,
                                   std::string* why) {
    if (argv.empty()) return ua::status::BadInvalidArgument;
    {
        std::lock_guard guard(mutex_);
        if (children_.contains(toolId)) return ua::status::Good;
        auto child = start(argv);
        if (!child) {
            if (why != nullptr) *why = child.error();
            return ua::status::BadResourceUnavailable;
        }
        spdlog::info("tool changer: powered tool {} (pid {}: {})", toolId, child->pid(),
                     argv.front());
        children_.emplace(toolId, Powered{std::move(*child), argv, 0});
    }
    wake();
    return ua::status::Good;
}

int ToolPowerSupply::off(const std::string& toolId) {
    std::optional<process::ChildProcess> child;
    {
        std::lock_guard guard(mutex_);
        const auto it = children_.find(toolId);
        if (it == children_.end()) return -1;
        child.emplace(std::move(it->second.child));
        children_.erase(it);
    }
    wake();
    // SIGTERM, then SIGKILL for an adapter that has not ended within the grace period.
    const auto status = child->terminate(stopTimeout_);
    if (!status) {
        spdlog::warn("tool changer: tool {} did not power off: {}", toolId, status.error());
        return -1;
    }
    spdlog::info("tool changer: tool {} powered off ({})", toolId, status->describe());
    return status->code;
}

bool ToolPowerSupply::powered(const std::string& toolId) {
    std::lock_guard guard(mutex_);
    return children_.contains(toolId);
}

int ToolPowerSupply::restarts(const std::string& toolId) {
    std::lock_guard guard(mutex_);
    const auto it = children_.find(toolId);
    return it == children_.end() ? 0 : it->second.restarts;
}

void ToolPowerSupply::watch() {
    for (;;) {
        std::vector<pollfd> fds{{wakeFd_.get(), POLLIN, 0}};
        std::vector<std::string> ids;
        {
            std::lock_guard guard(mutex_);
            if (stopping_) return;
            for (const auto& [id, powered] : children_) {
                if (powered.child.exitFd() < 0) continue;  // no pidfd: not watched
                fds.push_back({powered.child.exitFd(), POLLIN, 0});
                ids.push_back(id);
            }
        }
        if (::poll(fds.data(), fds.size(), -1) < 0 && errno != EINTR) {
            spdlog::warn("tool changer: the adapters' watchdog stops: poll: {}",
                         std::strerror(errno));
            return;
        }
        if ((fds[0].revents & POLLIN) != 0) {
            std::uint64_t count = 0;
            (void)::read(wakeFd_.get(), &count, sizeof count);
        }
        std::lock_guard guard(mutex_);
        if (stopping_) return;
        for (std::size_t i = 1; i < fds.size(); ++i) {
            if (fds[i].revents == 0) continue;
            // Still powered, by this very process (not powered off and on meanwhile)?
            const auto it = children_.find(ids[i - 1]);
            if (it == children_.end() || it->second.child.exitFd() != fds[i].fd ||
                it->second.child.running()) {
                continue;
            }
            Powered& p = it->second;
            const auto ended = p.child.wait(std::chrono::milliseconds(0));
            const std::string how = ended ? ended->describe() : ended.error();
            if (p.restarts >= kWatchdogRestarts) {
                spdlog::error(
                    "tool changer: tool {}'s adapter ended ({}) while powered, {} "
                    "times: not restarted again",
                    it->first, how, p.restarts + 1);
                children_.erase(it);
                continue;
            }
            auto child = start(p.argv);
            if (!child) {
                spdlog::error(
                    "tool changer: tool {}'s adapter ended ({}) and cannot be "
                    "restarted: {}",
                    it->first, how, child.error());
                children_.erase(it);
                continue;
            }
            ++p.restarts;
            spdlog::warn(
                "tool changer: tool {}'s adapter ended ({}) while powered: restarted "
                "(pid {}), as its watchdog would ({} of {})",
                it->first, how, child->pid(), p.restarts, kWatchdogRestarts);
            p.child = std::move(*child);
        }
    }
}

}  // namespace skillcell::devices::toolchanger
