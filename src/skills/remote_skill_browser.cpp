#include "skills/remote_skill_browser.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <set>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::skills {

namespace {

namespace ns0 = ua::ns0;
using ua::NodeId;
using ua::Result;
using ua::StatusCode;

constexpr std::uint32_t kObjectMask = static_cast<std::uint32_t>(ua::NodeClass::Object);
constexpr std::uint32_t kVariableMask = static_cast<std::uint32_t>(ua::NodeClass::Variable);
constexpr std::uint32_t kObjectTypeMask = static_cast<std::uint32_t>(ua::NodeClass::ObjectType);
constexpr std::string_view kParameterSet = "ParameterSet";

std::optional<std::uint16_t> indexOf(const std::vector<std::string>& namespaces,
                                     std::string_view uri) {
    for (std::size_t i = 0; i < namespaces.size(); ++i) {
        if (namespaces[i] == uri) return static_cast<std::uint16_t>(i);
    }
    return std::nullopt;
}

/// A reference's target as a NodeId of this server; nullopt for another server's node or a
/// namespace URI the server does not list.
std::optional<NodeId> localTarget(const ua::ExpandedNodeId& id,
                                  const std::vector<std::string>& namespaces) {
    if (id.serverIndex != 0) return std::nullopt;
    if (id.namespaceUri.empty()) return id.nodeId;
    const auto ns = indexOf(namespaces, id.namespaceUri);
    if (!ns) return std::nullopt;
    return std::visit([&](const auto& v) { return NodeId(*ns, v); }, id.nodeId.identifier());
}

/// Browses every description, following continuation points, `perRequest` nodes at a time.
/// One vector of references per description (empty when the server refused that node).
asio::awaitable<Result<std::vector<std::vector<ua::ReferenceDescription>>>> browseAll(
    ua::Client& client, const std::vector<ua::BrowseDescription>& descriptions,
    std::size_t perRequest) {
    std::vector<std::vector<ua::ReferenceDescription>> out(descriptions.size());
    std::deque<std::size_t> queue;
    for (std::size_t i = 0; i < descriptions.size(); ++i) queue.push_back(i);
    const auto append = [&out](std::size_t index, ua::BrowseResult& result) {
        auto& refs = out[index];
        refs.insert(refs.end(), std::make_move_iterator(result.references.begin()),
                    std::make_move_iterator(result.references.end()));
    };
    while (!queue.empty()) {
        std::vector<std::size_t> batch;
        ua::BrowseRequest req;
        while (!queue.empty() && batch.size() < perRequest) {
            batch.push_back(queue.front());
            req.nodesToBrowse.push_back(descriptions[queue.front()]);
            queue.pop_front();
        }
        auto resp = co_await client.browse(std::move(req));
        if (!resp) co_return resp.status();
        if (resp->results.size() != batch.size()) co_return ua::status::BadUnknownResponse;
        // A server keeps a few continuation points per session: the nodes it had none left
        // for are browsed again once the others have been drained.
        std::size_t retried = 0;
        std::vector<std::pair<std::size_t, ua::ByteString>> points;
        for (std::size_t k = 0; k < batch.size(); ++k) {
            auto& result = resp->results[k];
            if (result.statusCode == ua::status::BadNoContinuationPoints) {
                queue.push_back(batch[k]);
                ++retried;
                continue;
            }
            if (result.statusCode.isBad()) continue;  // e.g. a node deleted meanwhile
            append(batch[k], result);
            if (!result.continuationPoint.empty())
                points.emplace_back(batch[k], std::move(result.continuationPoint));
        }
        if (retried == batch.size()) co_return ua::status::BadNoContinuationPoints;
        while (!points.empty()) {
            ua::BrowseNextRequest more;
            for (const auto& point : points) more.continuationPoints.push_back(point.second);
            auto nextResp = co_await client.browseNext(std::move(more));
            if (!nextResp) co_return nextResp.status();
            if (nextResp->results.size() != points.size()) co_return ua::status::BadUnknownResponse;
            std::vector<std::pair<std::size_t, ua::ByteString>> still;
            for (std::size_t k = 0; k < points.size(); ++k) {
                auto& result = nextResp->results[k];
                if (result.statusCode.isBad()) continue;
                append(points[k].first, result);
                if (!result.continuationPoint.empty())
                    still.emplace_back(points[k].first, std::move(result.continuationPoint));
            }
            points = std::move(still);
        }
    }
    co_return out;
}

/// Reads every item, `perRequest` at a time; one DataValue per item.
asio::awaitable<Result<std::vector<ua::DataValue>>> readAll(ua::Client& client,
                                                            const std::vector<ua::ReadValueId>& ids,
                                                            std::size_t perRequest) {
    std::vector<ua::DataValue> out;
    out.reserve(ids.size());
    for (std::size_t next = 0; next < ids.size(); next += perRequest) {
        const std::size_t end = std::min(ids.size(), next + perRequest);
        ua::ReadRequest req;
        req.timestampsToReturn = ua::TimestampsToReturn::Neither;
        req.nodesToRead.assign(ids.begin() + static_cast<std::ptrdiff_t>(next),
                               ids.begin() + static_cast<std::ptrdiff_t>(end));
        auto resp = co_await client.read(std::move(req));
        if (!resp) co_return resp.status();
        if (resp->results.size() != end - next) co_return ua::status::BadUnknownResponse;
        for (auto& dv : resp->results) out.push_back(std::move(dv));
    }
    co_return out;
}

ua::ReadValueId readOf(const NodeId& id, ua::AttributeId attribute) {
    ua::ReadValueId r;
    r.nodeId = id;
    r.attributeId = static_cast<std::uint32_t>(attribute);
    return r;
}

template <class T>
const T* valueOf(const ua::DataValue& dv) {
    if (dv.statusOrGood().isBad() || !dv.value) return nullptr;
    return dv.value->get<T>();
}

/// One object met while walking the tree.
struct FoundObject {
    NodeId id;
    NodeId typeDefinition;  // null when the server gave none
    ua::QualifiedName browseName;
    std::size_t parent = 0;  // index into the walk; the Objects folder is its own parent
    bool isParameterSet = false;
    std::vector<std::pair<NodeId, ua::QualifiedName>> variables;  // ParameterSets only
};

}  // namespace

std::string GlobalNodeId::toString() const {
    const NodeId local = std::visit([](const auto& v) { return NodeId(0, v); }, identifier);
    return "nsu=" + namespaceUri + ";" + local.toString();
}

std::optional<NodeId> GlobalNodeId::toNodeId(const std::vector<std::string>& namespaceArray) const {
    const auto ns = indexOf(namespaceArray, namespaceUri);
    if (!ns) return std::nullopt;
    return std::visit([&](const auto& v) { return NodeId(*ns, v); }, identifier);
}

std::optional<GlobalNodeId> GlobalNodeId::from(const std::vector<std::string>& namespaceArray,
                                               const NodeId& id) {
    if (id.namespaceIndex() >= namespaceArray.size()) return std::nullopt;
    return GlobalNodeId(namespaceArray[id.namespaceIndex()], id.identifier());
}

GlobalNodeId skillTypeId() {
    return {ua::companion::kSkillsUri, ua::companion::kSkillType};
}

std::string RemoteSkill::browsePathString() const {
    std::string out;
    for (const auto& element : browsePath) {
        if (!out.empty()) out += '/';
        out += element.name;
    }
    return out;
}

std::vector<std::string> RemoteSkillBrowser::namespacesOf(const ua::Variant& value) {
    std::vector<std::string> namespaces;
    for (const auto& element : value.elements()) {
        const auto* uri = std::get_if<ua::String>(&element);
        namespaces.push_back(uri != nullptr ? *uri : std::string());
    }
    return namespaces;
}

asio::awaitable<Result<std::vector<RemoteSkill>>> RemoteSkillBrowser::browse(
    ua::Client& client, std::optional<std::vector<std::string>> namespaceArray) {
    // 1. The namespaces: where SkillType and the DI ParameterSet live on this server.
    if (!namespaceArray) {
        auto nsValue = co_await client.readValue(NodeId(ns0::Server_NamespaceArray));
        if (!nsValue) co_return nsValue.status();
        namespaceArray = namespacesOf(*nsValue);
    }
    const std::vector<std::string> namespaces = std::move(*namespaceArray);
    if (namespaces != namespaces_) {
        types_.clear();  // another server, or the same one restarted with other models
        namespaces_ = namespaces;
    }
    const auto skillsNs = indexOf(namespaces, ua::companion::kSkillsUri);
    if (!skillsNs) co_return std::vector<RemoteSkill>{};  // no Skills model: no skills
    const NodeId skillType(*skillsNs, ua::companion::kSkillType);
    const auto diNs = indexOf(namespaces, ua::companion::kDiUri);
    const auto globalName = [&](const ua::QualifiedName& q) {
        return GlobalName{q.namespaceIndex < namespaces.size() ? namespaces[q.namespaceIndex] : "",
                          q.name};
    };

    // 2. Walk the objects below the Objects folder, a level per round trip, and climb the
    //    server's type hierarchy from every type met there of another namespace than 0 (a
    //    namespace-0 type is never below SkillType), a supertype per round trip: both in
    //    the same Browse, so that the climb costs no round trips of its own beyond the
    //    walk's. ParameterSets are browsed for their variables too (the declared
    //    parameters). Types already climbed (the cache) cost nothing.
    std::vector<FoundObject> found;
    found.push_back({NodeId(ns0::ObjectsFolder), NodeId(), {0, "Objects"}, 0, false, {}});
    std::set<NodeId> visited{NodeId(ns0::ObjectsFolder)};
    std::vector<std::size_t> level{0};
    std::size_t depth = 0;
    // Types to climb this round, each with how many supertypes above the one met it is.
    std::vector<std::pair<NodeId, std::size_t>> climb;
    const auto meetType = [&](const NodeId& t, std::size_t height) {
        if (t.isNull() || t.namespaceIndex() == 0 || t == skillType) return;
        const auto it = types_.try_emplace(t).first;
        if (it->second.climbed || height >= limits_.maxTypeDepth) return;
        const bool queued =
            std::any_of(climb.begin(), climb.end(), [&t](const auto& c) { return c.first == t; });
        if (!queued) climb.emplace_back(t, height);
    };
    while ((!level.empty() && depth < limits_.maxDepth) || !climb.empty()) {
        const std::size_t walked = depth < limits_.maxDepth ? level.size() : 0;
        std::vector<ua::BrowseDescription> descriptions;
        descriptions.reserve(walked + climb.size());
        for (std::size_t k = 0; k < walked; ++k) {
            const FoundObject& o = found[level[k]];
            ua::BrowseDescription d;
            d.nodeId = o.id;
            d.referenceTypeId = NodeId(ns0::HierarchicalReferences);
            d.nodeClassMask = o.isParameterSet ? (kObjectMask | kVariableMask) : kObjectMask;
            d.resultMask = ua::browse_result::kIsForward | ua::browse_result::kNodeClass |
                           ua::browse_result::kBrowseName | ua::browse_result::kTypeDefinition;
            descriptions.push_back(std::move(d));
        }
        for (const auto& [t, height] : climb) {
            ua::BrowseDescription d;
            d.nodeId = t;
            d.browseDirection = ua::BrowseDirection::Inverse;
            d.referenceTypeId = NodeId(ns0::HasSubtype);
            d.includeSubtypes = false;
            d.nodeClassMask = kObjectTypeMask;
            d.resultMask = ua::browse_result::kIsForward | ua::browse_result::kBrowseName;
            descriptions.push_back(std::move(d));
        }
        auto refs = co_await browseAll(client, descriptions, limits_.nodesPerRequest);
        if (!refs) co_return refs.status();

        // The supertypes found, queued for the next round.
        const auto climbed = std::exchange(climb, {});
        for (std::size_t k = 0; k < climbed.size(); ++k) {
            const auto& [t, height] = climbed[k];
            TypeInfo& info = types_[t];
            info.climbed = true;
            for (auto& ref : (*refs)[walked + k]) {
                if (ref.isForward) continue;
                auto super = localTarget(ref.nodeId, namespaces);
                if (!super) continue;
                info.superType = *super;
                auto [it, added] = types_.try_emplace(*super);
                if (added || it->second.browseName.name.empty())
                    it->second.browseName = std::move(ref.browseName);
                meetType(*super, height + 1);
                break;  // a type has one supertype (OPC 10000-3, 6.3)
            }
        }

        std::vector<std::size_t> nextLevel;
        for (std::size_t k = 0; k < walked; ++k) {
            const std::size_t parent = level[k];
            for (auto& ref : (*refs)[k]) {
                if (!ref.isForward) continue;
                auto target = localTarget(ref.nodeId, namespaces);
                if (!target) continue;
                if (ref.nodeClass == ua::NodeClass::Variable) {
                    if (found[parent].isParameterSet)
                        found[parent].variables.emplace_back(*target, ref.browseName);
                    continue;
                }
                if (ref.nodeClass != ua::NodeClass::Object || !visited.insert(*target).second)
                    continue;
                if (found.size() >= limits_.maxNodes) {
                    spdlog::warn("skill browse of {}: more than {} objects, giving up",
                                 client.endpointUrl(), limits_.maxNodes);
                    co_return ua::status::BadResourceUnavailable;
                }
                FoundObject o;
                o.id = *target;
                o.typeDefinition = localTarget(ref.typeDefinition, namespaces).value_or(NodeId());
                o.isParameterSet = diNs && ref.browseName.namespaceIndex == *diNs &&
                                   ref.browseName.name == kParameterSet;
                o.browseName = std::move(ref.browseName);
                o.parent = parent;
                meetType(o.typeDefinition, 0);
                nextLevel.push_back(found.size());
                found.push_back(std::move(o));
            }
        }
        if (walked > 0) {
            level = std::move(nextLevel);
            ++depth;
        }
    }

    // The chain from `type` up to SkillType; empty if SkillType is not among its supertypes.
    const auto skillChain = [&](const NodeId& type) {
        std::vector<NodeId> chain;
        std::optional<NodeId> cur = type;
        for (std::size_t n = 0; cur && n <= limits_.maxTypeDepth + 1; ++n) {
            chain.push_back(*cur);
            if (*cur == skillType) return chain;
            if (cur->namespaceIndex() == 0) break;
            auto it = types_.find(*cur);
            if (it == types_.end() || !it->second.climbed) break;
            cur = it->second.superType;
        }
        return std::vector<NodeId>{};
    };

    // 3. The skills, their paths, types and ParameterSets.
    std::map<std::size_t, std::size_t> parameterSetOf;  // skill index -> ParameterSet index
    for (std::size_t i = 1; i < found.size(); ++i) {
        if (found[i].isParameterSet) parameterSetOf.try_emplace(found[i].parent, i);
    }
    std::vector<RemoteSkill> skills;
    std::vector<NodeId> unnamed;
    for (std::size_t i = 1; i < found.size(); ++i) {
        const auto chain = skillChain(found[i].typeDefinition);
        if (chain.empty()) continue;
        RemoteSkill s;
        s.nodeId = found[i].id;
        for (std::size_t at = i; at != 0; at = found[at].parent)
            s.browsePath.push_back(globalName(found[at].browseName));
        std::reverse(s.browsePath.begin(), s.browsePath.end());
        for (const auto& t : chain) {
            SkillTypeRef ref;
            ref.id = GlobalNodeId::from(namespaces, t).value_or(GlobalNodeId());
            auto it = types_.find(t);
            ref.browseName = it != types_.end() ? it->second.browseName.name : std::string();
            // A skill's own type: the walk gave its NodeId, not its name (step 4 reads it).
            if (ref.browseName.empty() && it != types_.end() && t != skillType &&
                std::find(unnamed.begin(), unnamed.end(), t) == unnamed.end()) {
                unnamed.push_back(t);
            }
            s.types.push_back(std::move(ref));
        }
        if (auto ps = parameterSetOf.find(i); ps != parameterSetOf.end()) {
            for (const auto& [id, name] : found[ps->second].variables) {
                SkillParameter p;
                p.browseName = globalName(name);
                p.nodeId = id;
                s.parameters.push_back(std::move(p));
            }
        }
        skills.push_back(std::move(s));
    }

    // 4. In one Read: the parameters' data types and value ranks, and the names of the
    //    skills' own types (a supertype's name came with the climb).
    std::vector<ua::ReadValueId> ids;
    for (const auto& s : skills) {
        for (const auto& p : s.parameters) {
            ids.push_back(readOf(p.nodeId, ua::AttributeId::DataType));
            ids.push_back(readOf(p.nodeId, ua::AttributeId::ValueRank));
        }
    }
    const std::size_t parameterReads = ids.size();
    for (const auto& t : unnamed) ids.push_back(readOf(t, ua::AttributeId::BrowseName));
    if (!ids.empty()) {
        auto values = co_await readAll(client, ids, limits_.nodesPerRequest);
        if (!values) co_return values.status();
        std::size_t k = 0;
        for (auto& s : skills) {
            for (auto& p : s.parameters) {
                if (const auto* dt = valueOf<NodeId>((*values)[k])) {
                    p.dataTypeId = *dt;
                    p.dataType = GlobalNodeId::from(namespaces, *dt).value_or(GlobalNodeId());
                }
                if (const auto* rank = valueOf<std::int32_t>((*values)[k + 1])) p.valueRank = *rank;
                k += 2;
            }
        }
        for (std::size_t n = 0; n < unnamed.size(); ++n) {
            const auto* q = valueOf<ua::QualifiedName>((*values)[parameterReads + n]);
            if (q == nullptr) continue;
            types_[unnamed[n]].browseName = *q;
            const auto id = GlobalNodeId::from(namespaces, unnamed[n]);
            for (auto& s : skills) {
                for (auto& ref : s.types) {
                    if (id && ref.id == *id) ref.browseName = q->name;
                }
            }
        }
    }
    co_return skills;
}

}  // namespace skillcell::skills
