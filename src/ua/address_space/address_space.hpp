#pragma once
// AddressSpace: the nodes a server exposes, their references, the type hierarchies and the
// namespace array (OPC 10000-3).
//
// Threading: single-threaded by design. The server runs one io_context thread and every
// service call runs on it; application code that changes nodes or values from another
// thread must post the change to that io_context (asio::post(io, [&]{ as.setValue(...); })).
// Value sources, sinks and method callbacks are called on that thread too.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "ua/address_space/node.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/messages/method.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

inline constexpr std::string_view kNs0Uri = "http://opcfoundation.org/UA/";

class AddressSpace {
public:
    /// Namespace 0 is the OPC UA namespace, namespace 1 the server's application URI.
    explicit AddressSpace(std::string applicationUri = "urn:skillcell:server");

    // --- Namespaces -----------------------------------------------------------------------
    [[nodiscard]] const std::vector<String>& namespaces() const { return namespaces_; }
    /// The index of `uri`, registering it at the end if it is new.
    std::uint16_t registerNamespace(std::string_view uri);
    [[nodiscard]] std::optional<std::uint16_t> namespaceIndex(std::string_view uri) const;
    /// Replaces namespace 1 (the application URI).
    void setApplicationUri(std::string uri) { namespaces_[1] = std::move(uri); }

    // --- Nodes and references -------------------------------------------------------------
    [[nodiscard]] Node* find(const NodeId& id);
    [[nodiscard]] const Node* find(const NodeId& id) const;
    [[nodiscard]] std::size_t size() const { return nodes_.size(); }
    /// Calls f(const Node&) for every node, in no particular order (exporters, checks).
    template <class F>
    void forEachNode(F&& f) const {
        for (const auto& [id, node] : nodes_) f(node);
    }

    /// Adds a node without references. BadNodeIdInvalid for the null NodeId,
    /// BadNodeIdExists when the id is taken. The returned pointer stays valid until the
    /// node is removed (nodes are held in a node-based map).
    Result<Node*> addNode(Node node);
    /// Adds a reference at both ends (the target's end only if the target is in this
    /// address space). A reference that is already there is not added twice.
    /// BadNodeIdUnknown for an unknown source, BadReferenceTypeIdInvalid when the type is
    /// not a ReferenceType node.
    StatusCode addReference(const NodeId& source, const NodeId& referenceTypeId,
                            const NodeId& target, bool isForward = true);
    /// Removes a node and every reference to it (not its children: the caller removes what
    /// it built). For nodes a server adds and drops at run time (an MES's orders); monitored
    /// items on it then report BadNodeIdUnknown. BadNodeIdUnknown when it is not there.
    StatusCode removeNode(const NodeId& id);

    // --- Type hierarchy -------------------------------------------------------------------
    /// True if `type` is `superType` or a (transitive) subtype of it. Works for every type
    /// node class (reference types, data types, object and variable types).
    [[nodiscard]] bool isSubtypeOf(const NodeId& type, const NodeId& superType) const;
    [[nodiscard]] bool isReferenceType(const NodeId& id) const;
    /// The HasTypeDefinition target of an Object or Variable; null if it has none.
    [[nodiscard]] NodeId typeDefinitionOf(const Node& node) const;
    /// The first forward hierarchical child of `parent` with `browseName`, or nullptr.
    [[nodiscard]] const Node* findChild(const NodeId& parent,
                                        const QualifiedName& browseName) const;

    /// True when `value` may be stored in a variable (or passed as an argument) of
    /// `dataType` and `valueRank`: the value's built-in type is the data type or one of its
    /// subtypes, or the data type is a subtype of the built-in type that encodes it
    /// (Duration takes a Double, an enumeration an Int32); and the value's dimensions fit.
    [[nodiscard]] bool valueMatches(const Variant& value, const NodeId& dataType,
                                    std::int32_t valueRank) const;
    /// True unless `value` holds a structure of another data type than `dataType`: every
    /// ExtensionObject in it (scalar or array element) must be encoded as `dataType` or one
    /// of its subtypes, as its type id (an encoding node, e.g. 3DFrame's Default Binary)
    /// tells through the data type registry or the address space's HasEncoding references.
    /// Structure and BaseDataType take any structure; so does an abstract data type, or one
    /// without known encodings, when the encoding is unknown. A null ExtensionObject passes
    /// (its value is the callee's business). Values of other built-in types pass (that is
    /// valueMatches' part). Lookups only, no allocation: for the Call service, beside
    /// valueMatches (OPC 10000-4, 5.11.2: a wrong structure is BadTypeMismatch).
    [[nodiscard]] bool structuresMatch(const Variant& value, const NodeId& dataType) const;
    /// The data type whose encoding node is `encodingId` (registry, else the encoding
    /// node's inverse HasEncoding reference); nullptr when unknown.
    [[nodiscard]] const NodeId* dataTypeOfEncoding(const NodeId& encodingId) const;

    // --- Values ---------------------------------------------------------------------------
    /// The current value of a Variable or VariableType: from its ValueSource if it has
    /// one, else the stored value. No access checks (that is the Read service's job).
    [[nodiscard]] DataValue readValue(const Node& node) const;
    /// Stores a value (source timestamp now). BadNodeIdUnknown, BadNodeClassInvalid for a
    /// node without a Value attribute, BadTypeMismatch for a value that does not fit.
    StatusCode setValue(const NodeId& id, Variant value);
    StatusCode setValueSource(const NodeId& id, ValueSource source);

    /// Told after a variable's value changed through setValue() or the Write service, so
    /// that subscriptions report the change at once instead of polling for it. One observer
    /// (the server's subscription engine); values from a ValueSource are not observed (the
    /// engine samples those). Runs on the address space's thread, inside the change.
    using ValueObserver = std::function<void(const Node&)>;
    void setValueObserver(ValueObserver observer) { valueObserver_ = std::move(observer); }
    void notifyValueChanged(const Node& node) const {
        if (valueObserver_) valueObserver_(node);
    }
    StatusCode setValueSink(const NodeId& id, ValueSink sink);
    StatusCode setMethodCallback(const NodeId& id, MethodCallback callback);

    // --- Building address spaces from C++ -------------------------------------------------
    // `parent` gets a forward reference to the new node: `referenceType` if not null, else
    // Organizes when the parent is a folder (FolderType or a subtype, or a type-less
    // node of the standard folder tree) and HasComponent otherwise. Properties always use
    // HasProperty. A browse name is given as text in the node's own namespace.
    Result<Node*> addObject(const NodeId& parent, const NodeId& id, std::string_view browseName,
                            const NodeId& typeDefinition = NodeId(ns0::BaseObjectType),
                            const NodeId& referenceType = {});
    Result<Node*> addFolder(const NodeId& parent, const NodeId& id, std::string_view browseName);
    Result<Node*> addVariable(const NodeId& parent, const NodeId& id, std::string_view browseName,
                              const NodeId& dataType, Variant value,
                              std::uint8_t accessLevel = access_level::kCurrentRead,
                              std::int32_t valueRank = value_rank::kScalar,
                              const NodeId& typeDefinition = NodeId(ns0::BaseDataVariableType),
                              const NodeId& referenceType = {});
    Result<Node*> addProperty(const NodeId& parent, const NodeId& id, std::string_view browseName,
                              const NodeId& dataType, Variant value,
                              std::int32_t valueRank = value_rank::kScalar);
    /// Adds a method with its InputArguments / OutputArguments properties (omitted when
    /// empty); their NodeIds are derived from the method's (see childNodeId).
    Result<Node*> addMethod(const NodeId& parent, const NodeId& id, std::string_view browseName,
                            std::vector<Argument> inputs, std::vector<Argument> outputs,
                            MethodCallback callback);

    /// A deterministic NodeId for a child that C++ creates on the caller's behalf:
    /// ns=<parent's>;s=<parent id text>/<name>, e.g. "ns=1;s=Demo.Add/InputArguments".
    [[nodiscard]] static NodeId childNodeId(const NodeId& parent, std::string_view name);

    // --- Data types and models -----------------------------------------------------------
    /// The structured and enumerated data types known to this address space (filled by the
    /// NodeSet2 loader from DataType nodes and their <Definition>), for DynamicStructure.
    [[nodiscard]] const DataTypeRegistry& dataTypes() const { return dataTypes_; }
    [[nodiscard]] DataTypeRegistry& dataTypes() { return dataTypes_; }

    /// A loaded information model (a NodeSet2 <Model>), for RequiredModel checks.
    struct Model {
        String uri;
        String version;
        std::optional<DateTime> publicationDate;
    };
    void registerModel(Model model);
    [[nodiscard]] const Model* findModel(std::string_view uri) const;

    /// The Argument list stored in a method's InputArguments or OutputArguments property;
    /// empty if it has none. BadDecodingError for a property that holds something else.
    [[nodiscard]] Result<std::vector<Argument>> methodArguments(
        const NodeId& methodId, std::string_view propertyName) const;

private:
    Result<Node*> addInstance(Node node, const NodeId& parent, const NodeId& referenceType,
                              const NodeId& typeDefinition);
    [[nodiscard]] bool isFolder(const NodeId& id) const;

    std::vector<String> namespaces_;
    std::unordered_map<NodeId, Node> nodes_;
    DataTypeRegistry dataTypes_;
    std::vector<Model> models_;
    ValueObserver valueObserver_;
};

/// An ExtensionObject array value holding `arguments` (for InputArguments properties).
[[nodiscard]] Variant argumentsValue(const std::vector<Argument>& arguments);

}  // namespace skillcell::ua
