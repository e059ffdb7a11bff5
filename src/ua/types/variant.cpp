#include "ua/types/variant.hpp"

#include <array>

namespace skillcell::ua {

namespace {

constexpr std::array<std::string_view, kMaxBuiltinType + 1> kBuiltinTypeNames = {
    "Null",          "Boolean",       "SByte",           "Byte",           "Int16",
    "UInt16",        "Int32",         "UInt32",          "Int64",          "UInt64",
    "Float",         "Double",        "String",          "DateTime",       "Guid",
    "ByteString",    "XmlElement",    "NodeId",          "ExpandedNodeId", "StatusCode",
    "QualifiedName", "LocalizedText", "ExtensionObject", "DataValue",      "Variant",
    "DiagnosticInfo"};

}  // namespace

std::string_view builtinTypeName(BuiltinType type) {
    const auto i = static_cast<std::size_t>(type);
    return i < kBuiltinTypeNames.size() ? kBuiltinTypeNames[i] : std::string_view{};
}

std::optional<BuiltinType> builtinTypeByName(std::string_view name) {
    for (std::size_t i = 1; i < kBuiltinTypeNames.size(); ++i) {
        if (kBuiltinTypeNames[i] == name) return static_cast<BuiltinType>(i);
    }
    return std::nullopt;
}

Variant Variant::array(BuiltinType type, std::vector<Scalar> elements,
                       std::vector<std::int32_t> dimensions) {
    Variant v;
    v.isArray_ = true;
    v.arrayType_ = type;
    v.elements_ = std::move(elements);
    v.dimensions_ = std::move(dimensions);
    return v;
}

}  // namespace skillcell::ua
