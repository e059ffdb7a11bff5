#pragma once
// NodeSet2 loader (OPC 10000-6, Annex F): reads UANodeSet XML into an AddressSpace.
//
// Loading is two-phase, so that a bad file changes nothing:
//   1. parseNodeSet: XML -> ParsedNodeSet (nodes with attributes, values and references,
//      NodeIds already mapped from the file's namespace indices to the server's).
//   2. commitNodeSet: checks every reference type and target against the parsed nodes and
//      the address space, then registers the namespaces and adds nodes and references
//      (both directions).
// The parse also reads <Models> (checked against the loaded models at commit: a missing or
// too old RequiredModel is an error naming it) and the <Definition> of data types, which
// become DataTypeDefinition attributes and DataTypeRegistry entries. Values are read after
// all nodes, so ExtensionObjects of structures defined in the same file (or in a model
// loaded before) decode through DynamicStructure without hand-written code.
//
// Errors are values: "<source>:<line>: <what>", never exceptions.
#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ua/address_space/address_space.hpp"

namespace skillcell::ua {

struct ParsedReference {
    NodeId referenceTypeId;
    NodeId target;
    bool isForward = true;
    std::size_t line = 0;
};

struct ParsedNode {
    Node node;  // attributes and value; references are kept apart until commit
    std::vector<ParsedReference> references;
    std::size_t line = 0;
};

/// A <Model> of the file and the models it requires (<RequiredModel>).
struct ParsedModel {
    struct Requirement {
        std::string uri;
        std::string version;  // empty: any version
        std::optional<DateTime> publicationDate;
    };
    std::string uri;
    std::string version;
    std::optional<DateTime> publicationDate;
    std::vector<Requirement> required;
    std::size_t line = 0;
};

struct ParsedNodeSet {
    std::string source;                      // file name for messages
    std::vector<std::string> namespaceUris;  // the file's NamespaceUris, file index 1..n
    /// The namespace table the parsed NodeIds refer to (the address space's, then the
    /// file's new URIs): index -> URI.
    std::vector<std::string> serverNamespaces;
    std::vector<ParsedModel> models;
    std::vector<ParsedNode> nodes;
    /// Every DataType of the file, for the address space's DataTypeRegistry.
    std::vector<DataTypeInfo> dataTypes;
};

/// The outcome of a parse or load: empty `error` on success.
struct NodeSetStatus {
    std::string error;
    std::size_t nodes = 0;
    std::size_t references = 0;
    [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Where a file's NamespaceUris go in `as`, one index each: a URI `as` knows keeps its index,
/// new ones get the next free indices in file order (a URI listed twice, one). The parse and
/// the snapshots (nodeset_snapshot.hpp) share it.
[[nodiscard]] std::vector<std::uint16_t> namespaceMap(const AddressSpace& as,
                                                      std::span<const std::string> fileUris);
/// `as`'s namespace table with the file's URIs at the indices `map` (namespaceMap's) gives
/// them: the table a parsed set's NodeIds refer to (ParsedNodeSet::serverNamespaces).
[[nodiscard]] std::vector<std::string> serverNamespaceTable(const AddressSpace& as,
                                                            std::span<const std::string> fileUris,
                                                            std::span<const std::uint16_t> map);

/// Parses `xml`. The server's namespace indices are computed against `as` (without
/// registering anything yet): a URI already known keeps its index, new URIs get the next
/// free ones in file order.
[[nodiscard]] NodeSetStatus parseNodeSet(const AddressSpace& as, std::string_view xml,
                                         std::string_view sourceName, ParsedNodeSet& out);
/// Adds a parsed node set to `as`. On error nothing has been added.
[[nodiscard]] NodeSetStatus commitNodeSet(AddressSpace& as, const ParsedNodeSet& parsed);
/// The same, moving the nodes' attributes and values out of `parsed`.
[[nodiscard]] NodeSetStatus commitNodeSet(AddressSpace& as, ParsedNodeSet&& parsed);

/// parseNodeSet + commitNodeSet.
[[nodiscard]] NodeSetStatus loadNodeSet(AddressSpace& as, std::string_view xml,
                                        std::string_view sourceName);
/// Reads and loads a file; messages name the file as given.
[[nodiscard]] NodeSetStatus loadNodeSetFile(AddressSpace& as, const std::filesystem::path& path);

/// An embedded NodeSet2 file: its name, and the path its messages name it by.
struct EmbeddedNodeSet {
    std::string_view fileName;
    std::string_view sourceName;
};
/// Namespace 0, in load order: our subset (models/Opc.Ua.NodeSet2.Base.xml), then the nodes
/// the OPC Foundation's companion models use beyond it.
inline constexpr std::array<EmbeddedNodeSet, 2> kNamespaceZeroFiles{{
    {"Opc.Ua.NodeSet2.Base.xml", "models/Opc.Ua.NodeSet2.Base.xml"},
    {"Opc.Ua.NodeSet2.Closure.xml", "models/opcfoundation/Opc.Ua.NodeSet2.Closure.xml"},
}};

/// A NodeSet2 file from models/ compiled into the library ("Opc.Ua.NodeSet2.Base.xml");
/// empty if there is no such file.
[[nodiscard]] std::string_view embeddedModel(std::string_view fileName);
/// Names of all embedded model files.
[[nodiscard]] std::vector<std::string_view> embeddedModelNames();

}  // namespace skillcell::ua
