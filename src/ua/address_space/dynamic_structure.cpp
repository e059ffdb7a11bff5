#include "ua/address_space/dynamic_structure.hpp"

#include <algorithm>

namespace skillcell::ua {
namespace {

constexpr std::uint32_t kStructure = 22;
constexpr std::uint32_t kBaseDataType = 24;
constexpr std::uint32_t kEnumeration = 29;
// A model's supertype chains are short; the bound only stops a cycle in a malformed model.
constexpr int kMaxSupertypeDepth = 64;

bool isArrayRank(std::int32_t valueRank) {
    return valueRank >= 0;
}

// --- One element of a field -------------------------------------------------------------

template <class T>
void encodeAlternative(BinaryWriter& w, const T& v) {
    encode(w, v);
}
template <class T>
void encodeAlternative(BinaryWriter& w, const Box<T>& v) {
    encode(w, *v);
}
inline void encodeAlternative(BinaryWriter&, const std::monostate&) {}

template <class T>
Scalar decodeAlternative(BinaryReader& r) {
    T v{};
    decode(r, v);
    return Scalar(std::move(v));
}

Scalar decodeBuiltin(BinaryReader& r, BuiltinType t) {
    switch (t) {
        case BuiltinType::Boolean:
            return decodeAlternative<bool>(r);
        case BuiltinType::SByte:
            return decodeAlternative<std::int8_t>(r);
        case BuiltinType::Byte:
            return decodeAlternative<std::uint8_t>(r);
        case BuiltinType::Int16:
            return decodeAlternative<std::int16_t>(r);
        case BuiltinType::UInt16:
            return decodeAlternative<std::uint16_t>(r);
        case BuiltinType::Int32:
            return decodeAlternative<std::int32_t>(r);
        case BuiltinType::UInt32:
            return decodeAlternative<std::uint32_t>(r);
        case BuiltinType::Int64:
            return decodeAlternative<std::int64_t>(r);
        case BuiltinType::UInt64:
            return decodeAlternative<std::uint64_t>(r);
        case BuiltinType::Float:
            return decodeAlternative<float>(r);
        case BuiltinType::Double:
            return decodeAlternative<double>(r);
        case BuiltinType::String:
            return decodeAlternative<String>(r);
        case BuiltinType::DateTime:
            return decodeAlternative<DateTime>(r);
        case BuiltinType::Guid:
            return decodeAlternative<Guid>(r);
        case BuiltinType::ByteString:
            return decodeAlternative<ByteString>(r);
        case BuiltinType::XmlElement:
            return decodeAlternative<XmlElement>(r);
        case BuiltinType::NodeId:
            return decodeAlternative<NodeId>(r);
        case BuiltinType::ExpandedNodeId:
            return decodeAlternative<ExpandedNodeId>(r);
        case BuiltinType::StatusCode:
            return decodeAlternative<StatusCode>(r);
        case BuiltinType::QualifiedName:
            return decodeAlternative<QualifiedName>(r);
        case BuiltinType::LocalizedText:
            return decodeAlternative<LocalizedText>(r);
        case BuiltinType::ExtensionObject:
            return decodeAlternative<ExtensionObject>(r);
        case BuiltinType::DataValue: {
            DataValue v;
            decode(r, v);
            return Scalar(Box<DataValue>(std::move(v)));
        }
        case BuiltinType::Variant: {
            Variant v;
            decode(r, v);
            return Scalar(Box<Variant>(std::move(v)));
        }
        case BuiltinType::DiagnosticInfo: {
            DiagnosticInfo v;
            decode(r, v);
            return Scalar(Box<DiagnosticInfo>(std::move(v)));
        }
        case BuiltinType::Null:
            break;
    }
    r.fail(status::BadDecodingError);
    return {};
}

/// The default value of one element: zero / empty of the built-in type.
Scalar defaultBuiltin(BuiltinType t) {
    Scalar s;
    switch (t) {
        case BuiltinType::Boolean:
            s = false;
            break;
        case BuiltinType::SByte:
            s = std::int8_t{};
            break;
        case BuiltinType::Byte:
            s = std::uint8_t{};
            break;
        case BuiltinType::Int16:
            s = std::int16_t{};
            break;
        case BuiltinType::UInt16:
            s = std::uint16_t{};
            break;
        case BuiltinType::Int32:
            s = std::int32_t{};
            break;
        case BuiltinType::UInt32:
            s = std::uint32_t{};
            break;
        case BuiltinType::Int64:
            s = std::int64_t{};
            break;
        case BuiltinType::UInt64:
            s = std::uint64_t{};
            break;
        case BuiltinType::Float:
            s = float{};
            break;
        case BuiltinType::Double:
            s = double{};
            break;
        case BuiltinType::String:
            s = String{};
            break;
        case BuiltinType::DateTime:
            s = DateTime{};
            break;
        case BuiltinType::Guid:
            s = Guid{};
            break;
        case BuiltinType::ByteString:
            s = ByteString{};
            break;
        case BuiltinType::XmlElement:
            s = XmlElement{};
            break;
        case BuiltinType::NodeId:
            s = NodeId{};
            break;
        case BuiltinType::ExpandedNodeId:
            s = ExpandedNodeId{};
            break;
        case BuiltinType::StatusCode:
            s = StatusCode{};
            break;
        case BuiltinType::QualifiedName:
            s = QualifiedName{};
            break;
        case BuiltinType::LocalizedText:
            s = LocalizedText{};
            break;
        case BuiltinType::ExtensionObject:
            s = ExtensionObject{};
            break;
        case BuiltinType::DataValue:
            s = Box<DataValue>();
            break;
        case BuiltinType::Variant:
            s = Box<Variant>();
            break;
        case BuiltinType::DiagnosticInfo:
            s = Box<DiagnosticInfo>();
            break;
        case BuiltinType::Null:
            break;
    }
    return s;
}

class StructureCodec {
public:
    explicit StructureCodec(const DataTypeRegistry& types) : types_(types) {}

    StatusCode encodeBody(BinaryWriter& w, const DynamicStructure& value, int depth) {
        if (depth > static_cast<int>(DecodeLimits{}.maxDepth)) {
            return status::BadEncodingLimitsExceeded;
        }
        const StructureDefinition* def = types_.structureOf(value.dataTypeId);
        if (def == nullptr) return status::BadDataTypeIdUnknown;
        if (value.fields.size() != def->fields.size()) return status::BadEncodingError;
        for (std::size_t i = 0; i < def->fields.size(); ++i) {
            if (value.fields[i].name != def->fields[i].name) return status::BadEncodingError;
        }
        switch (def->structureType) {
            case StructureType::Structure:
            case StructureType::StructureWithSubtypedValues:
                for (std::size_t i = 0; i < def->fields.size(); ++i) {
                    auto st = encodeField(w, def->fields[i], value.fields[i].value);
                    if (st.isBad()) return st;
                }
                return status::Good;
            case StructureType::StructureWithOptionalFields: {
                // The mask has one bit per optional field, in field order (OPC 10000-6, 5.2.7).
                std::uint32_t mask = 0;
                std::uint32_t bit = 0;
                for (std::size_t i = 0; i < def->fields.size(); ++i) {
                    if (!def->fields[i].isOptional) continue;
                    if (bit >= 32) return status::BadEncodingError;
                    if (!value.fields[i].value.isEmpty()) mask |= 1u << bit;
                    ++bit;
                }
                w.write(mask);
                for (std::size_t i = 0; i < def->fields.size(); ++i) {
                    if (def->fields[i].isOptional && value.fields[i].value.isEmpty()) continue;
                    auto st = encodeField(w, def->fields[i], value.fields[i].value);
                    if (st.isBad()) return st;
                }
                return status::Good;
            }
            case StructureType::Union:
            case StructureType::UnionWithSubtypedValues: {
                std::uint32_t chosen = 0;  // 1-based; 0 is the null union
                for (std::size_t i = 0; i < def->fields.size(); ++i) {
                    if (value.fields[i].value.isEmpty()) continue;
                    if (chosen != 0) return status::BadEncodingError;
                    chosen = static_cast<std::uint32_t>(i + 1);
                }
                w.write(chosen);
                if (chosen == 0) return status::Good;
                return encodeField(w, def->fields[chosen - 1], value.fields[chosen - 1].value);
            }
        }
        return status::BadEncodingError;
    }

    void decodeBody(BinaryReader& r, const NodeId& dataTypeId, DynamicStructure& out) {
        BinaryReader::DepthGuard guard(r);
        if (!r.ok()) return;
        const StructureDefinition* def = types_.structureOf(dataTypeId);
        if (def == nullptr) {
            r.fail(status::BadDataTypeIdUnknown);
            return;
        }
        out.dataTypeId = dataTypeId;
        out.fields.clear();
        out.fields.reserve(def->fields.size());
        for (const auto& f : def->fields) out.fields.push_back({f.name, Variant{}});
        switch (def->structureType) {
            case StructureType::Structure:
            case StructureType::StructureWithSubtypedValues:
                for (std::size_t i = 0; i < def->fields.size() && r.ok(); ++i) {
                    out.fields[i].value = decodeField(r, def->fields[i]);
                }
                return;
            case StructureType::StructureWithOptionalFields: {
                const auto mask = r.read<std::uint32_t>();
                std::uint32_t bit = 0;
                for (std::size_t i = 0; i < def->fields.size() && r.ok(); ++i) {
                    if (def->fields[i].isOptional) {
                        const bool present = bit < 32 && (mask & (1u << bit)) != 0;
                        ++bit;
                        if (!present) continue;
                    }
                    out.fields[i].value = decodeField(r, def->fields[i]);
                }
                return;
            }
            case StructureType::Union:
            case StructureType::UnionWithSubtypedValues: {
                const auto chosen = r.read<std::uint32_t>();
                if (!r.ok() || chosen == 0) return;
                if (chosen > def->fields.size()) {
                    r.fail(status::BadDecodingError);
                    return;
                }
                out.fields[chosen - 1].value = decodeField(r, def->fields[chosen - 1]);
                return;
            }
        }
        r.fail(status::BadDecodingError);
    }

    Result<DynamicStructure> makeDefault(const NodeId& dataTypeId, int depth) {
        if (depth > static_cast<int>(DecodeLimits{}.maxDepth)) {
            return status::BadEncodingLimitsExceeded;
        }
        const StructureDefinition* def = types_.structureOf(dataTypeId);
        if (def == nullptr) return status::BadDataTypeIdUnknown;
        DynamicStructure out;
        out.dataTypeId = dataTypeId;
        for (const auto& f : def->fields) {
            Variant v;
            const bool optional =
                (def->structureType == StructureType::StructureWithOptionalFields &&
                 f.isOptional) ||
                def->structureType == StructureType::Union ||
                def->structureType == StructureType::UnionWithSubtypedValues;
            if (!optional && !isArrayRank(f.valueRank)) {
                if (types_.structureOf(f.dataType) != nullptr) {
                    auto nested = makeDefault(f.dataType, depth + 1);
                    if (!nested) return nested.status();
                    auto eo = wrap(*nested, depth + 1);
                    if (!eo) return eo.status();
                    v = std::move(*eo);
                } else if (auto bt = types_.builtinTypeOf(f.dataType)) {
                    if (*bt != BuiltinType::Variant) v = Variant::fromScalar(defaultBuiltin(*bt));
                } else {
                    return status::BadDataTypeIdUnknown;
                }
            }
            out.fields.push_back({f.name, std::move(v)});
        }
        return out;
    }

    Result<ExtensionObject> wrap(const DynamicStructure& value, int depth) {
        const DataTypeInfo* info = types_.find(value.dataTypeId);
        if (info == nullptr || info->binaryEncodingId.isNull()) return status::BadDataTypeIdUnknown;
        ExtensionObject eo;
        eo.typeId = info->binaryEncodingId;
        eo.encoding = ExtensionObject::Encoding::Binary;
        BinaryWriter w(eo.body.bytes);
        auto st = encodeBody(w, value, depth);
        if (st.isBad()) return st;
        if (w.status().isBad()) return w.status();
        return eo;
    }

private:
    StatusCode encodeField(BinaryWriter& w, const StructureField& f, const Variant& v) {
        const StructureDefinition* nested = types_.structureOf(f.dataType);
        const auto bt = nested != nullptr ? std::optional(BuiltinType::ExtensionObject)
                                          : types_.builtinTypeOf(f.dataType);
        if (!bt) return status::BadDataTypeIdUnknown;
        if (*bt == BuiltinType::Variant && !isArrayRank(f.valueRank)) {
            encode(w, v);  // BaseDataType: the field is a Variant of any type
            return status::Good;
        }
        if (isArrayRank(f.valueRank)) {
            if (v.isEmpty()) {
                w.write(std::int32_t{-1});
                return status::Good;
            }
            if (!v.isArray() || v.type() != *bt) return status::BadEncodingError;
            const auto& el = v.elements();
            if (el.size() > static_cast<std::size_t>(INT32_MAX)) {
                return status::BadEncodingLimitsExceeded;
            }
            w.write(el.empty() ? std::int32_t{-1} : static_cast<std::int32_t>(el.size()));
            for (const auto& e : el) {
                auto st = encodeElement(w, f, nested, *bt, e);
                if (st.isBad()) return st;
            }
            return status::Good;
        }
        if (v.isArray()) return status::BadEncodingError;
        return encodeElement(w, f, nested, *bt, v.scalar());
    }

    StatusCode encodeElement(BinaryWriter& w, const StructureField& f,
                             const StructureDefinition* nested, BuiltinType bt, const Scalar& s) {
        if (static_cast<BuiltinType>(s.index()) != bt) return status::BadEncodingError;
        if (nested != nullptr) {
            // A field of a concrete structured type is the structure's body, inline: the
            // ExtensionObject that holds it in DynamicStructure is unwrapped and checked.
            const auto& eo = std::get<ExtensionObject>(s);
            const DataTypeInfo* info = types_.find(f.dataType);
            if (eo.encoding != ExtensionObject::Encoding::Binary || info == nullptr ||
                (eo.typeId != info->binaryEncodingId && eo.typeId != f.dataType)) {
                return status::BadEncodingError;
            }
            BinaryReader check(eo.body.bytes);
            DynamicStructure inner;
            decodeBody(check, f.dataType, inner);
            if (!check.ok() || check.remaining() != 0) return status::BadEncodingError;
            w.writeBytes(eo.body.bytes);
            return status::Good;
        }
        std::visit([&w](const auto& x) { encodeAlternative(w, x); }, s);
        return status::Good;
    }

    Variant decodeField(BinaryReader& r, const StructureField& f) {
        const StructureDefinition* nested = types_.structureOf(f.dataType);
        const auto bt = nested != nullptr ? std::optional(BuiltinType::ExtensionObject)
                                          : types_.builtinTypeOf(f.dataType);
        if (!bt) {
            r.fail(status::BadDataTypeIdUnknown);
            return {};
        }
        if (*bt == BuiltinType::Variant && !isArrayRank(f.valueRank)) {
            Variant v;
            decode(r, v);
            return v;
        }
        if (isArrayRank(f.valueRank)) {
            // Counted as at least one byte per element, so a length beyond the input is
            // refused before anything is reserved (an array of field-less structures, the
            // one case where that is not true, has no use).
            const auto n = r.readLength(r.limits().maxArrayLength, 1);
            std::vector<Scalar> elements;
            elements.reserve(std::min<std::size_t>(n, r.remaining()));
            for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
                elements.push_back(decodeElement(r, f, nested, *bt));
            }
            if (!r.ok()) return {};
            return Variant::array(*bt, std::move(elements));
        }
        auto s = decodeElement(r, f, nested, *bt);
        if (!r.ok()) return {};
        return Variant::fromScalar(std::move(s));
    }

    Scalar decodeElement(BinaryReader& r, const StructureField& f,
                         const StructureDefinition* nested, BuiltinType bt) {
        if (nested != nullptr) {
            DynamicStructure inner;
            decodeBody(r, f.dataType, inner);
            if (!r.ok()) return {};
            // The nested value is kept as a binary ExtensionObject of its own type; its
            // body is re-encoded from what was read, which is what the bytes said.
            auto eo = wrap(inner, 0);
            if (!eo) {
                r.fail(status::BadDecodingError);
                return {};
            }
            return Scalar(std::move(*eo));
        }
        return decodeBuiltin(r, bt);
    }

    const DataTypeRegistry& types_;
};

}  // namespace

Variant dataTypeDefinitionValue(const StructureOrEnumDefinition& definition) {
    if (const auto* s = std::get_if<StructureDefinition>(&definition)) {
        return toExtensionObject(*s);
    }
    if (const auto* e = std::get_if<EnumDefinition>(&definition)) return toExtensionObject(*e);
    return {};
}

void DataTypeRegistry::add(DataTypeInfo info) {
    if (!info.binaryEncodingId.isNull()) byEncoding_[info.binaryEncodingId] = info.dataTypeId;
    if (!info.xmlEncodingId.isNull()) byEncoding_[info.xmlEncodingId] = info.dataTypeId;
    NodeId id = info.dataTypeId;
    types_.insert_or_assign(std::move(id), std::move(info));
}

const DataTypeInfo* DataTypeRegistry::find(const NodeId& dataTypeId) const {
    auto it = types_.find(dataTypeId);
    if (it != types_.end()) return &it->second;
    return fallback_ != nullptr ? fallback_->find(dataTypeId) : nullptr;
}

const DataTypeInfo* DataTypeRegistry::findByEncoding(const NodeId& encodingId) const {
    auto it = byEncoding_.find(encodingId);
    if (it != byEncoding_.end()) return find(it->second);
    return fallback_ != nullptr ? fallback_->findByEncoding(encodingId) : nullptr;
}

const DataTypeInfo* DataTypeRegistry::findByName(std::string_view name) const {
    // Used only for XML bodies whose TypeId is unknown, so a scan is fine.
    for (const auto& [id, info] : types_) {
        if (info.browseName.name == name) return &info;
    }
    return fallback_ != nullptr ? fallback_->findByName(name) : nullptr;
}

std::optional<BuiltinType> DataTypeRegistry::builtinTypeOf(const NodeId& dataTypeId) const {
    NodeId current = dataTypeId;
    for (int depth = 0; depth < kMaxSupertypeDepth; ++depth) {
        if (current.namespaceIndex() == 0) {
            if (const auto* n = std::get_if<std::uint32_t>(&current.identifier())) {
                if (*n == kBaseDataType) return BuiltinType::Variant;
                if (*n == kEnumeration) return BuiltinType::Int32;
                if (*n == kStructure) return BuiltinType::ExtensionObject;
                if (*n >= 1 && *n <= kMaxBuiltinType) return static_cast<BuiltinType>(*n);
            }
        }
        const DataTypeInfo* info = find(current);
        if (info == nullptr) return std::nullopt;
        if (std::holds_alternative<EnumDefinition>(info->definition)) return BuiltinType::Int32;
        if (info->superType.isNull()) return std::nullopt;
        current = info->superType;
    }
    return std::nullopt;
}

const StructureDefinition* DataTypeRegistry::structureOf(const NodeId& dataTypeId) const {
    const DataTypeInfo* info = find(dataTypeId);
    if (info == nullptr) return nullptr;
    return std::get_if<StructureDefinition>(&info->definition);
}

const Variant* DynamicStructure::get(std::string_view name) const {
    for (const auto& f : fields) {
        if (f.name == name) return &f.value;
    }
    return nullptr;
}

bool DynamicStructure::set(std::string_view name, Variant value) {
    for (auto& f : fields) {
        if (f.name == name) {
            f.value = std::move(value);
            return true;
        }
    }
    return false;
}

Result<DynamicStructure> defaultStructure(const DataTypeRegistry& types, const NodeId& dataTypeId) {
    return StructureCodec(types).makeDefault(dataTypeId, 0);
}

StatusCode encodeStructure(BinaryWriter& w, const DataTypeRegistry& types,
                           const DynamicStructure& value) {
    auto st = StructureCodec(types).encodeBody(w, value, 0);
    if (st.isBad()) return st;
    return w.status();
}

StatusCode decodeStructure(BinaryReader& r, const DataTypeRegistry& types, const NodeId& dataTypeId,
                           DynamicStructure& out) {
    StructureCodec(types).decodeBody(r, dataTypeId, out);
    return r.status();
}

Result<ExtensionObject> toExtensionObject(const DataTypeRegistry& types,
                                          const DynamicStructure& value) {
    return StructureCodec(types).wrap(value, 0);
}

Result<DynamicStructure> fromExtensionObject(const DataTypeRegistry& types,
                                             const ExtensionObject& eo, DecodeLimits limits) {
    if (eo.encoding != ExtensionObject::Encoding::Binary) return status::BadDataTypeIdUnknown;
    const DataTypeInfo* info = types.findByEncoding(eo.typeId);
    if (info == nullptr) return status::BadDataTypeIdUnknown;
    BinaryReader r(eo.body.bytes, limits);
    DynamicStructure out;
    StructureCodec(types).decodeBody(r, info->dataTypeId, out);
    if (r.ok() && r.remaining() != 0) return status::BadDecodingError;
    if (!r.ok()) return r.status();
    return out;
}

}  // namespace skillcell::ua
