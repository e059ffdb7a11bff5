#include "ua/nodeset/nodeset_snapshot.hpp"

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {

namespace {

// Bump when the layout below changes: a snapshot of another version is Malformed.
constexpr std::string_view kMagic = "skillcell NodeSet snapshot 1";

// The layout: the magic, the source name, the file's NamespaceUris with the indices they
// were mapped to, the models, the nodes (attributes, value, definition, references, line)
// and the data types. Each is the OPC UA binary encoding of its fields in this order.

void encodeDate(BinaryWriter& w, const std::optional<DateTime>& d) {
    encode(w, d.has_value());
    if (d) encode(w, *d);
}
void decodeDate(BinaryReader& r, std::optional<DateTime>& d) {
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

void encodeModel(BinaryWriter& w, const ParsedModel& m) {
    encode(w, m.uri);
    encode(w, m.version);
    encodeDate(w, m.publicationDate);
    encode(w, static_cast<std::uint32_t>(m.required.size()));
    for (const auto& req : m.required) {
        encode(w, req.uri);
        encode(w, req.version);
        encodeDate(w, req.publicationDate);
    }
    encodeLine(w, m.line);
}
void decodeModel(BinaryReader& r, ParsedModel& m) {
    decode(r, m.uri);
    decode(r, m.version);
    decodeDate(r, m.publicationDate);
    const auto n = r.readLength(r.remaining(), 1);
    for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
        auto& req = m.required.emplace_back();
        decode(r, req.uri);
        decode(r, req.version);
        decodeDate(r, req.publicationDate);
    }
    decodeLine(r, m.line);
}

// Every attribute a NodeSet2 file sets; the callbacks, references and cached supertype are
// the address space's, made at commit.
void encodeNode(BinaryWriter& w, const ParsedNode& pn) {
    const Node& n = pn.node;
    encode(w, n.nodeId);
    encode(w, n.nodeClass);
    encode(w, n.browseName);
    encode(w, n.displayName);
    encode(w, n.description);
    encode(w, n.writeMask);
    encode(w, n.userWriteMask);
    encode(w, n.isAbstract);
    encode(w, n.symmetric);
    encode(w, n.inverseName);
    encode(w, n.containsNoLoops);
    encode(w, n.eventNotifier);
    encode(w, n.value);
    encode(w, n.dataType);
    encode(w, n.valueRank);
    encode(w, n.arrayDimensions);
    encode(w, n.accessLevel);
    encode(w, n.userAccessLevel);
    encode(w, n.minimumSamplingInterval);
    encode(w, n.historizing);
    encode(w, n.executable);
    encode(w, n.userExecutable);
    encode(w, static_cast<std::uint8_t>(n.requiredRole));
    encodeDefinition(w, n.definition);
    encode(w, static_cast<std::uint32_t>(pn.references.size()));
    for (const auto& ref : pn.references) {
        encode(w, ref.referenceTypeId);
        encode(w, ref.target);
        encode(w, ref.isForward);
        encodeLine(w, ref.line);
    }
    encodeLine(w, pn.line);
}
void decodeNode(BinaryReader& r, ParsedNode& pn) {
    Node& n = pn.node;
    decode(r, n.nodeId);
    decode(r, n.nodeClass);
    decode(r, n.browseName);
    decode(r, n.displayName);
    decode(r, n.description);
    decode(r, n.writeMask);
    decode(r, n.userWriteMask);
    decode(r, n.isAbstract);
    decode(r, n.symmetric);
    decode(r, n.inverseName);
    decode(r, n.containsNoLoops);
    decode(r, n.eventNotifier);
    decode(r, n.value);
    decode(r, n.dataType);
    decode(r, n.valueRank);
    decode(r, n.arrayDimensions);
    decode(r, n.accessLevel);
    decode(r, n.userAccessLevel);
    decode(r, n.minimumSamplingInterval);
    decode(r, n.historizing);
    decode(r, n.executable);
    decode(r, n.userExecutable);
    std::uint8_t role = 0;
    decode(r, role);
    n.requiredRole = static_cast<Role>(role);
    decodeDefinition(r, n.definition);
    // A reference takes at least 9 bytes (two 2-byte NodeIds, the direction, the line).
    const auto refs = r.readLength(r.remaining(), 9);
    pn.references.reserve(refs);
    for (std::uint32_t i = 0; i < refs && r.ok(); ++i) {
        auto& ref = pn.references.emplace_back();
        decode(r, ref.referenceTypeId);
        decode(r, ref.target);
        decode(r, ref.isForward);
        decodeLine(r, ref.line);
    }
    decodeLine(r, pn.line);
}

void encodeDataType(BinaryWriter& w, const DataTypeInfo& t) {
    encode(w, t.dataTypeId);
    encode(w, t.browseName);
    encode(w, t.superType);
    encode(w, t.binaryEncodingId);
    encode(w, t.xmlEncodingId);
    encodeDefinition(w, t.definition);
}
void decodeDataType(BinaryReader& r, DataTypeInfo& t) {
    decode(r, t.dataTypeId);
    decode(r, t.browseName);
    decode(r, t.superType);
    decode(r, t.binaryEncodingId);
    decode(r, t.xmlEncodingId);
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
    out.serverNamespaces = serverNamespaceTable(as, out.namespaceUris);

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
