#pragma once
// Data Access structures (OPC 10000-8, 5.6): Range, the type of EURange and
// InstrumentRange, which bound what an analog variable (and a skill parameter) may hold.
#include "ua/messages/common.hpp"

namespace skillcell::ua {

struct Range {
    static constexpr std::uint32_t kBinaryEncodingId = 886;
    double low = 0;
    double high = 0;
    static auto tie(auto& s) { return std::tie(s.low, s.high); }
    friend bool operator==(const Range&, const Range&) = default;
};

}  // namespace skillcell::ua
