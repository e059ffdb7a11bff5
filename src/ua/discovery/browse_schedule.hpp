#pragma once
// BrowseSchedule: when a browser asks the network for every OPC UA server again (RFC 6762,
// 5.2). Only a process that wants to find others browses: a detector, an LDS, a server
// looking for its LDS. It asks at once, then after 1 s, 2 s, 4 s ... up to the longest
// interval (60 min by default): newcomers announce themselves, and the cache asks for each
// record before it expires, so repeated browsing only catches what was missed. When another
// host asks the same question and knows no server we do not, its answers reach us too: that
// counts as our query (7.3). Pure logic with the time passed in.
#include <chrono>
#include <optional>

#include "ua/discovery/service_cache.hpp"

namespace skillcell::ua::mdns {

class BrowseSchedule {
public:
    /// `longest`: the interval the backoff ends at (at least 100 ms).
    explicit BrowseSchedule(std::chrono::milliseconds longest);

    /// Begins browsing, or begins again from the shortest interval: the next query is due now.
    void restart(Clock::time_point now);
    [[nodiscard]] bool active() const { return next_.has_value(); }
    /// When the next query is due; none before restart().
    [[nodiscard]] std::optional<Clock::time_point> next() const { return next_; }
    /// Our query went out at `now`: the next waits twice as long as the last (up to the longest).
    void sent(Clock::time_point now);
    /// Another host asked our question at `now`, with no known answer we lack.
    void duplicateSeen(Clock::time_point now);

private:
    Clock::duration longest_;
    Clock::duration interval_;                           // the wait after the next query
    Clock::duration planned_ = Clock::duration::zero();  // the wait before the next query
    std::optional<Clock::time_point> next_;
};

}  // namespace skillcell::ua::mdns
