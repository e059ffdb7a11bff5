#include "devices/common/lost_device_retry.hpp"

#include <spdlog/spdlog.h>

#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

namespace skillcell::devices {

asio::awaitable<std::string> goOnAfterLostDevice(asio::any_io_executor executor, RunAttempt attempt,
                                                 std::function<bool()> halted, std::string who,
                                                 std::function<void()> onPause) {
    std::chrono::milliseconds pause = kLostDeviceFirstPause;
    std::string firstLoss;
    std::string why;
    for (int n = 1;; ++n) {
        bool lost = false;
        why = co_await attempt(lost);
        if (!why.empty() && !firstLoss.empty()) why += " (after a lost device: " + firstLoss + ")";
        if (why.empty() || halted() || !lost || n == kLostDeviceTries) break;
        if (firstLoss.empty()) firstLoss = why;
        spdlog::warn(
            "{}: {}: a device was lost; going on from what the cell shows in {} ms "
            "(try {} of {})",
            who, why, pause.count(), n + 1, kLostDeviceTries);
        if (onPause) onPause();
        asio::steady_timer timer(executor, pause);
        co_await timer.async_wait(asio::use_awaitable);
        if (halted()) break;
        pause *= 2;
    }
    co_return why;
}

}  // namespace skillcell::devices
