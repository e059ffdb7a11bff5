#include "ua/discovery/browse_schedule.hpp"

#include <algorithm>

namespace skillcell::ua::mdns {

namespace {
constexpr Clock::duration kFirstInterval = std::chrono::seconds(1);
}

BrowseSchedule::BrowseSchedule(std::chrono::milliseconds longest)
    : longest_(std::max<Clock::duration>(longest, std::chrono::milliseconds(100))),
      interval_(std::min(kFirstInterval, longest_)) {}

void BrowseSchedule::restart(Clock::time_point now) {
    interval_ = std::min(kFirstInterval, longest_);
    next_ = now;
    planned_ = Clock::duration::zero();
}

void BrowseSchedule::sent(Clock::time_point now) {
    if (!next_) return;
    next_ = now + interval_;
    planned_ = interval_;
    interval_ = std::min(interval_ * 2, longest_);
}

void BrowseSchedule::duplicateSeen(Clock::time_point now) {
    // Only a query we are about to send counts as sent: in the first half of the wait after
    // ours went out, the schedule stays, so that the backoff does not run twice as fast.
    if (!next_ || *next_ - now > planned_ / 2) return;
    sent(now);
}

}  // namespace skillcell::ua::mdns
