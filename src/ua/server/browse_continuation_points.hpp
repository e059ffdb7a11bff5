#pragma once
// BrowseContinuationPoints: the Browse results a session still owes its client
// (OPC 10000-4, 5.8.2 and 7.9). Each session owns one; Browse stores the references that did
// not fit, BrowseNext hands them out and releases them.
//
// A continuation point holds a snapshot of the remaining references, not a cursor into the
// address space: a node added or removed between Browse and BrowseNext cannot invalidate it.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "ua/messages/view.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

struct ServiceContext;

class BrowseContinuationPoints {
public:
    struct Entry {
        ByteString id;
        std::vector<ReferenceDescription> remaining;
        std::uint32_t maxReferences = 0;  // per BrowseNext call; 0 = unlimited
    };

    BrowseContinuationPoints() = default;
    /// `maxPoints`: the session's limit (ServerLimits::maxBrowseContinuationPoints).
    explicit BrowseContinuationPoints(std::size_t maxPoints) : maxPoints_(maxPoints) {}

    /// Stores the remaining references; BadNoContinuationPoints when min(`limit`, the
    /// session's limit) points are already held.
    Result<ByteString> store(std::vector<ReferenceDescription> remaining,
                             std::uint32_t maxReferences, std::size_t limit);
    /// Removes and returns the entry; BadContinuationPointInvalid for an unknown id.
    Result<Entry> take(const ByteString& id);
    /// Frees every point (session closed, or the client asked to).
    void clear() { entries_.clear(); }
    [[nodiscard]] std::size_t size() const { return entries_.size(); }
    [[nodiscard]] std::size_t maxPoints() const { return maxPoints_; }

private:
    std::vector<Entry> entries_;  // at most maxBrowseContinuationPoints (small): linear scans
    std::uint64_t nextId_ = 1;
    std::size_t maxPoints_ = std::numeric_limits<std::size_t>::max();
};

/// The calling session's continuation points. Declared here so that the services do not
/// depend on the Session class; defined by the server (session.cpp).
BrowseContinuationPoints& continuationPointsOf(ServiceContext& ctx);

}  // namespace skillcell::ua
