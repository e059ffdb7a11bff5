#include "ua/nodeset/companion_models.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <set>
#include <string>

namespace skillcell::ua {

namespace {

const CompanionModel* companionModel(std::string_view uri) {
    const auto* it = std::find_if(kCompanionModels.begin(), kCompanionModels.end(),
                                  [&](const CompanionModel& m) { return m.uri == uri; });
    return it == kCompanionModels.end() ? nullptr : it;
}

/// One top-level element of an embedded model (`name`: "Models", "NamespaceUris"), parsed
/// alone: the rest of the file is what a load skips by not loading it.
bool parseElement(std::string_view xml, std::string_view name, pugi::xml_document& doc) {
    const std::string open = "<" + std::string(name) + ">";
    const std::string close = "</" + std::string(name) + ">";
    const auto begin = xml.find(open);
    const auto end = xml.find(close);
    if (begin == std::string_view::npos || end == std::string_view::npos || end < begin) {
        return false;
    }
    const auto element = xml.substr(begin, end + close.size() - begin);
    return static_cast<bool>(doc.load_buffer(element.data(), element.size()));
}

/// The <RequiredModel> URIs of an embedded model.
std::vector<std::string> requiredModelUris(std::string_view xml) {
    pugi::xml_document doc;
    if (!parseElement(xml, "Models", doc)) return {};
    std::vector<std::string> uris;
    for (const auto& model : doc.child("Models").children("Model")) {
        for (const auto& required : model.children("RequiredModel")) {
            uris.emplace_back(required.attribute("ModelUri").as_string());
        }
    }
    return uris;
}

}  // namespace

std::optional<std::vector<CompanionModel>> companionModelsFor(
    std::span<const std::string_view> uris, std::string* unknown) {
    std::set<std::string_view> wanted;
    std::vector<std::string_view> pending(uris.begin(), uris.end());
    while (!pending.empty()) {
        const auto uri = pending.back();
        pending.pop_back();
        const CompanionModel* model = companionModel(uri);
        if (model == nullptr) {
            if (unknown != nullptr) *unknown = std::string(uri);
            return std::nullopt;
        }
        if (!wanted.insert(model->uri).second) continue;
        for (const auto& required : requiredModelUris(embeddedModel(model->fileName))) {
            // Namespace 0 is the base load's; other requirements are companion models.
            if (const CompanionModel* r = companionModel(required)) pending.push_back(r->uri);
        }
    }
    std::vector<CompanionModel> ordered;
    for (const auto& model : kCompanionModels) {
        if (wanted.contains(model.uri)) ordered.push_back(model);
    }
    return ordered;
}

std::optional<std::string_view> companionModelDeclaring(std::string_view name) {
    for (const auto& model : kCompanionModels) {
        const auto xml = embeddedModel(model.fileName);
        // The file's index of its own namespace: its place among the file's NamespaceUris.
        pugi::xml_document doc;
        if (!parseElement(xml, "NamespaceUris", doc)) continue;
        std::size_t index = 0;
        std::size_t own = 0;
        for (const auto& uri : doc.child("NamespaceUris").children("Uri")) {
            ++index;
            if (uri.text().as_string() == model.uri) own = index;
        }
        if (own == 0) continue;
        const std::string attribute =
            "BrowseName=\"" + std::to_string(own) + ":" + std::string(name) + "\"";
        if (xml.find(attribute) != std::string_view::npos) return model.uri;
    }
    return std::nullopt;
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
