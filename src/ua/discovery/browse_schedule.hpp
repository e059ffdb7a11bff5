#pragma once
// BrowseSchedule: when a browser asks the network for every OPC UA server again (RFC 6762,
// 5.2). Only a process that wants to find others browses: a detector, an LDS, a server
// looking for its LDS. Its first query waits 20-120 ms, at random (5.2), then it asks again
// after 1 s, 2 s, 4 s ... up to the longest interval (60 min by default): newcomers announce
// themselves, and the cache asks for each record before it expires, so repeated browsing only
// catches what was missed. When another host asks the same question and knows no server we
// do not, its answers reach us too: that counts as our query (7.3). That is what the first
// query's wait is for: of the servers of a cell powered on together, each looking for its LDS,
// a few ask and the others hear the answers. Pure logic with the time passed in.
#include <chrono>
#include <optional>

#include "ua/discovery/service_cache.hpp"

namespace skillcell::ua::mdns {

class BrowseSchedule {
public:
    /// `longest`: the interval the backoff ends at (at least 100 ms).
    explicit BrowseSchedule(std::chrono::milliseconds longest);

    /// Begins browsing, or begins again from the shortest interval: the next query is due
    /// after `firstDelay` (a process's first, 5.2), or now (a query a user asked for).
    void restart(Clock::time_point now, Clock::duration firstDelay = Clock::duration::zero());
    [[nodiscard]] bool active() const { return next_.has_value(); }
    /// When the next query is due; none before restart().
    [[nodiscard]] std::optional<Clock::time_point> next() const { return next_; }
    /// Our query went out at `now`: the next waits twice as long as the last (up to the longest).
    void sent(Clock::time_point now);
    /// Another host asked our question at `now`, with no known answer we lack. While our first
    /// query waits, that always counts as it; later, only when ours was due within half its wait.
    /// The backoff then goes on from when ours was due. True when it counted as ours.
    bool duplicateSeen(Clock::time_point now);

private:
    Clock::duration longest_;
    Clock::duration interval_;                           // the wait after the next query
    Clock::duration planned_ = Clock::duration::zero();  // the wait before the next query
    std::optional<Clock::time_point> next_;
    bool firstPending_ = false;
};

}  // namespace skillcell::ua::mdns
