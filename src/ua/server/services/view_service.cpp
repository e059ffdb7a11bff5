#include "ua/server/services/view_service.hpp"

#include <algorithm>

#include "ua/server/services/operations.hpp"
#include "ua/server/services/register_services.hpp"

namespace skillcell::ua {
namespace {

bool referenceTypeMatches(const AddressSpace& as, const NodeId& actual, const NodeId& wanted,
                          bool includeSubtypes) {
    if (wanted.isNull()) return true;
    return includeSubtypes ? as.isSubtypeOf(actual, wanted) : actual == wanted;
}

ReferenceDescription describe(const AddressSpace& as, const Reference& r, const Node* target,
                              std::uint32_t mask) {
    ReferenceDescription d;
    d.nodeId.nodeId = r.target;
    if ((mask & browse_result::kReferenceTypeId) != 0) d.referenceTypeId = r.referenceTypeId;
    d.isForward = (mask & browse_result::kIsForward) != 0 && r.isForward;
    if (target == nullptr) return d;
    if ((mask & browse_result::kNodeClass) != 0) d.nodeClass = target->nodeClass;
    if ((mask & browse_result::kBrowseName) != 0) d.browseName = target->browseName;
    if ((mask & browse_result::kDisplayName) != 0) d.displayName = target->displayName;
    if ((mask & browse_result::kTypeDefinition) != 0 &&
        (target->nodeClass == NodeClass::Object || target->nodeClass == NodeClass::Variable)) {
        d.typeDefinition.nodeId = as.typeDefinitionOf(*target);
    }
    return d;
}

/// Moves the first `max` references into the result and the rest into a continuation point.
void page(BrowseResult& result, std::vector<ReferenceDescription> all, std::uint32_t max,
          BrowseContinuationPoints& points, std::size_t maxContinuationPoints) {
    if (max == 0 || all.size() <= max) {
        result.references = std::move(all);
        return;
    }
    std::vector<ReferenceDescription> rest(std::make_move_iterator(all.begin() + max),
                                           std::make_move_iterator(all.end()));
    all.resize(max);
    auto cp = points.store(std::move(rest), max, maxContinuationPoints);
    if (!cp) {
        result.statusCode = cp.status();
        return;
    }
    result.continuationPoint = std::move(*cp);
    result.references = std::move(all);
}

std::uint32_t effectiveMax(const ServerLimits& limits, std::uint32_t requested) {
    const std::uint32_t serverMax = limits.maxReferencesPerBrowse;
    if (requested == 0) return serverMax;
    return serverMax == 0 ? requested : std::min(requested, serverMax);
}

}  // namespace

BrowseResult browseNode(const AddressSpace& as, BrowseContinuationPoints& points,
                        const BrowseDescription& description, std::uint32_t maxReferences,
                        std::size_t maxContinuationPoints) {
    BrowseResult result;
    const auto dir = description.browseDirection;
    if (dir != BrowseDirection::Forward && dir != BrowseDirection::Inverse &&
        dir != BrowseDirection::Both) {
        result.statusCode = status::BadBrowseDirectionInvalid;
        return result;
    }
    const Node* node = as.find(description.nodeId);
    if (node == nullptr) {
        result.statusCode = status::BadNodeIdUnknown;
        return result;
    }
    if (!description.referenceTypeId.isNull() && !as.isReferenceType(description.referenceTypeId)) {
        result.statusCode = status::BadReferenceTypeIdInvalid;
        return result;
    }
    std::vector<ReferenceDescription> all;
    for (const auto& r : node->references) {
        if ((dir == BrowseDirection::Forward && !r.isForward) ||
            (dir == BrowseDirection::Inverse && r.isForward)) {
            continue;
        }
        if (!referenceTypeMatches(as, r.referenceTypeId, description.referenceTypeId,
                                  description.includeSubtypes)) {
            continue;
        }
        const Node* target = as.find(r.target);
        if (description.nodeClassMask != 0 &&
            (target == nullptr ||
             (description.nodeClassMask & static_cast<std::uint32_t>(target->nodeClass)) == 0)) {
            continue;
        }
        all.push_back(describe(as, r, target, description.resultMask));
    }
    page(result, std::move(all), maxReferences, points, maxContinuationPoints);
    return result;
}

StatusCode browse(const AddressSpace& as, BrowseContinuationPoints& points,
                  const ServerLimits& limits, const BrowseRequest& request,
                  BrowseResponse& response) {
    if (!request.view.viewId.isNull()) {
        const Node* view = as.find(request.view.viewId);
        if (view == nullptr || view->nodeClass != NodeClass::View) return status::BadViewIdUnknown;
    }
    const std::uint32_t max = effectiveMax(limits, request.requestedMaxReferencesPerNode);
    return forEachOperation(
        limits, request.nodesToBrowse, response.results, [&](const BrowseDescription& d) {
            return browseNode(as, points, d, max, limits.maxBrowseContinuationPoints);
        });
}

BrowseResult browseNextOne(BrowseContinuationPoints& points, const ByteString& continuationPoint,
                           bool release) {
    BrowseResult result;
    auto entry = points.take(continuationPoint);
    if (!entry) {
        result.statusCode = entry.status();
        return result;
    }
    if (release) return result;
    // The point just taken frees a slot, so storing the remainder cannot fail.
    page(result, std::move(entry->remaining), entry->maxReferences, points, points.size() + 1);
    return result;
}

StatusCode browseNext(BrowseContinuationPoints& points, const ServerLimits& limits,
                      const BrowseNextRequest& request, BrowseNextResponse& response) {
    return forEachOperation(limits, request.continuationPoints, response.results,
                            [&](const ByteString& cp) {
                                return browseNextOne(points, cp, request.releaseContinuationPoints);
                            });
}

BrowsePathResult translateBrowsePath(const AddressSpace& as, const BrowsePath& path) {
    BrowsePathResult result;
    const auto& elements = path.relativePath.elements;
    if (elements.empty()) {
        result.statusCode = status::BadNothingToDo;
        return result;
    }
    for (const auto& e : elements) {
        if (e.targetName.name.empty()) {
            result.statusCode = status::BadBrowseNameInvalid;
            return result;
        }
    }
    if (as.find(path.startingNode) == nullptr) {
        result.statusCode = status::BadNodeIdUnknown;
        return result;
    }
    std::vector<NodeId> current{path.startingNode};
    for (const auto& e : elements) {
        std::vector<NodeId> next;
        for (const auto& id : current) {
            const Node* n = as.find(id);
            if (n == nullptr) continue;
            for (const auto& r : n->references) {
                if (r.isForward == e.isInverse) continue;
                if (!referenceTypeMatches(as, r.referenceTypeId, e.referenceTypeId,
                                          e.includeSubtypes)) {
                    continue;
                }
                const Node* t = as.find(r.target);
                if (t == nullptr || t->browseName != e.targetName) continue;
                if (std::find(next.begin(), next.end(), r.target) == next.end()) {
                    next.push_back(r.target);
                }
            }
        }
        if (next.empty()) {
            result.statusCode = status::BadNoMatch;
            return result;
        }
        current = std::move(next);
    }
    for (auto& id : current) {
        result.targets.push_back(
            BrowsePathTarget{ExpandedNodeId{std::move(id), {}, 0}, 0xFFFFFFFF});
    }
    return result;
}

StatusCode translateBrowsePathsToNodeIds(const AddressSpace& as, const ServerLimits& limits,
                                         const TranslateBrowsePathsToNodeIdsRequest& request,
                                         TranslateBrowsePathsToNodeIdsResponse& response) {
    return forEachOperation(limits, request.browsePaths, response.results,
                            [&](const BrowsePath& p) { return translateBrowsePath(as, p); });
}

StatusCode registerNodes(const ServerLimits& limits, const RegisterNodesRequest& request,
                         RegisterNodesResponse& response) {
    const auto& ids = request.nodesToRegister;
    if (ids.empty()) return status::BadNothingToDo;
    if (ids.size() > limits.maxOperationsPerRequest) return status::BadTooManyOperations;
    for (const auto& id : ids) {
        if (id.isNull()) return status::BadNodeIdInvalid;
    }
    response.registeredNodeIds = ids;
    return status::Good;
}

StatusCode unregisterNodes(const ServerLimits& limits, const UnregisterNodesRequest& request,
                           UnregisterNodesResponse& /*response*/) {
    const auto& ids = request.nodesToUnregister;
    if (ids.empty()) return status::BadNothingToDo;
    if (ids.size() > limits.maxOperationsPerRequest) return status::BadTooManyOperations;
    for (const auto& id : ids) {
        if (id.isNull()) return status::BadNodeIdInvalid;
    }
    return status::Good;
}

void registerViewServices(ServiceTable& table, AddressSpace& as) {
    using A = ServiceTable::Access;
    table.add<BrowseRequest, BrowseResponse>(
        A::ActivatedSession, [&as](ServiceContext& ctx, const auto& req, auto& resp) {
            return browse(as, continuationPointsOf(ctx), limitsOf(ctx), req, resp);
        });
    table.add<BrowseNextRequest, BrowseNextResponse>(
        A::ActivatedSession, [](ServiceContext& ctx, const auto& req, auto& resp) {
            return browseNext(continuationPointsOf(ctx), limitsOf(ctx), req, resp);
        });
    table.add<TranslateBrowsePathsToNodeIdsRequest, TranslateBrowsePathsToNodeIdsResponse>(
        A::ActivatedSession, [&as](ServiceContext& ctx, const auto& req, auto& resp) {
            return translateBrowsePathsToNodeIds(as, limitsOf(ctx), req, resp);
        });
    table.add<RegisterNodesRequest, RegisterNodesResponse>(
        A::ActivatedSession, [](ServiceContext& ctx, const auto& req, auto& resp) {
            return registerNodes(limitsOf(ctx), req, resp);
        });
    table.add<UnregisterNodesRequest, UnregisterNodesResponse>(
        A::ActivatedSession, [](ServiceContext& ctx, const auto& req, auto& resp) {
            return unregisterNodes(limitsOf(ctx), req, resp);
        });
}

}  // namespace skillcell::ua
