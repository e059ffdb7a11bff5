#pragma once
// The IRIs of skillcell's core OPC UA ontology (models/owl/opcua-core.ttl): what the NodeSet
// converter writes about nodes beyond the NodeSet's own types and reference types. Kept in
// one place so that the converter, the queries and the core ontology agree; a test checks
// that every term used here is declared there.
#include <string>
#include <string_view>

namespace skillcell::kb::owl {

inline constexpr std::string_view kCoreOntologyIri = "http://skillcell.dev/ontology/opcua";
inline constexpr std::string_view kOpc = "http://skillcell.dev/ontology/opcua#";

[[nodiscard]] inline std::string opc(std::string_view localName) {
    return std::string(kOpc) + std::string(localName);
}

// Terms, by local name (the core ontology declares each).
namespace term {
// Classes: one per node class.
inline constexpr std::string_view kObjectNode = "ObjectNode";
inline constexpr std::string_view kVariableNode = "VariableNode";
inline constexpr std::string_view kMethodNode = "MethodNode";
inline constexpr std::string_view kObjectTypeNode = "ObjectTypeNode";
inline constexpr std::string_view kVariableTypeNode = "VariableTypeNode";
inline constexpr std::string_view kReferenceTypeNode = "ReferenceTypeNode";
inline constexpr std::string_view kDataTypeNode = "DataTypeNode";
inline constexpr std::string_view kViewNode = "ViewNode";
// Data properties: attributes.
inline constexpr std::string_view kNodeId = "nodeId";
inline constexpr std::string_view kBrowseName = "browseName";
inline constexpr std::string_view kIsAbstract = "isAbstract";
inline constexpr std::string_view kValueRank = "valueRank";
inline constexpr std::string_view kValue = "value";
inline constexpr std::string_view kEngineeringUnits = "engineeringUnits";
inline constexpr std::string_view kEuRangeLow = "euRangeLow";
inline constexpr std::string_view kEuRangeHigh = "euRangeHigh";
// Object properties.
inline constexpr std::string_view kDataType = "dataType";
}  // namespace term

}  // namespace skillcell::kb::owl
