#pragma once
// Binary encoding of the built-in types (OPC 10000-6, 5.2) and, generically, of every
// structure that lists its fields with a static `tie` (see Structure below).
//
// encode(w, value) / decode(r, value) are overloads, so a structure's codec is the fold of
// its fields' codecs: adding a service type means declaring its fields, nothing else.
#include <span>
#include <tuple>
#include <type_traits>
#include <vector>

#include "ua/encoding/binary_reader.hpp"
#include "ua/encoding/binary_writer.hpp"
#include "ua/types/variant.hpp"

namespace skillcell::ua {

// Numbers. Enumerations are Int32 on the wire, whatever their C++ underlying type.
template <class T>
concept Number = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

template <Number T>
void encode(BinaryWriter& w, T v) {
    w.write(v);
}
template <Number T>
void decode(BinaryReader& r, T& v) {
    v = r.read<T>();
}
void encode(BinaryWriter& w, bool v);
void decode(BinaryReader& r, bool& v);

template <class E>
requires std::is_enum_v<E>
void encode(BinaryWriter& w, E v) {
    w.write(static_cast<std::int32_t>(v));
}
template <class E>
requires std::is_enum_v<E>
void decode(BinaryReader& r, E& v) {
    v = static_cast<E>(r.read<std::int32_t>());
}

void encode(BinaryWriter& w, const String& v);
void decode(BinaryReader& r, String& v);
void encode(BinaryWriter& w, const ByteString& v);
void decode(BinaryReader& r, ByteString& v);
void encode(BinaryWriter& w, const XmlElement& v);
void decode(BinaryReader& r, XmlElement& v);
void encode(BinaryWriter& w, const DateTime& v);
void decode(BinaryReader& r, DateTime& v);
void encode(BinaryWriter& w, const Guid& v);
void decode(BinaryReader& r, Guid& v);
void encode(BinaryWriter& w, const NodeId& v);
void decode(BinaryReader& r, NodeId& v);
void encode(BinaryWriter& w, const ExpandedNodeId& v);
void decode(BinaryReader& r, ExpandedNodeId& v);
void encode(BinaryWriter& w, StatusCode v);
void decode(BinaryReader& r, StatusCode& v);
void encode(BinaryWriter& w, const QualifiedName& v);
void decode(BinaryReader& r, QualifiedName& v);
void encode(BinaryWriter& w, const LocalizedText& v);
void decode(BinaryReader& r, LocalizedText& v);
void encode(BinaryWriter& w, const ExtensionObject& v);
void decode(BinaryReader& r, ExtensionObject& v);
void encode(BinaryWriter& w, const Variant& v);
void decode(BinaryReader& r, Variant& v);
void encode(BinaryWriter& w, const DataValue& v);
void decode(BinaryReader& r, DataValue& v);
void encode(BinaryWriter& w, const DiagnosticInfo& v);
void decode(BinaryReader& r, DiagnosticInfo& v);

/// A structure declares its fields in wire order:
///   static auto tie(auto& s) { return std::tie(s.a, s.b, s.c); }
template <class T>
concept Structure = requires(T& t, const T& c) {
    T::tie(t);
    T::tie(c);
};

/// A structure that can travel in an ExtensionObject or as a service message.
template <class T>
concept EncodableStructure = Structure<T> && requires {
    { T::kBinaryEncodingId } -> std::convertible_to<std::uint32_t>;
};

template <Structure T>
void encode(BinaryWriter& w, const T& v) {
    std::apply([&w](const auto&... f) { (encode(w, f), ...); }, T::tie(v));
}
template <Structure T>
void decode(BinaryReader& r, T& v) {
    std::apply([&r](auto&... f) { (decode(r, f), ...); }, T::tie(v));
}

template <class T>
void encode(BinaryWriter& w, const std::vector<T>& v) {
    if (v.size() > static_cast<std::size_t>(INT32_MAX)) {
        w.fail(status::BadEncodingLimitsExceeded);
        return;
    }
    // Empty encodes as a null array (-1); see builtin.hpp on null versus empty.
    w.write(v.empty() ? std::int32_t{-1} : static_cast<std::int32_t>(v.size()));
    for (const auto& e : v) encode(w, e);
}
template <class T>
void decode(BinaryReader& r, std::vector<T>& v) {
    const auto n = r.readLength(r.limits().maxArrayLength, 1);
    v.clear();
    v.reserve(n);
    for (std::uint32_t i = 0; i < n && r.ok(); ++i) decode(r, v.emplace_back());
}

/// Wraps a structure into a binary-encoded ExtensionObject.
template <EncodableStructure T>
[[nodiscard]] ExtensionObject toExtensionObject(const T& value) {
    ExtensionObject eo;
    eo.typeId = NodeId(T::kBinaryEncodingId);
    eo.encoding = ExtensionObject::Encoding::Binary;
    BinaryWriter w(eo.body.bytes);
    encode(w, value);
    return eo;
}

/// Decodes an ExtensionObject holding a T. BadDataTypeIdUnknown if it holds another type,
/// BadDecodingError if its body is malformed or has bytes left over.
template <EncodableStructure T>
[[nodiscard]] StatusCode fromExtensionObject(const ExtensionObject& eo, T& out,
                                             DecodeLimits limits = {}) {
    if (eo.encoding != ExtensionObject::Encoding::Binary ||
        eo.typeId != NodeId(T::kBinaryEncodingId)) {
        return status::BadDataTypeIdUnknown;
    }
    BinaryReader r(eo.body.bytes, limits);
    decode(r, out);
    if (r.ok() && r.remaining() != 0) return status::BadDecodingError;
    return r.status();
}

/// Encodes a value into a fresh buffer (tests, tools).
template <class T>
[[nodiscard]] std::vector<std::uint8_t> encodeToBytes(const T& value) {
    std::vector<std::uint8_t> out;
    BinaryWriter w(out);
    encode(w, value);
    return out;
}

/// Decodes a whole buffer into `out`; trailing bytes are an error.
template <class T>
[[nodiscard]] StatusCode decodeFromBytes(std::span<const std::uint8_t> bytes, T& out,
                                         DecodeLimits limits = {}) {
    BinaryReader r(bytes, limits);
    decode(r, out);
    if (r.ok() && r.remaining() != 0) return status::BadDecodingError;
    return r.status();
}

}  // namespace skillcell::ua
