#pragma once
// Attribute service set (OPC 10000-4, 5.10): Read and Write.
#include <optional>
#include <string_view>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/messages/attribute.hpp"
#include "ua/server/server_limits.hpp"

namespace skillcell::ua {

/// One dimension of a NumericRange (OPC 10000-4, 7.27): elements first..last inclusive.
struct IndexRange {
    std::uint32_t first = 0;
    std::uint32_t last = 0;
};
/// Parses "3" or "1:3", dimensions separated by ','; nullopt for a malformed range
/// (including first >= last). An empty text gives an empty vector.
[[nodiscard]] std::optional<std::vector<IndexRange>> parseIndexRange(std::string_view text);

[[nodiscard]] DataValue readAttribute(const AddressSpace& as, const ReadValueId& item,
                                      TimestampsToReturn timestamps);
StatusCode read(const AddressSpace& as, const ServerLimits& limits, const ReadRequest& request,
                ReadResponse& response);

/// `caller` is handed to the variable's ValueSink.
[[nodiscard]] StatusCode writeAttribute(AddressSpace& as, const WriteValue& item,
                                        const Caller& caller = {});
StatusCode write(AddressSpace& as, const ServerLimits& limits, const WriteRequest& request,
                 WriteResponse& response, const Caller& caller = {});

}  // namespace skillcell::ua
