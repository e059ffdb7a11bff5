#include "ua/nodeset/embedded_models.hpp"

#include <string>

#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/nodeset_snapshot.hpp"

namespace skillcell::ua {

bool loadEmbeddedModel(AddressSpace& as, std::string_view fileName, std::string_view sourceName,
                       NodeSetStatus& total) {
    NodeSetStatus st;
    bool loaded = false;
    for (const auto snapshot : embeddedSnapshots(fileName)) {
        ParsedNodeSet parsed;
        if (decodeSnapshot(as, snapshot, parsed) == SnapshotDecode::Decoded) {
            parsed.source = sourceName;
            st = commitNodeSet(as, std::move(parsed));
            loaded = true;
            break;
        }
    }
    // No snapshot for the indices its namespaces get here: the XML.
    if (!loaded) {
        if (const auto xml = embeddedModel(fileName); !xml.empty()) {
            st = loadNodeSet(as, xml, sourceName);
        } else {
            st.error = std::string(sourceName) + ": not embedded";
        }
    }
    total.nodes += st.nodes;
    total.references += st.references;
    if (!st.ok()) total.error = st.error;
    return st.ok();
}

NodeSetStatus loadBaseNodeSet(AddressSpace& as) {
    NodeSetStatus total;
    for (const auto& file : kNamespaceZeroFiles) {
        if (!loadEmbeddedModel(as, file.fileName, file.sourceName, total)) break;
    }
    return total;
}

NodeSetStatus loadCompanionModels(AddressSpace& as) {
    NodeSetStatus total;
    for (const auto& model : kCompanionModels) {
        if (as.findModel(model.uri) != nullptr) continue;
        if (!loadEmbeddedModel(as, model.fileName, model.fileName, total)) break;
    }
    return total;
}

NodeSetStatus loadCompanionModels(AddressSpace& as, std::span<const std::string_view> uris) {
    NodeSetStatus total;
    std::string unknown;
    const auto models = companionModelsFor(uris, &unknown);
    if (!models) {
        total.error = "no companion model has the namespace URI " + unknown;
        return total;
    }
    for (const auto& model : *models) {
        if (as.findModel(model.uri) != nullptr) continue;
        if (!loadEmbeddedModel(as, model.fileName, model.fileName, total)) break;
    }
    return total;
}

}  // namespace skillcell::ua
