#include "devices/common/boot_profile.hpp"

namespace skillcell::devices {

using std::chrono::milliseconds;

milliseconds BootProfile::total() const {
    milliseconds sum{0};
    for (const auto& s : powerOn) sum += s.duration;
    for (const auto& s : applicationStart) sum += s.duration;
    return sum;
}

BootProfile tinyUaBootProfile(bool ioLinkBoard) {
    BootProfile p;
    p.powerOn = {{"boot loader", milliseconds(1800)},
                 {"Wi-Fi join", milliseconds(2900)},
                 {"NTP time", milliseconds(1900)}};
    if (ioLinkBoard) p.applicationStart.push_back({"IO-Link master init", milliseconds(1200)});
    p.applicationStart.push_back({"OPC UA application start", milliseconds(1800)});
    return p;
}

std::optional<BootProfile> bootProfileNamed(std::string_view name, bool ioLinkBoard) {
    if (name == "none") return BootProfile{};
    if (name == "tinyua") return tinyUaBootProfile(ioLinkBoard);
    return std::nullopt;
}

}  // namespace skillcell::devices
