#pragma once
// The ontologies written by the project (models/owl/*.ttl), compiled in by
// src/ua/nodeset/embed_models.cmake so that the knowledge base needs no source tree.
#include <string_view>
#include <vector>

namespace skillcell::kb::owl {

/// The text of models/owl/<fileName> ("opcua-core.ttl"); empty if there is no such file.
[[nodiscard]] std::string_view embeddedOntology(std::string_view fileName);
/// The names of all embedded ontology files.
[[nodiscard]] std::vector<std::string_view> embeddedOntologyNames();

}  // namespace skillcell::kb::owl
