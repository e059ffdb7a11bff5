#pragma once
// A parsed NodeSet in binary form: what parseNodeSet makes of a file (nodes, references,
// decoded values, models, data types, the XML's line numbers for messages), written with
// the OPC UA binary encoding of each attribute. The build parses the embedded models once
// and compiles their snapshots in (tools/nodeset_snapshots.cpp); a server's start decodes
// a snapshot instead of parsing the XML again (a fifth of the time) and commits it as it
// would the parse, with every check of commitNodeSet.
//
// A snapshot holds the server namespace indices its NodeIds got when it was made, inside
// values too (an Argument's DataType). It is used only where the file's namespaces get the
// same indices in the address space it goes into; elsewhere the XML is parsed.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::ua {

/// The parse of a NodeSet file as bytes.
[[nodiscard]] std::vector<std::uint8_t> encodeSnapshot(const ParsedNodeSet& parsed);

enum class SnapshotDecode : std::uint8_t {
    Decoded,
    /// The file's namespaces would get other indices in this address space.
    OtherNamespaces,
    /// Not a snapshot of this format (or truncated).
    Malformed,
};

/// Decodes `snapshot` into `out` for loading into `as` (out.serverNamespaces is `as`'s
/// table with the file's new URIs, as parseNodeSet makes it).
[[nodiscard]] SnapshotDecode decodeSnapshot(const AddressSpace& as,
                                            std::span<const std::uint8_t> snapshot,
                                            ParsedNodeSet& out);

}  // namespace skillcell::ua
