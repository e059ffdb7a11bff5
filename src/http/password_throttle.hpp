#pragma once
// PasswordThrottle: slows down guessing of the cell's passwords over HTTP. Each check costs
// a scrypt hash on purpose (tens of milliseconds), so unlimited guesses would both find weak
// passwords and load the host. After kFreeFailures wrong passwords for one user name in a row,
// further checks of that name are refused without hashing, for 1 s, then 2 s, 4 s … up to
// kMaxLockout; a right password ends the series. Names that do not exist count the same, so
// that the answers do not tell which names do. Thread-safe.
#include <chrono>
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace skillcell::http {

class PasswordThrottle {
public:
    using Clock = std::chrono::steady_clock;
    static constexpr int kFreeFailures = 5;
    static constexpr std::chrono::seconds kMaxLockout{300};
    static constexpr std::size_t kMaxNames = 4096;  // beyond: the oldest series are dropped

    /// How long checks of `name` are still refused; nothing when one may go ahead.
    [[nodiscard]] std::optional<std::chrono::seconds> refusedFor(
        std::string_view name, Clock::time_point now = Clock::now());
    /// A check of `name` failed: counts, and locks once there are more than kFreeFailures.
    void failed(std::string_view name, Clock::time_point now = Clock::now());
    /// A check of `name` succeeded: its series ends.
    void succeeded(std::string_view name);

private:
    struct Series {
        int failures = 0;
        Clock::time_point lockedUntil;
        Clock::time_point last;
    };
    std::mutex mutex_;
    std::unordered_map<std::string, Series> names_;
};

}  // namespace skillcell::http
