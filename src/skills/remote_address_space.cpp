#include "skills/remote_address_space.hpp"

#include <algorithm>
#include <deque>
#include <set>

#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::skills {

namespace ns0 = ua::ns0;

RemoteAddressSpace::RemoteAddressSpace(ua::Client& client, RemoteLimits limits)
    : client_(client), limits_(limits) {}

asio::awaitable<ua::Result<std::vector<ua::ReferenceDescription>>> RemoteAddressSpace::browse(
    ua::NodeId node, ua::BrowseDirection direction, ua::NodeId referenceType,
    std::uint32_t nodeClassMask) {
    BrowseKey key{node, static_cast<int>(direction), referenceType, nodeClassMask};
    if (auto it = browseCache_.find(key); it != browseCache_.end()) co_return it->second;

    ++requests_;
    auto first = co_await client_.browse(node, direction, referenceType, true, nodeClassMask);
    if (!first) co_return first.status();
    std::vector<ua::ReferenceDescription> refs = std::move(first->references);
    ua::ByteString cp = std::move(first->continuationPoint);
    // A server may hand out continuation points forever; stop at the reference limit and
    // release the point so that it does not count against the session's few.
    while (!cp.empty()) {
        if (refs.size() >= limits_.maxReferencesPerNode) {
            ++requests_;
            (void)co_await client_.browseNext(std::move(cp), true);
            break;
        }
        ++requests_;
        auto next = co_await client_.browseNext(cp);
        if (!next) co_return next.status();
        if (next->references.empty() && next->continuationPoint == cp) break;  // no progress
        refs.insert(refs.end(), std::make_move_iterator(next->references.begin()),
                    std::make_move_iterator(next->references.end()));
        cp = std::move(next->continuationPoint);
    }
    if (refs.size() > limits_.maxReferencesPerNode) refs.resize(limits_.maxReferencesPerNode);
    browseCache_.emplace(std::move(key), refs);
    co_return refs;
}

asio::awaitable<ua::Result<std::vector<ua::ReferenceDescription>>> RemoteAddressSpace::children(
    ua::NodeId node) {
    co_return co_await browse(std::move(node), ua::BrowseDirection::Forward,
                              ua::NodeId(ns0::HierarchicalReferences));
}

asio::awaitable<ua::Result<std::optional<ua::ReferenceDescription>>> RemoteAddressSpace::child(
    ua::NodeId parent, ua::QualifiedName browseName) {
    auto refs = co_await children(std::move(parent));
    if (!refs) co_return refs.status();
    for (auto& ref : *refs) {
        if (ref.browseName == browseName && ref.nodeId.isLocal()) {
            co_return std::optional<ua::ReferenceDescription>(ref);
        }
    }
    co_return std::optional<ua::ReferenceDescription>();
}

asio::awaitable<ua::Result<ua::NodeId>> RemoteAddressSpace::superTypeOf(ua::NodeId type) {
    auto refs =
        co_await browse(std::move(type), ua::BrowseDirection::Inverse, ua::NodeId(ns0::HasSubtype));
    if (!refs) co_return refs.status();
    for (const auto& ref : *refs) {
        if (ref.nodeId.isLocal()) co_return ref.nodeId.nodeId;
    }
    co_return ua::NodeId();
}

asio::awaitable<ua::Result<std::vector<ua::NodeId>>> RemoteAddressSpace::typeChain(
    ua::NodeId type) {
    if (auto it = chainCache_.find(type); it != chainCache_.end()) co_return it->second;
    std::vector<ua::NodeId> chain{type};
    ua::NodeId current = type;
    for (;;) {
        auto super = co_await superTypeOf(current);
        if (!super) co_return super.status();
        if (super->isNull()) break;
        if (std::find(chain.begin(), chain.end(), *super) != chain.end() ||
            chain.size() >= limits_.maxTypeDepth) {
            co_return ua::status::BadInternalError;  // a cycle in the server's type tree
        }
        chain.push_back(*super);
        current = *super;
    }
    chainCache_.emplace(type, chain);
    co_return chain;
}

asio::awaitable<ua::Result<bool>> RemoteAddressSpace::isSubtypeOf(ua::NodeId type,
                                                                  ua::NodeId superType) {
    if (type == superType) co_return true;
    auto chain = co_await typeChain(std::move(type));
    if (!chain) co_return chain.status();
    co_return std::find(chain->begin(), chain->end(), superType) != chain->end();
}

asio::awaitable<ua::Result<std::vector<ua::NodeId>>> RemoteAddressSpace::subtypesOf(
    ua::NodeId type) {
    std::vector<ua::NodeId> out{type};
    std::set<ua::NodeId> seen{type};
    std::deque<ua::NodeId> queue{type};
    while (!queue.empty() && out.size() < limits_.maxSubtypes) {
        const ua::NodeId t = queue.front();
        queue.pop_front();
        auto refs = co_await browse(t, ua::BrowseDirection::Forward, ua::NodeId(ns0::HasSubtype));
        if (!refs) co_return refs.status();
        for (const auto& ref : *refs) {
            if (!ref.nodeId.isLocal() || !seen.insert(ref.nodeId.nodeId).second) continue;
            out.push_back(ref.nodeId.nodeId);
            queue.push_back(ref.nodeId.nodeId);
        }
    }
    co_return out;
}

asio::awaitable<ua::Result<std::vector<ua::DataValue>>> RemoteAddressSpace::read(
    std::vector<ua::ReadValueId> ids) {
    std::vector<ua::DataValue> out;
    out.reserve(ids.size());
    const std::size_t chunk = std::max<std::size_t>(limits_.maxReadsPerRequest, 1);
    for (std::size_t i = 0; i < ids.size(); i += chunk) {
        ua::ReadRequest req;
        req.timestampsToReturn = ua::TimestampsToReturn::Neither;
        const auto end = std::min(ids.size(), i + chunk);
        req.nodesToRead.assign(ids.begin() + static_cast<std::ptrdiff_t>(i),
                               ids.begin() + static_cast<std::ptrdiff_t>(end));
        ++requests_;
        auto resp = co_await client_.read(std::move(req));
        if (!resp) co_return resp.status();
        if (resp->results.size() != end - i) co_return ua::status::BadUnknownResponse;
        for (auto& dv : resp->results) out.push_back(std::move(dv));
    }
    co_return out;
}

asio::awaitable<ua::DataValue> RemoteAddressSpace::readAttribute(ua::NodeId node,
                                                                 ua::AttributeId attribute) {
    ua::ReadValueId id;
    id.nodeId = std::move(node);
    id.attributeId = static_cast<std::uint32_t>(attribute);
    std::vector<ua::ReadValueId> ids{std::move(id)};
    auto values = co_await read(std::move(ids));
    if (!values) co_return ua::DataValue::withStatus(values.status());
    co_return std::move((*values)[0]);
}

asio::awaitable<ua::Result<std::vector<std::string>>> RemoteAddressSpace::namespaceArray() {
    if (namespaces_) co_return *namespaces_;
    const ua::DataValue dv =
        co_await readAttribute(ua::NodeId(ns0::Server_NamespaceArray), ua::AttributeId::Value);
    if (dv.statusOrGood().isBad()) co_return dv.statusOrGood();
    if (!dv.value || !dv.value->isArray() || dv.value->type() != ua::BuiltinType::String) {
        co_return ua::status::BadTypeMismatch;
    }
    std::vector<std::string> uris;
    for (const auto& e : dv.value->elements()) {
        const auto* s = std::get_if<ua::String>(&e);
        uris.push_back(s != nullptr ? *s : std::string());
    }
    namespaces_ = uris;
    co_return uris;
}

asio::awaitable<ua::Result<std::optional<std::uint16_t>>> RemoteAddressSpace::namespaceIndex(
    std::string uri) {
    auto uris = co_await namespaceArray();
    if (!uris) co_return uris.status();
    for (std::size_t i = 0; i < uris->size() && i <= 0xFFFF; ++i) {
        if ((*uris)[i] == uri)
            co_return std::optional<std::uint16_t>(static_cast<std::uint16_t>(i));
    }
    co_return std::optional<std::uint16_t>();
}

asio::awaitable<std::string> RemoteAddressSpace::browseName(ua::NodeId node) {
    if (auto it = names_.find(node); it != names_.end()) co_return it->second;
    const ua::DataValue dv = co_await readAttribute(node, ua::AttributeId::BrowseName);
    std::string text = node.toString();
    if (dv.statusOrGood().isGood() && dv.value) {
        if (const auto* qn = dv.value->get<ua::QualifiedName>();
            qn != nullptr && !qn->name.empty()) {
            text = qn->name;
        }
    }
    names_.emplace(std::move(node), text);
    co_return text;
}

asio::awaitable<std::string> RemoteAddressSpace::describe(ua::NodeId node) {
    std::string text = co_await browseName(node);
    const std::string id = node.toString();
    if (text == id) co_return text;
    co_return text + " (" + id + ")";
}

}  // namespace skillcell::skills
