#pragma once
// View service set (OPC 10000-4, 5.8): Browse, BrowseNext, TranslateBrowsePathsToNodeIds,
// RegisterNodes, UnregisterNodes.
#include "ua/messages/common.hpp"

namespace skillcell::ua {

struct ViewDescription {
    NodeId viewId;
    DateTime timestamp;
    std::uint32_t viewVersion = 0;
    static auto tie(auto& s) { return std::tie(s.viewId, s.timestamp, s.viewVersion); }
};

/// BrowseResultMask bits (OPC 10000-4, 5.8.2.2).
namespace browse_result {
inline constexpr std::uint32_t kReferenceTypeId = 0x01;
inline constexpr std::uint32_t kIsForward = 0x02;
inline constexpr std::uint32_t kNodeClass = 0x04;
inline constexpr std::uint32_t kBrowseName = 0x08;
inline constexpr std::uint32_t kDisplayName = 0x10;
inline constexpr std::uint32_t kTypeDefinition = 0x20;
inline constexpr std::uint32_t kAll = 0x3F;
}  // namespace browse_result

struct BrowseDescription {
    NodeId nodeId;
    BrowseDirection browseDirection = BrowseDirection::Forward;
    NodeId referenceTypeId;
    bool includeSubtypes = true;
    std::uint32_t nodeClassMask = 0;  // 0: all node classes
    std::uint32_t resultMask = browse_result::kAll;
    static auto tie(auto& s) {
        return std::tie(s.nodeId, s.browseDirection, s.referenceTypeId, s.includeSubtypes,
                        s.nodeClassMask, s.resultMask);
    }
};

struct ReferenceDescription {
    NodeId referenceTypeId;
    bool isForward = true;
    ExpandedNodeId nodeId;
    QualifiedName browseName;
    LocalizedText displayName;
    NodeClass nodeClass = NodeClass::Unspecified;
    ExpandedNodeId typeDefinition;
    static auto tie(auto& s) {
        return std::tie(s.referenceTypeId, s.isForward, s.nodeId, s.browseName, s.displayName,
                        s.nodeClass, s.typeDefinition);
    }
};

struct BrowseResult {
    StatusCode statusCode;
    ByteString continuationPoint;
    std::vector<ReferenceDescription> references;
    static auto tie(auto& s) { return std::tie(s.statusCode, s.continuationPoint, s.references); }
};

struct BrowseRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 527;
    RequestHeader requestHeader;
    ViewDescription view;
    std::uint32_t requestedMaxReferencesPerNode = 0;
    std::vector<BrowseDescription> nodesToBrowse;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.view, s.requestedMaxReferencesPerNode, s.nodesToBrowse);
    }
};

struct BrowseResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 530;
    ResponseHeader responseHeader;
    std::vector<BrowseResult> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct BrowseNextRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 533;
    RequestHeader requestHeader;
    bool releaseContinuationPoints = false;
    std::vector<ByteString> continuationPoints;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.releaseContinuationPoints, s.continuationPoints);
    }
};

struct BrowseNextResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 536;
    ResponseHeader responseHeader;
    std::vector<BrowseResult> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct RelativePathElement {
    NodeId referenceTypeId;
    bool isInverse = false;
    bool includeSubtypes = true;
    QualifiedName targetName;
    static auto tie(auto& s) {
        return std::tie(s.referenceTypeId, s.isInverse, s.includeSubtypes, s.targetName);
    }
};

struct RelativePath {
    std::vector<RelativePathElement> elements;
    static auto tie(auto& s) { return std::tie(s.elements); }
};

struct BrowsePath {
    NodeId startingNode;
    RelativePath relativePath;
    static auto tie(auto& s) { return std::tie(s.startingNode, s.relativePath); }
};

struct BrowsePathTarget {
    ExpandedNodeId targetId;
    std::uint32_t remainingPathIndex = 0xFFFFFFFF;  // all elements processed
    static auto tie(auto& s) { return std::tie(s.targetId, s.remainingPathIndex); }
};

struct BrowsePathResult {
    StatusCode statusCode;
    std::vector<BrowsePathTarget> targets;
    static auto tie(auto& s) { return std::tie(s.statusCode, s.targets); }
};

struct TranslateBrowsePathsToNodeIdsRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 554;
    RequestHeader requestHeader;
    std::vector<BrowsePath> browsePaths;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.browsePaths); }
};

struct TranslateBrowsePathsToNodeIdsResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 557;
    ResponseHeader responseHeader;
    std::vector<BrowsePathResult> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct RegisterNodesRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 560;
    RequestHeader requestHeader;
    std::vector<NodeId> nodesToRegister;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.nodesToRegister); }
};

struct RegisterNodesResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 563;
    ResponseHeader responseHeader;
    std::vector<NodeId> registeredNodeIds;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.registeredNodeIds); }
};

struct UnregisterNodesRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 566;
    RequestHeader requestHeader;
    std::vector<NodeId> nodesToUnregister;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.nodesToUnregister); }
};

struct UnregisterNodesResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 569;
    ResponseHeader responseHeader;
    static auto tie(auto& s) { return std::tie(s.responseHeader); }
};

}  // namespace skillcell::ua
