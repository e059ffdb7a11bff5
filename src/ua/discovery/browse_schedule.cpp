#include "ua/discovery/browse_schedule.hpp"

#include <algorithm>

namespace skillcell::ua::mdns {

namespace {
constexpr Clock::duration kFirstInterval = std::chrono::seconds(1);
}

BrowseSchedule::BrowseSchedule(std::chrono::milliseconds longest)
    : longest_(std::max<Clock::duration>(longest, std::chrono::milliseconds(100))),
      interval_(std::min(kFirstInterval, longest_)) {}

void BrowseSchedule::restart(Clock::time_point now, Clock::duration firstDelay) {
    interval_ = std::min(kFirstInterval, longest_);
    next_ = now + firstDelay;
    planned_ = firstDelay;
    firstPending_ = true;
}

void BrowseSchedule::sent(Clock::time_point now) {
    if (!next_) return;
    firstPending_ = false;
    next_ = now + interval_;
    planned_ = interval_;
    interval_ = std::min(interval_ * 2, longest_);
}

bool BrowseSchedule::duplicateSeen(Clock::time_point now) {
    // Only a query we are about to send counts as sent: in the first half of the wait after
    // ours went out, the schedule stays, so that the backoff does not run twice as fast.
    if (!next_ || (!firstPending_ && *next_ - now > planned_ / 2)) return false;
    // As if ours had gone out when it was due, not now: every host that heard this question
    // would otherwise ask again at one instant, all of them, at each step of the backoff.
    sent(*next_);
    return true;
}

}  // namespace skillcell::ua::mdns
