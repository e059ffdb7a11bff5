#include "ua/nodeset/companion_models.hpp"

#include <string>

namespace skillcell::ua {

NodeSetStatus loadCompanionModels(AddressSpace& as) {
    NodeSetStatus total;
    for (const auto& model : kCompanionModels) {
        if (as.findModel(model.uri) != nullptr) continue;
        if (!loadEmbeddedModel(as, model.fileName, model.fileName, total)) break;
    }
    return total;
}

std::optional<NodeId> skillsNodeId(const AddressSpace& as, std::uint32_t id) {
    const auto ns = as.namespaceIndex(companion::kSkillsUri);
    if (!ns) return std::nullopt;
    return NodeId(*ns, id);
}

std::optional<NodeId> findTypeByName(const AddressSpace& as, std::string_view uri,
                                     std::string_view name) {
    const auto ns = as.namespaceIndex(uri);
    if (!ns) return std::nullopt;
    std::optional<NodeId> found;
    as.forEachNode([&](const Node& n) {
        if (found || n.browseName.namespaceIndex != *ns || n.browseName.name != name) return;
        if (n.nodeClass == NodeClass::ObjectType || n.nodeClass == NodeClass::DataType) {
            found = n.nodeId;
        }
    });
    return found;
}

}  // namespace skillcell::ua
