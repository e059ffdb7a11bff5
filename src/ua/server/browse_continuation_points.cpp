#include "ua/server/browse_continuation_points.hpp"

#include <algorithm>

namespace skillcell::ua {

Result<ByteString> BrowseContinuationPoints::store(std::vector<ReferenceDescription> remaining,
                                                   std::uint32_t maxReferences, std::size_t limit) {
    if (entries_.size() >= std::min(limit, maxPoints_)) return status::BadNoContinuationPoints;
    // A per-session counter is unique for the session's lifetime, which is all the
    // standard asks of a continuation point.
    ByteString id;
    id.bytes.resize(8);
    std::uint64_t v = nextId_++;
    for (auto& b : id.bytes) {
        b = static_cast<std::uint8_t>(v & 0xFF);
        v >>= 8;
    }
    entries_.push_back(Entry{id, std::move(remaining), maxReferences});
    return id;
}

Result<BrowseContinuationPoints::Entry> BrowseContinuationPoints::take(const ByteString& id) {
    auto it =
        std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.id == id; });
    if (it == entries_.end() || id.empty()) return status::BadContinuationPointInvalid;
    Entry e = std::move(*it);
    entries_.erase(it);
    return e;
}

}  // namespace skillcell::ua
