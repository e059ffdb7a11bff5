#include "kb/owl/model_repository.hpp"

#include <fstream>
#include <set>
#include <sstream>

#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace skillcell::kb::owl {
namespace {

namespace fs = std::filesystem;

struct FileModel {
    NodeSetText text;
    std::string uri;
    std::vector<std::string> required;
};

// What a file provides and requires, from its <Models> (parsed against namespace 0 and the
// companion models, which is enough to read them).
Expected<FileModel> readModel(const fs::path& path, const ua::AddressSpace& known) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{"cannot read " + path.string(), ErrorKind::BadInput};
    std::ostringstream text;
    text << in.rdbuf();
    FileModel m{{path.string(), text.str()}, {}, {}};
    ua::ParsedNodeSet parsed;
    if (auto s = ua::parseNodeSet(known, m.text.xml, m.text.name, parsed); !s.ok()) {
        return Error{s.error, ErrorKind::BadInput};
    }
    if (parsed.models.empty()) return Error{path.string() + ": no <Model>", ErrorKind::BadInput};
    m.uri = parsed.models.front().uri;
    for (const auto& r : parsed.models.front().required) m.required.push_back(r.uri);
    return m;
}

}  // namespace

Expected<ModelRepository> ModelRepository::fromDirectory(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        return Error{"model directory " + dir.string() + " does not exist", ErrorKind::BadInput};
    }
    ua::AddressSpace known;
    if (auto s = ua::loadBaseNodeSet(known); !s.ok()) return Error{s.error};
    if (auto s = ua::loadCompanionModels(known); !s.ok()) return Error{s.error};
    std::set<std::string> provided;  // compiled in
    for (const auto& uri : known.namespaces()) provided.insert(uri);

    std::vector<fs::path> paths;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        if (entry.is_regular_file() && entry.path().extension() == ".xml") {
            paths.push_back(entry.path());
        }
    }
    std::sort(paths.begin(), paths.end());
    std::vector<FileModel> pending;
    for (const auto& p : paths) {
        auto m = readModel(p, known);
        if (!m) return m.failure();
        pending.push_back(std::move(*m));
    }
    // Dependency order: repeatedly take the files whose requirements are all provided.
    std::vector<NodeSetText> ordered;
    while (!pending.empty()) {
        const auto ready = std::find_if(pending.begin(), pending.end(), [&](const FileModel& m) {
            return std::all_of(m.required.begin(), m.required.end(),
                               [&](const std::string& r) { return provided.count(r) != 0; });
        });
        if (ready == pending.end()) {
            const FileModel& m = pending.front();
            std::string missing;
            for (const auto& r : m.required) {
                if (provided.count(r) == 0) missing += (missing.empty() ? "" : ", ") + r;
            }
            return Error{m.text.name + " requires " + missing +
                             ", which neither skillcell nor the directory provides (or the "
                             "files require each other in a cycle)",
                         ErrorKind::BadInput};
        }
        provided.insert(ready->uri);
        ordered.push_back(std::move(ready->text));
        pending.erase(ready);
    }
    auto ontologies = convertNodeSets(ordered, false, true);
    if (!ontologies) return ontologies.failure();
    ModelRepository repository;
    for (auto& o : *ontologies) repository.byUri_[o.iri] = std::move(o);
    return repository;
}

std::vector<const Ontology*> ModelRepository::withRequirements(const std::string& uri) const {
    std::vector<const Ontology*> out;
    std::set<std::string> seen;
    // Depth first, requirements before the model that requires them.
    const auto visit = [&](const auto& self, const std::string& u) -> void {
        const auto it = byUri_.find(u);
        if (it == byUri_.end() || !seen.insert(u).second) return;
        for (const auto& i : it->second.imports) self(self, i);
        out.push_back(&it->second);
    };
    visit(visit, uri);
    return out;
}

std::vector<std::string> ModelRepository::uris() const {
    std::vector<std::string> out;
    for (const auto& [uri, o] : byUri_) out.push_back(uri);
    return out;
}

}  // namespace skillcell::kb::owl
