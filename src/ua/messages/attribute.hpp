#pragma once
// Attribute service set (OPC 10000-4, 5.10): Read, Write.
#include "ua/messages/common.hpp"

namespace skillcell::ua {

struct ReadValueId {
    NodeId nodeId;
    std::uint32_t attributeId = static_cast<std::uint32_t>(AttributeId::Value);
    String indexRange;
    QualifiedName dataEncoding;
    static auto tie(auto& s) {
        return std::tie(s.nodeId, s.attributeId, s.indexRange, s.dataEncoding);
    }
};

struct ReadRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 631;
    RequestHeader requestHeader;
    double maxAge = 0;
    TimestampsToReturn timestampsToReturn = TimestampsToReturn::Both;
    std::vector<ReadValueId> nodesToRead;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.maxAge, s.timestampsToReturn, s.nodesToRead);
    }
};

struct ReadResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 634;
    ResponseHeader responseHeader;
    std::vector<DataValue> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct WriteValue {
    NodeId nodeId;
    std::uint32_t attributeId = static_cast<std::uint32_t>(AttributeId::Value);
    String indexRange;
    DataValue value;
    static auto tie(auto& s) { return std::tie(s.nodeId, s.attributeId, s.indexRange, s.value); }
};

struct WriteRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 673;
    RequestHeader requestHeader;
    std::vector<WriteValue> nodesToWrite;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.nodesToWrite); }
};

struct WriteResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 676;
    ResponseHeader responseHeader;
    std::vector<StatusCode> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

}  // namespace skillcell::ua
