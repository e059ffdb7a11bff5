#pragma once
// Filters of monitored items (OPC 10000-4, 7.22 MonitoringFilter and 7.7 ContentFilter):
// DataChangeFilter, AggregateFilter, EventFilter and the content filter operands. Each
// structure that travels in an ExtensionObject carries its binary encoding id (checked
// against Schema/NodeIds.csv).
#include <cstdint>
#include <tuple>
#include <vector>

#include "ua/messages/common.hpp"
#include "ua/messages/view.hpp"

namespace skillcell::ua {

enum class DataChangeTrigger : std::int32_t {
    Status = 0,
    StatusValue = 1,
    StatusValueTimestamp = 2
};
enum class DeadbandType : std::uint32_t { None = 0, Absolute = 1, Percent = 2 };

struct DataChangeFilter {
    static constexpr std::uint32_t kBinaryEncodingId = 724;
    DataChangeTrigger trigger = DataChangeTrigger::StatusValue;
    std::uint32_t deadbandType = static_cast<std::uint32_t>(DeadbandType::None);
    double deadbandValue = 0;
    static auto tie(auto& s) { return std::tie(s.trigger, s.deadbandType, s.deadbandValue); }
};

struct AggregateConfiguration {
    bool useServerCapabilitiesDefaults = true;
    bool treatUncertainAsBad = false;
    std::uint8_t percentDataBad = 0;
    std::uint8_t percentDataGood = 0;
    bool useSlopedExtrapolation = false;
    static auto tie(auto& s) {
        return std::tie(s.useServerCapabilitiesDefaults, s.treatUncertainAsBad, s.percentDataBad,
                        s.percentDataGood, s.useSlopedExtrapolation);
    }
};

struct AggregateFilter {
    static constexpr std::uint32_t kBinaryEncodingId = 730;
    DateTime startTime;
    NodeId aggregateType;
    double processingInterval = 0;
    AggregateConfiguration aggregateConfiguration;
    static auto tie(auto& s) {
        return std::tie(s.startTime, s.aggregateType, s.processingInterval,
                        s.aggregateConfiguration);
    }
};

/// ContentFilter operators (OPC 10000-4, 7.7.3).
enum class FilterOperator : std::int32_t {
    Equals = 0,
    IsNull = 1,
    GreaterThan = 2,
    LessThan = 3,
    GreaterThanOrEqual = 4,
    LessThanOrEqual = 5,
    Like = 6,
    Not = 7,
    Between = 8,
    InList = 9,
    And = 10,
    Or = 11,
    Cast = 12,
    InView = 13,
    OfType = 14,
    RelatedTo = 15,
    BitwiseAnd = 16,
    BitwiseOr = 17
};

struct ElementOperand {
    static constexpr std::uint32_t kBinaryEncodingId = 594;
    std::uint32_t index = 0;
    static auto tie(auto& s) { return std::tie(s.index); }
};

struct LiteralOperand {
    static constexpr std::uint32_t kBinaryEncodingId = 597;
    Variant value;
    static auto tie(auto& s) { return std::tie(s.value); }
};

struct AttributeOperand {
    static constexpr std::uint32_t kBinaryEncodingId = 600;
    NodeId nodeId;
    String alias;
    RelativePath browsePath;
    std::uint32_t attributeId = static_cast<std::uint32_t>(AttributeId::Value);
    String indexRange;
    static auto tie(auto& s) {
        return std::tie(s.nodeId, s.alias, s.browsePath, s.attributeId, s.indexRange);
    }
};

/// An event field: a browse path relative to an event type (OPC 10000-4, 7.7.4.5).
struct SimpleAttributeOperand {
    static constexpr std::uint32_t kBinaryEncodingId = 603;
    NodeId typeDefinitionId;
    std::vector<QualifiedName> browsePath;
    std::uint32_t attributeId = static_cast<std::uint32_t>(AttributeId::Value);
    String indexRange;
    static auto tie(auto& s) {
        return std::tie(s.typeDefinitionId, s.browsePath, s.attributeId, s.indexRange);
    }
};

struct ContentFilterElement {
    static constexpr std::uint32_t kBinaryEncodingId = 585;
    FilterOperator filterOperator = FilterOperator::Equals;
    std::vector<ExtensionObject> filterOperands;  // one of the four operand types
    static auto tie(auto& s) { return std::tie(s.filterOperator, s.filterOperands); }
};

struct ContentFilter {
    static constexpr std::uint32_t kBinaryEncodingId = 588;
    std::vector<ContentFilterElement> elements;  // element 0 is the root of the expression
    static auto tie(auto& s) { return std::tie(s.elements); }
};

struct EventFilter {
    static constexpr std::uint32_t kBinaryEncodingId = 727;
    std::vector<SimpleAttributeOperand> selectClauses;
    ContentFilter whereClause;
    static auto tie(auto& s) { return std::tie(s.selectClauses, s.whereClause); }
};

struct ContentFilterElementResult {
    static constexpr std::uint32_t kBinaryEncodingId = 606;
    StatusCode statusCode;
    std::vector<StatusCode> operandStatusCodes;
    std::vector<DiagnosticInfo> operandDiagnosticInfos;
    static auto tie(auto& s) {
        return std::tie(s.statusCode, s.operandStatusCodes, s.operandDiagnosticInfos);
    }
};

struct ContentFilterResult {
    static constexpr std::uint32_t kBinaryEncodingId = 609;
    std::vector<ContentFilterElementResult> elementResults;
    std::vector<DiagnosticInfo> elementDiagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.elementResults, s.elementDiagnosticInfos); }
};

struct EventFilterResult {
    static constexpr std::uint32_t kBinaryEncodingId = 736;
    std::vector<StatusCode> selectClauseResults;
    std::vector<DiagnosticInfo> selectClauseDiagnosticInfos;
    ContentFilterResult whereClauseResult;
    static auto tie(auto& s) {
        return std::tie(s.selectClauseResults, s.selectClauseDiagnosticInfos, s.whereClauseResult);
    }
};

}  // namespace skillcell::ua
