#pragma once
// Data type definitions (OPC 10000-3, 5.8.3 and 8.48-8.52) and a data-driven codec for the
// structures they describe.
//
// A model's structured type (a 3D frame, a skill parameter record) is described by the
// StructureDefinition on its DataType node. DynamicStructure holds a value of such a type
// as ordered (name, Variant) fields, and encodeStructure/decodeStructure turn it into the
// binary encoding and back by walking the definition: no hand-written code per type.
//
// This header depends only on the encoding layer: the DataTypeRegistry is plain data that
// the address space fills from the DataType nodes it loads, and that a client could fill
// from a server's DataTypeDefinition attributes just as well.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <variant>
#include <vector>

#include "ua/encoding/codec.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

/// StructureType (i=98): how the fields of a structure are put on the wire.
enum class StructureType : std::int32_t {
    Structure = 0,
    StructureWithOptionalFields = 1,
    Union = 2,
    StructureWithSubtypedValues = 3,
    UnionWithSubtypedValues = 4,
};

/// StructureField (i=101), binary encoding i=14844.
struct StructureField {
    static constexpr std::uint32_t kBinaryEncodingId = 14844;
    String name;
    LocalizedText description;
    NodeId dataType;
    std::int32_t valueRank = -1;
    std::vector<std::uint32_t> arrayDimensions;
    std::uint32_t maxStringLength = 0;
    bool isOptional = false;
    static auto tie(auto& s) {
        return std::tie(s.name, s.description, s.dataType, s.valueRank, s.arrayDimensions,
                        s.maxStringLength, s.isOptional);
    }
    friend bool operator==(const StructureField&, const StructureField&) = default;
};

/// StructureDefinition (i=99), binary encoding i=122.
struct StructureDefinition {
    static constexpr std::uint32_t kBinaryEncodingId = 122;
    NodeId defaultEncodingId;
    NodeId baseDataType;
    StructureType structureType = StructureType::Structure;
    std::vector<StructureField> fields;
    static auto tie(auto& s) {
        return std::tie(s.defaultEncodingId, s.baseDataType, s.structureType, s.fields);
    }
    friend bool operator==(const StructureDefinition&, const StructureDefinition&) = default;
};

/// EnumField (i=102), binary encoding i=14845: EnumValueType's fields plus the Name.
struct EnumField {
    static constexpr std::uint32_t kBinaryEncodingId = 14845;
    std::int64_t value = 0;
    LocalizedText displayName;
    LocalizedText description;
    String name;
    static auto tie(auto& s) { return std::tie(s.value, s.displayName, s.description, s.name); }
    friend bool operator==(const EnumField&, const EnumField&) = default;
};

/// EnumDefinition (i=100), binary encoding i=123.
struct EnumDefinition {
    static constexpr std::uint32_t kBinaryEncodingId = 123;
    std::vector<EnumField> fields;
    static auto tie(auto& s) { return std::tie(s.fields); }
    friend bool operator==(const EnumDefinition&, const EnumDefinition&) = default;
};

/// The DataTypeDefinition attribute of a DataType node: absent, a structure or an enumeration.
using StructureOrEnumDefinition = std::variant<std::monostate, StructureDefinition, EnumDefinition>;

/// The DataTypeDefinition attribute value: an ExtensionObject holding the definition, or an
/// empty Variant for a data type without one.
[[nodiscard]] Variant dataTypeDefinitionValue(const StructureOrEnumDefinition& definition);

/// What the codec needs to know about one data type.
struct DataTypeInfo {
    NodeId dataTypeId;
    QualifiedName browseName;
    NodeId superType;         // null for BaseDataType
    NodeId binaryEncodingId;  // "Default Binary" encoding node, null if none
    NodeId xmlEncodingId;     // "Default XML" encoding node, null if none
    StructureOrEnumDefinition definition;
};

/// The data types a codec can resolve: by data type id, by encoding id and by browse name.
/// Lookups fall back to `fallback` (set by the NodeSet2 parser, which layers the types of
/// the file it reads over the address space's own registry).
class DataTypeRegistry {
public:
    DataTypeRegistry() = default;
    explicit DataTypeRegistry(const DataTypeRegistry* fallback) : fallback_(fallback) {}

    /// Adds or replaces the entry for info.dataTypeId.
    void add(DataTypeInfo info);
    [[nodiscard]] const DataTypeInfo* find(const NodeId& dataTypeId) const;
    /// The data type whose Default Binary or Default XML encoding is `encodingId`.
    [[nodiscard]] const DataTypeInfo* findByEncoding(const NodeId& encodingId) const;
    /// The first data type called `name` (any namespace), for XML bodies named by element.
    [[nodiscard]] const DataTypeInfo* findByName(std::string_view name) const;
    [[nodiscard]] std::size_t size() const { return types_.size(); }

    /// The built-in type that carries values of `dataTypeId` on the wire: the type itself
    /// for ids 1..25, the built-in supertype for simple subtypes (Duration -> Double), Int32
    /// for enumerations, ExtensionObject for structures. nullopt if the type is unknown.
    [[nodiscard]] std::optional<BuiltinType> builtinTypeOf(const NodeId& dataTypeId) const;
    /// The StructureDefinition of a concrete structured type, else nullptr.
    [[nodiscard]] const StructureDefinition* structureOf(const NodeId& dataTypeId) const;

private:
    std::unordered_map<NodeId, DataTypeInfo> types_;
    std::unordered_map<NodeId, NodeId> byEncoding_;
    const DataTypeRegistry* fallback_ = nullptr;
};

/// A value of a structured type described by a StructureDefinition: one Variant per field,
/// in definition order. Field values hold the field's built-in type (an array for
/// ValueRank >= 1); a nested structure is a binary ExtensionObject of that structure (use
/// decodeStructure on it to look inside); an absent optional field is an empty Variant; a
/// union has exactly one non-empty field (or none).
struct DynamicStructure {
    struct Field {
        String name;
        Variant value;
        friend bool operator==(const Field&, const Field&) = default;
    };
    NodeId dataTypeId;
    std::vector<Field> fields;

    [[nodiscard]] const Variant* get(std::string_view name) const;
    /// Sets an existing field; false if the structure has no field called `name`.
    bool set(std::string_view name, Variant value);
    friend bool operator==(const DynamicStructure&, const DynamicStructure&) = default;
};

/// A structure of `dataTypeId` with every field at its default (zero, empty; nested
/// structures default recursively). BadDataTypeIdUnknown if the type has no definition.
[[nodiscard]] Result<DynamicStructure> defaultStructure(const DataTypeRegistry& types,
                                                        const NodeId& dataTypeId);

/// Binary encoding of a structure's body (no ExtensionObject header). BadEncodingError for
/// a value that does not fit the definition (wrong field count, type or rank).
StatusCode encodeStructure(BinaryWriter& w, const DataTypeRegistry& types,
                           const DynamicStructure& value);
/// Decodes a body of `dataTypeId`. Truncated or malformed bytes give BadDecodingError,
/// lengths or nesting beyond the reader's limits BadEncodingLimitsExceeded.
StatusCode decodeStructure(BinaryReader& r, const DataTypeRegistry& types, const NodeId& dataTypeId,
                           DynamicStructure& out);

/// Wraps a structure into a binary ExtensionObject (type id = its Default Binary encoding).
[[nodiscard]] Result<ExtensionObject> toExtensionObject(const DataTypeRegistry& types,
                                                        const DynamicStructure& value);
/// Decodes a binary ExtensionObject whose encoding id the registry knows. Trailing bytes
/// are BadDecodingError; an unknown encoding BadDataTypeIdUnknown.
[[nodiscard]] Result<DynamicStructure> fromExtensionObject(const DataTypeRegistry& types,
                                                           const ExtensionObject& eo,
                                                           DecodeLimits limits = {});

}  // namespace skillcell::ua
