#pragma once
// ModelRepository: the NodeSet2 files of a directory as ontologies, by model URI: the models
// a component's namespaces need beyond the ones compiled in (skillcell kb --models DIR).
// Files may require namespace 0, the companion models and each other; they are converted in
// dependency order, whatever their names.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "kb/expected.hpp"
#include "kb/owl/nodeset_ontology.hpp"

namespace skillcell::kb::owl {

class ModelRepository {
public:
    ModelRepository() = default;
    /// Converts every *.xml of `dir`. An Error names the file and what is wrong (a file that
    /// cannot be read or converted, a required model nobody provides, a cycle).
    [[nodiscard]] static Expected<ModelRepository> fromDirectory(const std::filesystem::path& dir);

    /// The ontology of model `uri` and those of the models it requires (transitively) that
    /// the repository holds, each after the ones it requires. Empty when `uri` is not here.
    [[nodiscard]] std::vector<const Ontology*> withRequirements(const std::string& uri) const;
    [[nodiscard]] std::vector<std::string> uris() const;

private:
    std::map<std::string, Ontology> byUri_;
};

}  // namespace skillcell::kb::owl
