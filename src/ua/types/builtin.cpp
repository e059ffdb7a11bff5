#include "ua/types/builtin.hpp"

#include <cstdio>
#include <ctime>

namespace skillcell::ua {

DateTime DateTime::now() {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
    return fromUnixNanoseconds(ns);
}

std::string DateTime::toIso8601() const {
    const std::int64_t unixTicks = ticks - kUnixEpochTicks;
    std::int64_t secs = unixTicks / 10'000'000;
    std::int64_t rem = unixTicks % 10'000'000;
    if (rem < 0) {
        rem += 10'000'000;
        --secs;
    }
    const auto t = static_cast<std::time_t>(secs);
    std::tm tm{};
    gmtime_r(&t, &tm);
    std::array<char, 64> buf{};
    std::snprintf(buf.data(), buf.size(), "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900,
                  tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec,
                  static_cast<int>(rem / 10'000));
    return buf.data();
}

}  // namespace skillcell::ua
