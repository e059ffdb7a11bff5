#include "skills/instance_declarations.hpp"

#include <algorithm>
#include <utility>

#include "ua/address_space/node.hpp"
#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::skills {

namespace ns0 = ua::ns0;

std::string pathText(const std::vector<ua::QualifiedName>& path) {
    std::string s;
    for (const auto& name : path) {
        if (!s.empty()) s += '/';
        s += name.name;
    }
    return s;
}

std::string InstanceDeclaration::pathText() const {
    return skills::pathText(path);
}

std::string modellingRuleName(const ua::NodeId& rule) {
    if (rule == ua::NodeId(modelling_rule::Mandatory)) return "Mandatory";
    if (rule == ua::NodeId(modelling_rule::Optional)) return "Optional";
    if (rule == ua::NodeId(modelling_rule::ExposesItsArray)) return "ExposesItsArray";
    if (rule == ua::NodeId(modelling_rule::OptionalPlaceholder)) return "OptionalPlaceholder";
    if (rule == ua::NodeId(modelling_rule::MandatoryPlaceholder)) return "MandatoryPlaceholder";
    if (rule.isNull()) return "none";
    return rule.toString();
}

namespace {

class Collector {
public:
    Collector(RemoteAddressSpace& remote, std::size_t maxDepth)
        : remote_(remote), maxDepth_(maxDepth) {}

    /// The declarations owned by `owners` (each overriding the earlier ones by browse name),
    /// appended under `prefix`, each followed by its own children.
    asio::awaitable<ua::StatusCode> level(std::vector<ua::NodeId> owners,
                                          std::vector<ua::QualifiedName> prefix) {
        std::vector<InstanceDeclaration> found;
        for (const auto& owner : owners) {
            auto refs = co_await remote_.browse(owner, ua::BrowseDirection::Forward,
                                                ua::NodeId(ns0::Aggregates));
            if (!refs) co_return refs.status();
            for (const auto& ref : *refs) {
                if (!ref.nodeId.isLocal()) continue;
                auto rule = co_await remote_.browse(ref.nodeId.nodeId, ua::BrowseDirection::Forward,
                                                    ua::NodeId(ns0::HasModellingRule));
                if (!rule) co_return rule.status();
                if (rule->empty()) continue;  // belongs to the type, not to its instances
                InstanceDeclaration d;
                d.path = prefix;
                d.path.push_back(ref.browseName);
                d.nodeId = ref.nodeId.nodeId;
                d.nodeClass = ref.nodeClass;
                d.referenceType = ref.referenceTypeId;
                if (ref.typeDefinition.isLocal()) d.typeDefinition = ref.typeDefinition.nodeId;
                d.modellingRule = rule->front().nodeId.nodeId;
                auto same = std::find_if(found.begin(), found.end(), [&](const auto& other) {
                    return other.path.back() == d.path.back();
                });
                if (same != found.end()) {
                    *same = std::move(d);  // the subtype's (or the declaration's own) wins
                } else {
                    found.push_back(std::move(d));
                }
            }
        }
        if (auto s = co_await readVariableAttributes(found); s.isBad()) co_return s;

        for (auto& d : found) {
            const bool descend = !d.isPlaceholder() && d.path.size() < maxDepth_;
            std::vector<ua::NodeId> childOwners;
            if (descend && !d.typeDefinition.isNull()) {
                auto chain = co_await remote_.typeChain(d.typeDefinition);
                if (!chain) co_return chain.status();
                childOwners.assign(chain->rbegin(), chain->rend());
            }
            childOwners.push_back(d.nodeId);
            auto path = d.path;
            out_.push_back(std::move(d));
            if (descend) {
                if (auto s = co_await level(std::move(childOwners), std::move(path)); s.isBad()) {
                    co_return s;
                }
            }
        }
        co_return ua::status::Good;
    }

    std::vector<InstanceDeclaration> take() { return std::move(out_); }

private:
    /// DataType and ValueRank of the variable declarations, in one Read.
    asio::awaitable<ua::StatusCode> readVariableAttributes(std::vector<InstanceDeclaration>& ds) {
        std::vector<ua::ReadValueId> ids;
        for (const auto& d : ds) {
            if (d.nodeClass != ua::NodeClass::Variable) continue;
            for (auto attribute : {ua::AttributeId::DataType, ua::AttributeId::ValueRank}) {
                ua::ReadValueId id;
                id.nodeId = d.nodeId;
                id.attributeId = static_cast<std::uint32_t>(attribute);
                ids.push_back(std::move(id));
            }
        }
        if (ids.empty()) co_return ua::status::Good;
        auto values = co_await remote_.read(std::move(ids));
        if (!values) co_return values.status();
        std::size_t i = 0;
        for (auto& d : ds) {
            if (d.nodeClass != ua::NodeClass::Variable) continue;
            const auto& dataType = (*values)[i++];
            const auto& valueRank = (*values)[i++];
            d.dataType = ua::NodeId(ns0::BaseDataType);
            if (dataType.value) {
                if (const auto* id = dataType.value->get<ua::NodeId>()) d.dataType = *id;
            }
            d.valueRank = ua::value_rank::kAny;
            if (valueRank.value) {
                if (const auto* rank = valueRank.value->get<std::int32_t>()) d.valueRank = *rank;
            }
        }
        co_return ua::status::Good;
    }

    RemoteAddressSpace& remote_;
    std::size_t maxDepth_;
    std::vector<InstanceDeclaration> out_;
};

}  // namespace

asio::awaitable<ua::Result<std::vector<InstanceDeclaration>>> instanceDeclarations(
    RemoteAddressSpace& remote, ua::NodeId type, std::size_t maxDepth) {
    auto chain = co_await remote.typeChain(std::move(type));
    if (!chain) co_return chain.status();
    Collector collector(remote, maxDepth);
    std::vector<ua::NodeId> owners(chain->rbegin(), chain->rend());  // root first
    std::vector<ua::QualifiedName> top;  // named: no braced temporary in co_await (GCC 12)
    if (auto s = co_await collector.level(std::move(owners), std::move(top)); s.isBad()) {
        co_return s;
    }
    co_return collector.take();
}

}  // namespace skillcell::skills
