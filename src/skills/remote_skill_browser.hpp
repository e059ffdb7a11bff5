#pragma once
// RemoteSkillBrowser: what skills a connected OPC UA server offers. It walks the server's
// object tree from the Objects folder, resolves the type of every object it meets through
// the server's own type hierarchy (inverse HasSubtype, never browse-name strings), keeps the
// objects whose type is SkillType or a subtype of it, and reports each with its browse
// path, its type chain up to SkillType and its declared parameters (the variables of its
// DI ParameterSet with their data type and value rank).
//
// Namespaces are named by URI: the Skills namespace is looked up in the server's
// NamespaceArray, and every type a result names is a GlobalNodeId (namespace URI +
// identifier), the same on every server whatever index the server gives the namespace.
//
// Requests are batched per tree level (Browse of a whole level at once, BrowseNext for
// continuation points, one Read for all parameters), so a browse costs a few round trips
// however many skills there are. Limits bound the work a large or hostile server can cause.
//
// Threading: a coroutine on the Client's executor, like the Client.
#include <asio/awaitable.hpp>
#include <compare>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ua/client/client.hpp"

namespace skillcell::skills {

/// A node named by namespace URI and identifier (the ExpandedNodeId form "nsu=...;i=..."):
/// the same type on every server, whatever namespace index each server gives it.
struct GlobalNodeId {
    GlobalNodeId() = default;
    GlobalNodeId(std::string uri, ua::NodeId::Identifier id)
        : namespaceUri(std::move(uri)), identifier(std::move(id)) {}
    GlobalNodeId(std::string_view uri, std::uint32_t numeric)
        : namespaceUri(uri), identifier(numeric) {}

    std::string namespaceUri;
    ua::NodeId::Identifier identifier{std::uint32_t{0}};

    /// "nsu=http://skillcell.dev/UA/Skills/;i=1002" (OPC 10000-6, 5.3.1.11).
    [[nodiscard]] std::string toString() const;
    /// The same node on a server with this NamespaceArray; nullopt if it lacks the namespace.
    [[nodiscard]] std::optional<ua::NodeId> toNodeId(
        const std::vector<std::string>& namespaceArray) const;
    /// `id` of a server with this NamespaceArray; nullopt for an index beyond the array.
    [[nodiscard]] static std::optional<GlobalNodeId> from(
        const std::vector<std::string>& namespaceArray, const ua::NodeId& id);

    friend bool operator==(const GlobalNodeId&, const GlobalNodeId&) = default;
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the literal 0 of the defaulted <=>
    friend auto operator<=>(const GlobalNodeId&, const GlobalNodeId&) = default;
};

/// SkillType (Skills namespace, i=1002): every skill type derives from it.
[[nodiscard]] GlobalNodeId skillTypeId();

/// A browse name with its namespace named by URI.
struct GlobalName {
    std::string namespaceUri;
    std::string name;
    friend bool operator==(const GlobalName&, const GlobalName&) = default;
};

/// One type of a skill's type chain.
struct SkillTypeRef {
    GlobalNodeId id;
    std::string browseName;  // without namespace, e.g. "CartesianLinearMoveSkillType"
    friend bool operator==(const SkillTypeRef&, const SkillTypeRef&) = default;
};

/// A parameter a skill declares (a variable of its ParameterSet).
struct SkillParameter {
    GlobalName browseName;
    ua::NodeId nodeId;      // on the component's server
    GlobalNodeId dataType;  // the DataType attribute
    ua::NodeId dataTypeId;  // the same, as the component's server names it
    std::int32_t valueRank = -1;
    friend bool operator==(const SkillParameter&, const SkillParameter&) = default;
};

/// A skill instance found on a server.
struct RemoteSkill {
    ua::NodeId nodeId;  // on the component's server (its namespace indices)
    /// Browse names from the Objects folder (exclusive) to the skill (inclusive).
    std::vector<GlobalName> browsePath;
    /// The skill's type first, then each supertype, SkillType last.
    std::vector<SkillTypeRef> types;
    std::vector<SkillParameter> parameters;
    friend bool operator==(const RemoteSkill&, const RemoteSkill&) = default;

    /// "DeviceSet/Robot/Move" (names only).
    [[nodiscard]] std::string browsePathString() const;
};

struct RemoteBrowseLimits {
    RemoteBrowseLimits() = default;  // not an aggregate: see ua::ClientConfig
    /// Objects visited at most; a server with more is refused (BadResourceUnavailable).
    std::size_t maxNodes = 100'000;
    /// Levels below the Objects folder that are walked.
    std::size_t maxDepth = 32;
    /// Nodes per Browse or Read request (servers limit operations per request).
    std::size_t nodesPerRequest = 500;
    /// Supertypes followed from a type before it counts as "not a skill".
    std::size_t maxTypeDepth = 64;
};

class RemoteSkillBrowser {
public:
    explicit RemoteSkillBrowser(RemoteBrowseLimits limits = {}) : limits_(limits) {}

    /// Every skill on the server `client` is connected to (with a session). The server's
    /// type hierarchy, as far as it was climbed, is cached for the next call: call
    /// forgetTypes() when the server restarted. `namespaceArray`: the server's, when the
    /// caller has read it already (with the StartTime, in one Read); else read here.
    asio::awaitable<ua::Result<std::vector<RemoteSkill>>> browse(
        ua::Client& client, std::optional<std::vector<std::string>> namespaceArray = std::nullopt);
    /// A NamespaceArray value as URIs (an element that is no String: an empty URI).
    [[nodiscard]] static std::vector<std::string> namespacesOf(const ua::Variant& value);

    void forgetTypes() { types_.clear(); }
    /// Types cached so far (for tests: a second browse climbs no further).
    [[nodiscard]] std::size_t cachedTypes() const { return types_.size(); }

private:
    struct TypeInfo {
        ua::QualifiedName browseName;
        std::optional<ua::NodeId> superType;  // none: a root, or not an ObjectType
        bool climbed = false;                 // superType was asked for
    };

    RemoteBrowseLimits limits_;
    std::map<ua::NodeId, TypeInfo> types_;  // the remote server's types, by its NodeIds
    std::vector<std::string> namespaces_;   // its NamespaceArray when the cache was filled
};

}  // namespace skillcell::skills
