#include "ua/nodeset/nodeset_snapshot.hpp"

#include <tuple>

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {

namespace {

// Bump when the layout below changes: a snapshot of another version is Malformed.
constexpr std::string_view kMagic = "skillcell NodeSet snapshot 2";

// The layout: the magic, the source name, the file's NamespaceUris with the indices they
// were mapped to, the models, the nodes (attributes, value, definition, references, line)
// and the data types. Each is the OPC UA binary encoding of its fields in this order.

// An optional date (a model's PublicationDate): whether it is there, then the date.
void encode(BinaryWriter& w, const std::optional<DateTime>& d) {
    encode(w, d.has_value());
    if (d) encode(w, *d);
}
void decode(BinaryReader& r, std::optional<DateTime>& d) {
    bool present = false;
    decode(r, present);
    if (present) decode(r, d.emplace());
}

void encodeLine(BinaryWriter& w, std::size_t line) {
    encode(w, static_cast<std::uint32_t>(line));
}
void decodeLine(BinaryReader& r, std::size_t& line) {
    std::uint32_t v = 0;
    decode(r, v);
    line = v;
}

void encodeDefinition(BinaryWriter& w, const StructureOrEnumDefinition& d) {
    encode(w, static_cast<std::uint8_t>(d.index()));
    if (const auto* s = std::get_if<StructureDefinition>(&d)) encode(w, *s);
    if (const auto* e = std::get_if<EnumDefinition>(&d)) encode(w, *e);
}
void decodeDefinition(BinaryReader& r, StructureOrEnumDefinition& d) {
    std::uint8_t kind = 0;
    decode(r, kind);
    if (kind == 1) decode(r, d.emplace<StructureDefinition>());
    if (kind == 2) decode(r, d.emplace<EnumDefinition>());
    if (kind > 2) r.fail(status::BadDecodingError);
}

// Each record's fields, in snapshot order, for encode and decode alike (as the structures of
// the codec list theirs with `tie`).

/// A model, or a model it requires: URI, version, publication date.
auto identityOf(auto& m) {
    return std::tie(m.uri, m.version, m.publicationDate);
}
/// Every attribute a NodeSet2 file sets; the callbacks, references and cached supertype are
/// the address space's, made at commit.
auto attributesOf(auto& n) {
    return std::tie(n.nodeId, n.nodeClass, n.browseName, n.displayName, n.description, n.writeMask,
                    n.userWriteMask, n.isAbstract, n.symmetric, n.inverseName, n.containsNoLoops,
                    n.eventNotifier, n.value, n.dataType, n.valueRank, n.arrayDimensions,
                    n.accessLevel, n.userAccessLevel, n.minimumSamplingInterval, n.historizing,
                    n.executable, n.userExecutable, n.requiredRole);
}
auto fieldsOf(auto& ref) {
    return std::tie(ref.referenceTypeId, ref.target, ref.isForward);
}
auto dataTypeFieldsOf(auto& t) {
    return std::tie(t.dataTypeId, t.browseName, t.superType, t.binaryEncodingId, t.xmlEncodingId);
}

void encodeAll(BinaryWriter& w, const auto& fields) {
    std::apply([&w](const auto&... f) { (encode(w, f), ...); }, fields);
}
void decodeAll(BinaryReader& r, const auto& fields) {
    std::apply([&r](auto&... f) { (decode(r, f), ...); }, fields);
}

void encodeModel(BinaryWriter& w, const ParsedModel& m) {
    encodeAll(w, identityOf(m));
    encode(w, static_cast<std::uint32_t>(m.required.size()));
    for (const auto& req : m.required) encodeAll(w, identityOf(req));
    encodeLine(w, m.line);
}
void decodeModel(BinaryReader& r, ParsedModel& m) {
    decodeAll(r, identityOf(m));
    const auto n = r.readLength(r.remaining(), 1);
    for (std::uint32_t i = 0; i < n && r.ok(); ++i)
        decodeAll(r, identityOf(m.required.emplace_back()));
    decodeLine(r, m.line);
}

void encodeNode(BinaryWriter& w, const ParsedNode& pn) {
    encodeAll(w, attributesOf(pn.node));
    encodeDefinition(w, pn.node.definition);
    encode(w, static_cast<std::uint32_t>(pn.references.size()));
    for (const auto& ref : pn.references) {
        encodeAll(w, fieldsOf(ref));
        encodeLine(w, ref.line);
    }
    encodeLine(w, pn.line);
}
void decodeNode(BinaryReader& r, ParsedNode& pn) {
    decodeAll(r, attributesOf(pn.node));
    decodeDefinition(r, pn.node.definition);
    // A reference takes at least 9 bytes (two 2-byte NodeIds, the direction, the line).
    const auto refs = r.readLength(r.remaining(), 9);
    pn.references.reserve(refs);
    for (std::uint32_t i = 0; i < refs && r.ok(); ++i) {
        auto& ref = pn.references.emplace_back();
        decodeAll(r, fieldsOf(ref));
        decodeLine(r, ref.line);
    }
    decodeLine(r, pn.line);
}

void encodeDataType(BinaryWriter& w, const DataTypeInfo& t) {
    encodeAll(w, dataTypeFieldsOf(t));
    encodeDefinition(w, t.definition);
}
void decodeDataType(BinaryReader& r, DataTypeInfo& t) {
    decodeAll(r, dataTypeFieldsOf(t));
    decodeDefinition(r, t.definition);
}

}  // namespace

std::vector<std::uint8_t> encodeSnapshot(const ParsedNodeSet& parsed) {
    std::vector<std::uint8_t> out;
    BinaryWriter w(out);
    encode(w, String(kMagic));
    encode(w, parsed.source);
    encode(w, parsed.namespaceUris);
    for (const auto& uri : parsed.namespaceUris) {
        std::uint16_t index = 0;
        for (std::size_t i = 0; i < parsed.serverNamespaces.size(); ++i) {
            if (parsed.serverNamespaces[i] == uri) index = static_cast<std::uint16_t>(i);
        }
        encode(w, index);
    }
    encode(w, static_cast<std::uint32_t>(parsed.models.size()));
    for (const auto& m : parsed.models) encodeModel(w, m);
    encode(w, static_cast<std::uint32_t>(parsed.nodes.size()));
    for (const auto& pn : parsed.nodes) encodeNode(w, pn);
    encode(w, static_cast<std::uint32_t>(parsed.dataTypes.size()));
    for (const auto& t : parsed.dataTypes) encodeDataType(w, t);
    return out;
}

SnapshotDecode decodeSnapshot(const AddressSpace& as, std::span<const std::uint8_t> snapshot,
                              ParsedNodeSet& out) {
    out = ParsedNodeSet{};
    // The build's own bytes: the limits are the input's size, not a peer's allowance.
    const auto size = static_cast<std::uint32_t>(snapshot.size());
    BinaryReader r(snapshot, DecodeLimits{size, size, size, 32});
    String magic;
    decode(r, magic);
    if (!r.ok() || magic != kMagic) return SnapshotDecode::Malformed;
    decode(r, out.source);
    decode(r, out.namespaceUris);
    std::vector<std::uint16_t> made(out.namespaceUris.size());
    for (auto& index : made) decode(r, index);
    if (!r.ok()) return SnapshotDecode::Malformed;
    if (namespaceMap(as, out.namespaceUris) != made) return SnapshotDecode::OtherNamespaces;
    out.serverNamespaces = serverNamespaceTable(as, out.namespaceUris, made);

    // Counts are checked against what is left (each item takes at least a byte) before
    // anything is reserved.
    const auto models = r.readLength(r.remaining(), 1);
    for (std::uint32_t i = 0; i < models && r.ok(); ++i) decodeModel(r, out.models.emplace_back());
    const auto nodes = r.readLength(r.remaining(), 1);
    out.nodes.reserve(nodes);
    for (std::uint32_t i = 0; i < nodes && r.ok(); ++i) decodeNode(r, out.nodes.emplace_back());
    const auto types = r.readLength(r.remaining(), 1);
    out.dataTypes.reserve(types);
    for (std::uint32_t i = 0; i < types && r.ok(); ++i) {
        decodeDataType(r, out.dataTypes.emplace_back());
    }
    if (!r.ok() || r.remaining() != 0) {
        out = ParsedNodeSet{};
        return SnapshotDecode::Malformed;
    }
    return SnapshotDecode::Decoded;
}

}  // namespace skillcell::ua
