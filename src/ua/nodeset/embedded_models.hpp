#pragma once
// Loading the models compiled into the program: namespace 0 and the companion models, each
// from its snapshot (nodeset_snapshot.hpp, made by the build from the embedded XML) where
// the snapshot's namespace indices fit the address space, else from the XML.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::ua {

/// The build's snapshots of the embedded model `fileName` ("Opc.Ua.Di.NodeSet2.xml"), one for
/// each set of namespace indices its namespaces get in the orders servers load models in.
[[nodiscard]] std::vector<std::span<const std::uint8_t>> embeddedSnapshots(
    std::string_view fileName);

/// Loads the embedded `fileName` and adds its counts (or its error) to `total`; false on
/// error (also when it is not embedded). Messages name the file `sourceName`.
bool loadEmbeddedModel(AddressSpace& as, std::string_view fileName, std::string_view sourceName,
                       NodeSetStatus& total);
/// Loads namespace 0 (kNamespaceZeroFiles), stopping at the first error.
[[nodiscard]] NodeSetStatus loadBaseNodeSet(AddressSpace& as);

/// Loads the embedded companion models that are not loaded yet, in dependency order
/// (namespace 0 must be loaded). Stops at the first error; the status sums the nodes and
/// references added.
[[nodiscard]] NodeSetStatus loadCompanionModels(AddressSpace& as);
/// Loads the companion models `uris` and, before them, the companion models they require
/// (their files' <RequiredModel>s, transitively); those loaded already are skipped. An URI
/// that is no companion model's is an error that names it, and nothing is loaded.
[[nodiscard]] NodeSetStatus loadCompanionModels(AddressSpace& as,
                                                std::span<const std::string_view> uris);

}  // namespace skillcell::ua
