#include "kb/engine/virtuoso_watch.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>

namespace skillcell::kb::engine {

namespace {
constexpr int kFirstRetryMs = 1000;
constexpr int kLongestRetryMs = 30'000;
}  // namespace

VirtuosoWatch::VirtuosoWatch(VirtuosoInstance& virtuoso, std::function<void()> restarted)
    : virtuoso_(virtuoso),
      restarted_(std::move(restarted)),
      stop_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
    thread_ = std::thread([this] { run(); });
}

VirtuosoWatch::~VirtuosoWatch() {
    const std::uint64_t one = 1;
    if (stop_.valid()) (void)!::write(stop_.get(), &one, sizeof one);
    if (thread_.joinable()) thread_.join();
}

bool VirtuosoWatch::waitFor(int fd, int ms) {
    std::array<pollfd, 2> fds{pollfd{stop_.get(), POLLIN, 0}, pollfd{fd, POLLIN, 0}};
    const nfds_t n = fd >= 0 ? 2 : 1;
    for (;;) {
        const int r = ::poll(fds.data(), n, ms);
        if (r < 0 && errno == EINTR) continue;
        return r > 0 && (fds[0].revents & POLLIN) != 0;
    }
}

void VirtuosoWatch::run() {
    if (!stop_.valid()) {
        spdlog::error("kb: cannot watch Virtuoso (no eventfd): a crash of it will not be mended");
        return;
    }
    for (;;) {
        const int ended = virtuoso_.exitFd();
        if (ended < 0) return;  // none runs: nothing to watch (a KB on another store)
        if (waitFor(ended, -1)) return;
        spdlog::error("kb: Virtuoso ended by itself ({}): starting it again on {}",
                      virtuoso_.howItEnded(), virtuoso_.dataDir().string());
        const auto t0 = std::chrono::steady_clock::now();
        int pause = kFirstRetryMs;
        for (;;) {
            auto started = virtuoso_.start();
            if (started) break;
            spdlog::error("kb: Virtuoso did not start again: {} (trying again in {} ms)",
                          started.error(), pause);
            if (waitFor(-1, pause)) return;
            pause = std::min(pause * 2, kLongestRetryMs);
        }
        spdlog::info("kb: Virtuoso is back after {} ms; recording the live components again",
                     std::chrono::duration_cast<std::chrono::milliseconds>(
                         std::chrono::steady_clock::now() - t0)
                         .count());
        if (restarted_) restarted_();
    }
}

}  // namespace skillcell::kb::engine
