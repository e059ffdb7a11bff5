#pragma once
// Going on after a lost device: a composite whose robot or tool dies mid-run (the component's
// supervisor starts it again) tries its run again once discovery finds the device again, from
// what the devices and the scene show. Only a run that settles from the state it finds may be
// tried again (docs/mes.md, "Settling"): the pick and place plans from where the object is,
// the tool changer from its identification pin.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <chrono>
#include <functional>
#include <string>

namespace skillcell::devices {

inline constexpr int kLostDeviceTries = 5;
inline constexpr std::chrono::milliseconds kLostDeviceFirstPause{500};  // then 1 s, 2 s, 4 s

/// One try of a run: "" or why it failed; it sets `lost` when it lost a device it drives (a
/// session gone, or a detected endpoint that could not be reached).
using RunAttempt = std::function<asio::awaitable<std::string>(bool& lost)>;

/// Runs `attempt` until it succeeds, fails without losing a device, `halted()` is true, or
/// kLostDeviceTries tries failed, pausing between tries (0.5 s, doubling). A run that still
/// fails says the device it lost first. `onPause` (if set) is told before each pause; `who`
/// names the composite in the log.
asio::awaitable<std::string> goOnAfterLostDevice(asio::any_io_executor executor, RunAttempt attempt,
                                                 std::function<bool()> halted, std::string who,
                                                 std::function<void()> onPause = {});

}  // namespace skillcell::devices
