#pragma once
// RemoteAddressSpace: what a client learns of another server's address space, asked over
// the wire once and remembered: references (every continuation point followed), the type
// hierarchy (inverse HasSubtype), attributes, the NamespaceArray.
//
// The skill model says that a skill's type is recognised through the *remote* type
// hierarchy, never by browse-name strings or by the client's own copy of the models (a
// device may ship a newer model, or a subtype of its own). Everything here asks the server.
//
// Bounded by design: a server that answers strangely (endless continuation points, a
// supertype cycle, huge reference lists) gives an error or a truncated answer, never a hang.
//
// Threading: like the Client it wraps, used from the client's executor only.
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include <asio/awaitable.hpp>

#include "ua/client/client.hpp"

namespace skillcell::skills {

struct RemoteLimits {
    // Not an aggregate on purpose (GCC 12, see ua::ClientConfig).
    RemoteLimits() = default;

    /// References kept per browsed node; the rest are dropped (continuation point released).
    std::size_t maxReferencesPerNode = 10'000;
    /// Length of a supertype chain; a longer one is taken for a cycle (BadInternalError).
    std::size_t maxTypeDepth = 32;
    /// Subtypes collected below one type (subtypesOf).
    std::size_t maxSubtypes = 10'000;
    /// ReadValueIds per Read request (servers limit operations per request).
    std::size_t maxReadsPerRequest = 100;
};

class RemoteAddressSpace {
public:
    explicit RemoteAddressSpace(ua::Client& client, RemoteLimits limits = {});

    [[nodiscard]] ua::Client& client() { return client_; }

    /// The references of `node` of `referenceType` and its subtypes in `direction`, all
    /// continuation points followed. `nodeClassMask` 0: every node class. Cached.
    asio::awaitable<ua::Result<std::vector<ua::ReferenceDescription>>> browse(
        ua::NodeId node, ua::BrowseDirection direction, ua::NodeId referenceType,
        std::uint32_t nodeClassMask = 0);
    /// Forward hierarchical children of `node` (Objects, Variables, Methods).
    asio::awaitable<ua::Result<std::vector<ua::ReferenceDescription>>> children(ua::NodeId node);
    /// The child of `parent` with `browseName` (forward hierarchical), if there is one.
    asio::awaitable<ua::Result<std::optional<ua::ReferenceDescription>>> child(
        ua::NodeId parent, ua::QualifiedName browseName);

    /// The supertype of a type (its inverse HasSubtype target); null for a root type.
    asio::awaitable<ua::Result<ua::NodeId>> superTypeOf(ua::NodeId type);
    /// `type`, then its supertype, and so on up to a root. Cached.
    asio::awaitable<ua::Result<std::vector<ua::NodeId>>> typeChain(ua::NodeId type);
    /// True if `type` is `superType` or a transitive subtype of it.
    asio::awaitable<ua::Result<bool>> isSubtypeOf(ua::NodeId type, ua::NodeId superType);
    /// `type` and all its transitive subtypes (forward HasSubtype), breadth first.
    asio::awaitable<ua::Result<std::vector<ua::NodeId>>> subtypesOf(ua::NodeId type);

    /// One Read per maxReadsPerRequest ids; one DataValue per id, in order. A failed service
    /// fails the whole call.
    asio::awaitable<ua::Result<std::vector<ua::DataValue>>> read(std::vector<ua::ReadValueId> ids);
    /// One attribute; a failed service comes back as the DataValue's status.
    asio::awaitable<ua::DataValue> readAttribute(ua::NodeId node, ua::AttributeId attribute);

    /// The server's NamespaceArray (i=2255), read once.
    asio::awaitable<ua::Result<std::vector<std::string>>> namespaceArray();
    /// The index of `uri` in the NamespaceArray; nullopt if the server does not have it.
    asio::awaitable<ua::Result<std::optional<std::uint16_t>>> namespaceIndex(std::string uri);

    /// A node's browse name (without namespace index) for messages; its NodeId when the
    /// browse name cannot be read. Cached.
    asio::awaitable<std::string> browseName(ua::NodeId node);
    /// "BrowseName (NodeId)", e.g. "SkillType (ns=3;i=1002)".
    asio::awaitable<std::string> describe(ua::NodeId node);

    /// Requests sent so far (tests and the CLI's --verbose output).
    [[nodiscard]] std::size_t requestCount() const { return requests_; }

private:
    using BrowseKey = std::tuple<ua::NodeId, int, ua::NodeId, std::uint32_t>;

    ua::Client& client_;
    RemoteLimits limits_;
    std::map<BrowseKey, std::vector<ua::ReferenceDescription>> browseCache_;
    std::map<ua::NodeId, std::vector<ua::NodeId>> chainCache_;
    std::map<ua::NodeId, std::string> names_;
    std::optional<std::vector<std::string>> namespaces_;
    std::size_t requests_ = 0;
};

}  // namespace skillcell::skills
