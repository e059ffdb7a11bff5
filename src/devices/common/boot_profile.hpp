#pragma once
// BootProfile: how long a device's controller takes from power-on until its OPC UA server
// is on the network. The paper's gripper adapters run on Wi-Fi microcontroller boards
// (TinyUA on an ESP32) whose start it measured stage by stage (section VIII-C): boot loader
// 1.8 s, joining the Wi-Fi 2.9 s, setting the clock by NTP 1.9 s, starting the OPC UA
// application and announcing it 1.8 s, plus 1.2 s to initialise the IO-Link board on the
// Schmalz adapter. A simulated device replays those stages, so the paper's 8-10 s
// detection times can be reproduced; without a profile it starts at once (the fast path).
#include <chrono>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skillcell::devices {

struct BootStage {
    std::string name;
    std::chrono::milliseconds duration{0};
};

struct BootProfile {
    /// Before the application runs at all (no network yet).
    std::vector<BootStage> powerOn;
    /// After the application set up its device (its nodes exist), before the server
    /// listens and announces itself.
    std::vector<BootStage> applicationStart;

    [[nodiscard]] bool empty() const { return powerOn.empty() && applicationStart.empty(); }
    [[nodiscard]] std::chrono::milliseconds total() const;
};

/// The TinyUA board as the paper measured it; `ioLinkBoard` adds the Schmalz adapter's
/// IO-Link master initialisation.
[[nodiscard]] BootProfile tinyUaBootProfile(bool ioLinkBoard);

/// "none" (no profile) or "tinyua"; nothing for another name.
[[nodiscard]] std::optional<BootProfile> bootProfileNamed(std::string_view name, bool ioLinkBoard);

}  // namespace skillcell::devices
