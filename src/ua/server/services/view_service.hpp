#pragma once
// View service set (OPC 10000-4, 5.8): one function per operation, one per service.
#include "ua/address_space/address_space.hpp"
#include "ua/messages/view.hpp"
#include "ua/server/browse_continuation_points.hpp"
#include "ua/server/server_limits.hpp"

namespace skillcell::ua {

/// Browses one node. At most `maxReferences` references (0: unlimited) are returned; the
/// rest go into a continuation point in `points` (at most `maxContinuationPoints`).
[[nodiscard]] BrowseResult browseNode(const AddressSpace& as, BrowseContinuationPoints& points,
                                      const BrowseDescription& description,
                                      std::uint32_t maxReferences,
                                      std::size_t maxContinuationPoints);
StatusCode browse(const AddressSpace& as, BrowseContinuationPoints& points,
                  const ServerLimits& limits, const BrowseRequest& request,
                  BrowseResponse& response);

[[nodiscard]] BrowseResult browseNextOne(BrowseContinuationPoints& points,
                                         const ByteString& continuationPoint, bool release);
StatusCode browseNext(BrowseContinuationPoints& points, const ServerLimits& limits,
                      const BrowseNextRequest& request, BrowseNextResponse& response);

[[nodiscard]] BrowsePathResult translateBrowsePath(const AddressSpace& as, const BrowsePath& path);
StatusCode translateBrowsePathsToNodeIds(const AddressSpace& as, const ServerLimits& limits,
                                         const TranslateBrowsePathsToNodeIdsRequest& request,
                                         TranslateBrowsePathsToNodeIdsResponse& response);

/// RegisterNodes returns the ids unchanged: every node is already as fast to reach as a
/// registered one. BadNodeIdInvalid (service result) for a null NodeId.
StatusCode registerNodes(const ServerLimits& limits, const RegisterNodesRequest& request,
                         RegisterNodesResponse& response);
StatusCode unregisterNodes(const ServerLimits& limits, const UnregisterNodesRequest& request,
                           UnregisterNodesResponse& response);

}  // namespace skillcell::ua
