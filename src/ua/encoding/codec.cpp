#include "ua/encoding/codec.hpp"

#include <limits>

namespace skillcell::ua {
namespace {

void encodeLengthPrefixed(BinaryWriter& w, std::span<const std::uint8_t> bytes) {
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
        w.fail(status::BadEncodingLimitsExceeded);
        return;
    }
    // Empty encodes as null (-1); see builtin.hpp on null versus empty.
    w.write(bytes.empty() ? std::int32_t{-1} : static_cast<std::int32_t>(bytes.size()));
    w.writeBytes(bytes);
}

std::span<const std::uint8_t> decodeLengthPrefixed(BinaryReader& r, std::uint32_t max) {
    const auto n = r.readLength(max, 1);
    return r.readBytes(n);
}

std::span<const std::uint8_t> asBytes(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// NodeId encoding byte values (OPC 10000-6, Table 6).
constexpr std::uint8_t kTwoByte = 0x00;
constexpr std::uint8_t kFourByte = 0x01;
constexpr std::uint8_t kNumeric = 0x02;
constexpr std::uint8_t kString = 0x03;
constexpr std::uint8_t kGuid = 0x04;
constexpr std::uint8_t kByteString = 0x05;
constexpr std::uint8_t kNamespaceUriFlag = 0x80;
constexpr std::uint8_t kServerIndexFlag = 0x40;

void encodeNodeId(BinaryWriter& w, const NodeId& v, std::uint8_t flags) {
    const auto ns = v.namespaceIndex();
    switch (v.idType()) {
        case NodeId::IdType::Numeric: {
            const auto id = v.numeric();
            if (ns == 0 && id <= 0xFF) {
                w.write<std::uint8_t>(kTwoByte | flags);
                w.write(static_cast<std::uint8_t>(id));
            } else if (ns <= 0xFF && id <= 0xFFFF) {
                w.write<std::uint8_t>(kFourByte | flags);
                w.write(static_cast<std::uint8_t>(ns));
                w.write(static_cast<std::uint16_t>(id));
            } else {
                w.write<std::uint8_t>(kNumeric | flags);
                w.write(ns);
                w.write(id);
            }
            return;
        }
        case NodeId::IdType::Text:
            w.write<std::uint8_t>(kString | flags);
            w.write(ns);
            encode(w, std::get<String>(v.identifier()));
            return;
        case NodeId::IdType::Uuid:
            w.write<std::uint8_t>(kGuid | flags);
            w.write(ns);
            encode(w, std::get<Guid>(v.identifier()));
            return;
        case NodeId::IdType::Opaque:
            w.write<std::uint8_t>(kByteString | flags);
            w.write(ns);
            encode(w, std::get<ByteString>(v.identifier()));
            return;
    }
}

/// Decodes a NodeId whose encoding byte has been read already (flags stripped).
NodeId decodeNodeIdBody(BinaryReader& r, std::uint8_t kind) {
    switch (kind) {
        case kTwoByte:
            return NodeId(0, r.read<std::uint8_t>());
        case kFourByte: {
            const auto ns = r.read<std::uint8_t>();
            return NodeId(ns, r.read<std::uint16_t>());
        }
        case kNumeric: {
            const auto ns = r.read<std::uint16_t>();
            return NodeId(ns, r.read<std::uint32_t>());
        }
        case kString: {
            const auto ns = r.read<std::uint16_t>();
            String s;
            decode(r, s);
            return NodeId(ns, std::move(s));
        }
        case kGuid: {
            const auto ns = r.read<std::uint16_t>();
            Guid g;
            decode(r, g);
            return NodeId(ns, g);
        }
        case kByteString: {
            const auto ns = r.read<std::uint16_t>();
            ByteString b;
            decode(r, b);
            return NodeId(ns, std::move(b));
        }
        default:
            r.fail(status::BadDecodingError);
            return {};
    }
}

void encodeScalar(BinaryWriter& w, const Scalar& s) {
    std::visit(
        [&w](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::monostate>) {
                w.fail(status::BadEncodingError);
            } else if constexpr (std::is_same_v<T, Box<DataValue>> ||
                                 std::is_same_v<T, Box<Variant>> ||
                                 std::is_same_v<T, Box<DiagnosticInfo>>) {
                encode(w, *v);
            } else {
                encode(w, v);
            }
        },
        s);
}

template <std::size_t I = 1>
Scalar decodeScalar(BinaryReader& r, std::uint8_t typeId) {
    if constexpr (I < std::variant_size_v<Scalar>) {
        if (typeId != I) return decodeScalar<I + 1>(r, typeId);
        using Alt = std::variant_alternative_t<I, Scalar>;
        Scalar out{std::in_place_index<I>};
        if constexpr (std::is_same_v<Alt, Box<DataValue>> || std::is_same_v<Alt, Box<Variant>> ||
                      std::is_same_v<Alt, Box<DiagnosticInfo>>) {
            decode(r, *std::get<I>(out));
        } else {
            decode(r, std::get<I>(out));
        }
        return out;
    } else {
        r.fail(status::BadDecodingError);
        return {};
    }
}

}  // namespace

void encode(BinaryWriter& w, bool v) {
    w.write<std::uint8_t>(v ? 1 : 0);
}
void decode(BinaryReader& r, bool& v) {
    v = r.read<std::uint8_t>() != 0;
}

void encode(BinaryWriter& w, const String& v) {
    encodeLengthPrefixed(w, asBytes(v));
}
void decode(BinaryReader& r, String& v) {
    auto bytes = decodeLengthPrefixed(r, r.limits().maxStringLength);
    v.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

void encode(BinaryWriter& w, const ByteString& v) {
    encodeLengthPrefixed(w, v.bytes);
}
void decode(BinaryReader& r, ByteString& v) {
    auto bytes = decodeLengthPrefixed(r, r.limits().maxByteStringLength);
    v.bytes.assign(bytes.begin(), bytes.end());
}

void encode(BinaryWriter& w, const XmlElement& v) {
    encode(w, v.xml);
}
void decode(BinaryReader& r, XmlElement& v) {
    decode(r, v.xml);
}

void encode(BinaryWriter& w, const DateTime& v) {
    w.write(v.ticks);
}
void decode(BinaryReader& r, DateTime& v) {
    v.ticks = r.read<std::int64_t>();
}

void encode(BinaryWriter& w, const Guid& v) {
    w.write(v.data1);
    w.write(v.data2);
    w.write(v.data3);
    w.writeBytes(v.data4);
}
void decode(BinaryReader& r, Guid& v) {
    v.data1 = r.read<std::uint32_t>();
    v.data2 = r.read<std::uint16_t>();
    v.data3 = r.read<std::uint16_t>();
    auto b = r.readBytes(8);
    if (b.size() == 8) std::copy(b.begin(), b.end(), v.data4.begin());
}

void encode(BinaryWriter& w, const NodeId& v) {
    encodeNodeId(w, v, 0);
}
void decode(BinaryReader& r, NodeId& v) {
    const auto kind = r.read<std::uint8_t>();
    if (!r.ok()) return;
    if ((kind & (kNamespaceUriFlag | kServerIndexFlag)) != 0) {
        r.fail(status::BadDecodingError);  // flags belong to ExpandedNodeId only
        return;
    }
    v = decodeNodeIdBody(r, kind);
}

void encode(BinaryWriter& w, const ExpandedNodeId& v) {
    std::uint8_t flags = 0;
    if (!v.namespaceUri.empty()) flags |= kNamespaceUriFlag;
    if (v.serverIndex != 0) flags |= kServerIndexFlag;
    encodeNodeId(w, v.nodeId, flags);
    if (!v.namespaceUri.empty()) encode(w, v.namespaceUri);
    if (v.serverIndex != 0) w.write(v.serverIndex);
}
void decode(BinaryReader& r, ExpandedNodeId& v) {
    const auto kind = r.read<std::uint8_t>();
    if (!r.ok()) return;
    v.nodeId = decodeNodeIdBody(r, kind & 0x3F);
    v.namespaceUri.clear();
    v.serverIndex = 0;
    if ((kind & kNamespaceUriFlag) != 0) decode(r, v.namespaceUri);
    if ((kind & kServerIndexFlag) != 0) v.serverIndex = r.read<std::uint32_t>();
}

void encode(BinaryWriter& w, StatusCode v) {
    w.write(v.code);
}
void decode(BinaryReader& r, StatusCode& v) {
    v.code = r.read<std::uint32_t>();
}

void encode(BinaryWriter& w, const QualifiedName& v) {
    w.write(v.namespaceIndex);
    encode(w, v.name);
}
void decode(BinaryReader& r, QualifiedName& v) {
    v.namespaceIndex = r.read<std::uint16_t>();
    decode(r, v.name);
}

void encode(BinaryWriter& w, const LocalizedText& v) {
    const std::uint8_t mask = (v.locale.empty() ? 0 : 0x01) | (v.text.empty() ? 0 : 0x02);
    w.write(mask);
    if ((mask & 0x01) != 0) encode(w, v.locale);
    if ((mask & 0x02) != 0) encode(w, v.text);
}
void decode(BinaryReader& r, LocalizedText& v) {
    const auto mask = r.read<std::uint8_t>();
    v = {};
    if ((mask & 0x01) != 0) decode(r, v.locale);
    if ((mask & 0x02) != 0) decode(r, v.text);
}

void encode(BinaryWriter& w, const ExtensionObject& v) {
    encode(w, v.typeId);
    w.write(static_cast<std::uint8_t>(v.encoding));
    if (v.encoding != ExtensionObject::Encoding::None) encode(w, v.body);
}
void decode(BinaryReader& r, ExtensionObject& v) {
    BinaryReader::DepthGuard guard(r);
    decode(r, v.typeId);
    const auto enc = r.read<std::uint8_t>();
    if (enc > 2) {
        r.fail(status::BadDecodingError);
        return;
    }
    v.encoding = static_cast<ExtensionObject::Encoding>(enc);
    v.body = {};
    if (v.encoding != ExtensionObject::Encoding::None) decode(r, v.body);
}

// Variant encoding mask (OPC 10000-6, 5.2.2.16).
constexpr std::uint8_t kArrayFlag = 0x80;
constexpr std::uint8_t kDimensionsFlag = 0x40;

void encode(BinaryWriter& w, const Variant& v) {
    const auto type = static_cast<std::uint8_t>(v.type());
    if (!v.isArray()) {
        w.write(type);
        if (!v.isEmpty()) encodeScalar(w, v.scalar());
        return;
    }
    const bool dims = !v.dimensions().empty();
    w.write(static_cast<std::uint8_t>(type | kArrayFlag | (dims ? kDimensionsFlag : 0)));
    w.write(static_cast<std::int32_t>(v.elements().size()));
    for (const auto& e : v.elements()) {
        if (e.index() != type) {
            w.fail(status::BadEncodingError);
            return;
        }
        encodeScalar(w, e);
    }
    if (dims) encode(w, v.dimensions());
}

void decode(BinaryReader& r, Variant& v) {
    BinaryReader::DepthGuard guard(r);
    const auto mask = r.read<std::uint8_t>();
    const std::uint8_t typeId = mask & 0x3F;
    v = {};
    if (!r.ok()) return;
    if (typeId > kMaxBuiltinType) {
        r.fail(status::BadDecodingError);
        return;
    }
    if ((mask & kArrayFlag) == 0) {
        if ((mask & kDimensionsFlag) != 0) {
            r.fail(status::BadDecodingError);
            return;
        }
        if (typeId == 0) return;
        Scalar s = decodeScalar(r, typeId);
        if (r.ok()) v = Variant::fromScalar(std::move(s));
        return;
    }
    const auto n = r.readLength(r.limits().maxArrayLength, 1);
    if (typeId == 0 && n != 0) {
        r.fail(status::BadDecodingError);  // an array of nothing has no meaning
        return;
    }
    std::vector<Scalar> elements;
    elements.reserve(n);
    for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
        elements.push_back(decodeScalar(r, typeId));
    }
    std::vector<std::int32_t> dims;
    if ((mask & kDimensionsFlag) != 0) {
        decode(r, dims);
        std::uint64_t product = 1;
        for (auto d : dims) {
            if (d < 0) {
                r.fail(status::BadDecodingError);
                return;
            }
            product *= static_cast<std::uint64_t>(d);
            if (product > n) break;
        }
        // An empty array may come with empty dimensions (node-opcua sends a matrix with no
        // value that way); any other array's dimensions must multiply to its length.
        if (r.ok() && (dims.empty() ? n != 0 : product != n)) {
            r.fail(status::BadDecodingError);
            return;
        }
    }
    if (!r.ok()) return;
    v = Variant::array(static_cast<BuiltinType>(typeId), std::move(elements), std::move(dims));
}

// DataValue encoding mask (OPC 10000-6, 5.2.2.17).
void encode(BinaryWriter& w, const DataValue& v) {
    std::uint8_t mask = 0;
    if (v.value) mask |= 0x01;
    if (v.status) mask |= 0x02;
    if (v.sourceTimestamp) mask |= 0x04;
    if (v.serverTimestamp) mask |= 0x08;
    if (v.sourcePicoseconds) mask |= 0x10;
    if (v.serverPicoseconds) mask |= 0x20;
    w.write(mask);
    if (v.value) encode(w, *v.value);
    if (v.status) encode(w, *v.status);
    if (v.sourceTimestamp) encode(w, *v.sourceTimestamp);
    if (v.sourcePicoseconds) w.write(*v.sourcePicoseconds);
    if (v.serverTimestamp) encode(w, *v.serverTimestamp);
    if (v.serverPicoseconds) w.write(*v.serverPicoseconds);
}
void decode(BinaryReader& r, DataValue& v) {
    BinaryReader::DepthGuard guard(r);
    const auto mask = r.read<std::uint8_t>();
    v = {};
    if ((mask & 0x01) != 0) decode(r, v.value.emplace());
    if ((mask & 0x02) != 0) decode(r, v.status.emplace());
    if ((mask & 0x04) != 0) decode(r, v.sourceTimestamp.emplace());
    if ((mask & 0x10) != 0) v.sourcePicoseconds = r.read<std::uint16_t>();
    if ((mask & 0x08) != 0) decode(r, v.serverTimestamp.emplace());
    if ((mask & 0x20) != 0) v.serverPicoseconds = r.read<std::uint16_t>();
}

// DiagnosticInfo encoding mask (OPC 10000-6, 5.2.2.12). Wire order differs from bit order:
// Locale (0x08) precedes LocalizedText (0x04).
void encode(BinaryWriter& w, const DiagnosticInfo& v) {
    std::uint8_t mask = 0;
    if (v.symbolicId) mask |= 0x01;
    if (v.namespaceUri) mask |= 0x02;
    if (v.localizedText) mask |= 0x04;
    if (v.locale) mask |= 0x08;
    if (v.additionalInfo) mask |= 0x10;
    if (v.innerStatusCode) mask |= 0x20;
    if (v.innerDiagnosticInfo) mask |= 0x40;
    w.write(mask);
    if (v.symbolicId) w.write(*v.symbolicId);
    if (v.namespaceUri) w.write(*v.namespaceUri);
    if (v.locale) w.write(*v.locale);
    if (v.localizedText) w.write(*v.localizedText);
    if (v.additionalInfo) encode(w, *v.additionalInfo);
    if (v.innerStatusCode) encode(w, *v.innerStatusCode);
    if (v.innerDiagnosticInfo) encode(w, **v.innerDiagnosticInfo);
}
void decode(BinaryReader& r, DiagnosticInfo& v) {
    BinaryReader::DepthGuard guard(r);
    const auto mask = r.read<std::uint8_t>();
    v = {};
    if ((mask & 0x01) != 0) v.symbolicId = r.read<std::int32_t>();
    if ((mask & 0x02) != 0) v.namespaceUri = r.read<std::int32_t>();
    if ((mask & 0x08) != 0) v.locale = r.read<std::int32_t>();
    if ((mask & 0x04) != 0) v.localizedText = r.read<std::int32_t>();
    if ((mask & 0x10) != 0) decode(r, v.additionalInfo.emplace());
    if ((mask & 0x20) != 0) decode(r, v.innerStatusCode.emplace());
    if ((mask & 0x40) != 0 && r.ok()) decode(r, *v.innerDiagnosticInfo.emplace());
}

}  // namespace skillcell::ua
