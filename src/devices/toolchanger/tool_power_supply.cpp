#include "devices/toolchanger/tool_power_supply.hpp"

#include <spdlog/spdlog.h>

#include <csignal>
#include <optional>
#include <utility>

namespace skillcell::devices::toolchanger {

ToolPowerSupply::~ToolPowerSupply() {
    offAll();
}

void ToolPowerSupply::offAll() {
    std::vector<std::string> ids;
    {
        std::lock_guard guard(mutex_);
        for (const auto& [id, child] : children_) ids.push_back(id);
    }
    for (const auto& id : ids) off(id);
}

ua::StatusCode ToolPowerSupply::on(const std::string& toolId, const std::vector<std::string>& argv,
                                   std::string* why) {
    if (argv.empty()) return ua::status::BadInvalidArgument;
    std::lock_guard guard(mutex_);
    if (children_.contains(toolId)) return ua::status::Good;
    process::ProcessOptions options;
    // SIGTERM when the changer dies, not SIGKILL: the adapter says goodbye on the network, as
    // a board with a supervisor does on a power-fail warning. Its output goes to the changer's
    // log (stderr), never into its stdout, which scripts read (the READY line).
    options.deathSignal = SIGTERM;
    auto child = process::ChildProcess::start(argv, options);
    if (!child) {
        if (why != nullptr) *why = child.error();
        return ua::status::BadResourceUnavailable;
    }
    spdlog::info("tool changer: powered tool {} (pid {}: {})", toolId, child->pid(), argv.front());
    children_.emplace(toolId, std::move(*child));
    return ua::status::Good;
}

int ToolPowerSupply::off(const std::string& toolId) {
    std::optional<process::ChildProcess> child;
    {
        std::lock_guard guard(mutex_);
        const auto it = children_.find(toolId);
        if (it == children_.end()) return -1;
        child.emplace(std::move(it->second));
        children_.erase(it);
    }
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

}  // namespace skillcell::devices::toolchanger
