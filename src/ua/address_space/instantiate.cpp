#include "ua/address_space/instantiate.hpp"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

namespace skillcell::ua {
namespace {

// Modelling rules (OPC 10000-3, 6.4.4); ids from NodeIds.csv.
constexpr std::uint32_t kMandatory = ns0::ModellingRuleMandatory;  // 78
constexpr std::uint32_t kOptional = ns0::ModellingRuleOptional;    // 80
constexpr std::uint32_t kOptionalPlaceholder = 11508;

struct Declaration {
    const Node* node;
    NodeId referenceType;
};

struct PlannedReference {
    NodeId source;
    NodeId referenceType;
    NodeId target;
};

class Planner {
public:
    Planner(const AddressSpace& as, const InstantiateOptions& options)
        : as_(as), options_(options) {}

    /// Plans the children of `instanceId` from the declarations of `sources` (priority
    /// order). `path` is the instance's browse path from the new root ("" for the root).
    StatusCode plan(const NodeId& instanceId, const std::vector<NodeId>& sources,
                    const std::string& path, int depth) {
        // A type that (indirectly) declares itself as a mandatory child would never end;
        // real models nest a few levels.
        if (depth > 32) return status::BadTypeDefinitionInvalid;
        for (const auto& d : declarations(sources)) {
            const NodeId rule = modellingRuleOf(*d.node);
            const std::string childPath =
                path.empty() ? d.node->browseName.name : path + "/" + d.node->browseName.name;
            // An OptionalPlaceholder is created when asked for by name, like an Optional
            // child: ProgramStateMachineType declares Start..Reset that way.
            const bool wanted =
                rule == NodeId(kMandatory) ||
                ((rule == NodeId(kOptional) || rule == NodeId(kOptionalPlaceholder)) &&
                 requested(childPath));
            if (!wanted) continue;

            Node child = copyDeclaration(*d.node);
            child.nodeId = AddressSpace::childNodeId(instanceId, d.node->browseName.name);
            if (as_.find(child.nodeId) != nullptr || !ids_.insert(child.nodeId).second) {
                return status::BadNodeIdExists;
            }
            const NodeId childId = child.nodeId;
            references_.push_back({instanceId, d.referenceType, childId});
            const NodeId type = as_.typeDefinitionOf(*d.node);
            if (!type.isNull())
                references_.push_back({childId, NodeId(ns0::HasTypeDefinition), type});
            declarationToInstance_.emplace(d.node->nodeId, childId);
            created_.emplace_back(d.node, childId);
            nodes_.push_back(std::move(child));

            std::vector<NodeId> childSources{d.node->nodeId};
            appendTypeChain(type, childSources);
            auto st = plan(childId, childSources, childPath, depth + 1);
            if (st.isBad()) return st;
        }
        return status::Good;
    }

    /// Copies the non-hierarchical references of the instantiated declarations.
    void planOtherReferences() {
        for (const auto& [decl, instanceId] : created_) {
            for (const auto& r : decl->references) {
                if (!r.isForward || r.referenceTypeId == NodeId(ns0::HasTypeDefinition) ||
                    r.referenceTypeId == NodeId(ns0::HasModellingRule) ||
                    as_.isSubtypeOf(r.referenceTypeId, NodeId(ns0::HierarchicalReferences))) {
                    continue;
                }
                auto it = declarationToInstance_.find(r.target);
                references_.push_back({instanceId, r.referenceTypeId,
                                       it != declarationToInstance_.end() ? it->second : r.target});
            }
        }
    }

    void appendTypeChain(NodeId type, std::vector<NodeId>& out) const {
        for (int depth = 0; depth < 64 && !type.isNull(); ++depth) {
            out.push_back(type);
            const Node* t = as_.find(type);
            if (t == nullptr) break;
            type = t->superType;
        }
    }

    bool reserve(const NodeId& id) { return as_.find(id) == nullptr && ids_.insert(id).second; }

    std::vector<Node>& nodes() { return nodes_; }
    std::vector<PlannedReference>& references() { return references_; }

private:
    std::vector<Declaration> declarations(const std::vector<NodeId>& sources) const {
        std::vector<Declaration> out;
        std::unordered_set<std::string> seen;
        for (const auto& sourceId : sources) {
            const Node* source = as_.find(sourceId);
            if (source == nullptr) continue;
            for (const auto& r : source->references) {
                if (!r.isForward || !as_.isSubtypeOf(r.referenceTypeId, NodeId(ns0::HasChild)) ||
                    as_.isSubtypeOf(r.referenceTypeId, NodeId(ns0::HasSubtype))) {
                    continue;
                }
                const Node* child = as_.find(r.target);
                if (child == nullptr || modellingRuleOf(*child).isNull()) continue;
                // The first source to declare a name wins: sources come most specific first.
                if (!seen.insert(child->browseName.name).second) continue;
                out.push_back({child, r.referenceTypeId});
            }
        }
        return out;
    }

    bool requested(const std::string& path) const {
        return std::any_of(options_.optionalChildren.begin(), options_.optionalChildren.end(),
                           [&](const std::string& p) {
                               return p == path || (p.size() > path.size() && p.starts_with(path) &&
                                                    p[path.size()] == '/');
                           });
    }

    static Node copyDeclaration(const Node& d) {
        Node n;
        n.nodeClass = d.nodeClass;
        n.browseName = d.browseName;
        n.displayName = d.displayName;
        n.description = d.description;
        n.writeMask = d.writeMask;
        n.userWriteMask = d.userWriteMask;
        n.eventNotifier = d.eventNotifier;
        n.value = d.value;
        n.dataType = d.dataType;
        n.valueRank = d.valueRank;
        n.arrayDimensions = d.arrayDimensions;
        n.accessLevel = d.accessLevel;
        n.userAccessLevel = d.userAccessLevel;
        n.minimumSamplingInterval = d.minimumSamplingInterval;
        n.historizing = d.historizing;
        n.executable = d.executable;
        n.userExecutable = d.userExecutable;
        n.method = d.method;
        return n;
    }

    const AddressSpace& as_;
    const InstantiateOptions& options_;
    std::unordered_set<NodeId> ids_;
    std::vector<Node> nodes_;
    std::vector<PlannedReference> references_;
    std::vector<std::pair<const Node*, NodeId>> created_;
    std::unordered_map<NodeId, NodeId> declarationToInstance_;
};

}  // namespace

NodeId modellingRuleOf(const Node& node) {
    for (const auto& r : node.references) {
        if (r.isForward && r.referenceTypeId == NodeId(ns0::HasModellingRule)) return r.target;
    }
    return {};
}

Result<NodeId> instantiate(AddressSpace& as, const NodeId& typeDefinition, const NodeId& parent,
                           const NodeId& referenceType, const QualifiedName& browseName,
                           const InstantiateOptions& options) {
    if (as.find(parent) == nullptr) return status::BadNodeIdUnknown;
    const Node* type = as.find(typeDefinition);
    if (type == nullptr || type->isAbstract ||
        (type->nodeClass != NodeClass::ObjectType && type->nodeClass != NodeClass::VariableType)) {
        return status::BadTypeDefinitionInvalid;
    }
    const NodeId ref = referenceType.isNull() ? NodeId(ns0::HasComponent) : referenceType;
    if (!as.isReferenceType(ref)) return status::BadReferenceTypeIdInvalid;
    if (browseName.name.empty()) return status::BadBrowseNameInvalid;

    Node root;
    root.nodeId = options.nodeId.isNull() ? AddressSpace::childNodeId(parent, browseName.name)
                                          : options.nodeId;
    root.browseName = browseName;
    root.displayName =
        options.displayName.text.empty() ? LocalizedText{{}, browseName.name} : options.displayName;
    if (type->nodeClass == NodeClass::ObjectType) {
        root.nodeClass = NodeClass::Object;
    } else {
        // A variable starts with its type's data type, rank and default value.
        root.nodeClass = NodeClass::Variable;
        root.dataType = type->dataType;
        root.valueRank = type->valueRank;
        root.arrayDimensions = type->arrayDimensions;
        root.value = type->value;
    }

    Planner planner(as, options);
    if (!planner.reserve(root.nodeId)) return status::BadNodeIdExists;
    std::vector<NodeId> sources;
    planner.appendTypeChain(typeDefinition, sources);
    auto st = planner.plan(root.nodeId, sources, "", 0);
    if (st.isBad()) return st;
    planner.planOtherReferences();

    // Commit: every id was checked free above, so these cannot fail.
    const NodeId rootId = root.nodeId;
    auto added = as.addNode(std::move(root));
    if (!added) return added.status();
    (void)as.addReference(parent, ref, rootId);
    (void)as.addReference(rootId, NodeId(ns0::HasTypeDefinition), typeDefinition);
    for (auto& n : planner.nodes()) {
        auto child = as.addNode(std::move(n));
        if (!child) return child.status();
    }
    for (const auto& r : planner.references()) {
        (void)as.addReference(r.source, r.referenceType, r.target);
    }
    return rootId;
}

}  // namespace skillcell::ua
