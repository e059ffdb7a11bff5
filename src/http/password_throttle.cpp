#include "http/password_throttle.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace skillcell::http {

std::optional<std::chrono::seconds> PasswordThrottle::refusedFor(std::string_view name,
                                                                 Clock::time_point now) {
    const std::lock_guard lock(mutex_);
    const auto it = names_.find(std::string(name));
    if (it == names_.end() || it->second.lockedUntil <= now) return std::nullopt;
    // Rounded up: a client that waits this long is let through.
    return std::chrono::ceil<std::chrono::seconds>(it->second.lockedUntil - now);
}

void PasswordThrottle::failed(std::string_view name, Clock::time_point now) {
    const std::lock_guard lock(mutex_);
    if (names_.size() >= kMaxNames && !names_.contains(std::string(name))) {
        // A flood of names: forget the series that are not locked, else the oldest half.
        std::erase_if(names_, [now](const auto& n) { return n.second.lockedUntil <= now; });
        if (names_.size() >= kMaxNames) {
            std::vector<Clock::time_point> times;
            times.reserve(names_.size());
            for (const auto& entry : names_) times.push_back(entry.second.last);
            const auto middle = times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2);
            std::nth_element(times.begin(), middle, times.end());
            const auto cut = *middle;
            std::erase_if(names_, [cut](const auto& n) { return n.second.last <= cut; });
        }
    }
    Series& s = names_[std::string(name)];
    ++s.failures;
    s.last = now;
    if (s.failures > kFreeFailures) {
        const int doublings = std::min(s.failures - kFreeFailures - 1, 16);
        const auto lockout = std::min<std::chrono::seconds>(
            std::chrono::seconds(std::int64_t{1} << doublings), kMaxLockout);
        s.lockedUntil = now + lockout;
    }
}

void PasswordThrottle::succeeded(std::string_view name) {
    const std::lock_guard lock(mutex_);
    names_.erase(std::string(name));
}

}  // namespace skillcell::http
