// `skillcell nodeset2owl`: NodeSet2 files to OWL 2 ontologies in Turtle (src/kb/owl), one
// ontology per NodeSet. Files are given in dependency order: each may require namespace 0
// (compiled in) and the files before it. Exit 0 on success, 1 when a file cannot be read or
// converted (the message names the file and line), 2 on usage errors.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "kb/owl/nodeset_ontology.hpp"
#include "ua/pki/file_util.hpp"

namespace skillcell::apps {

namespace {

namespace fs = std::filesystem;

struct Nodeset2OwlOptions {
    std::vector<std::string> files;
    bool embedded = false;
    bool base = false;
    bool core = false;
    std::string outputDir;
};

// "Skillcell.Skills.NodeSet2.xml" -> "Skillcell.Skills.ttl".
std::string turtleName(const std::string& nodeSetName) {
    std::string stem = fs::path(nodeSetName).filename().string();
    for (const std::string suffix : {".xml", ".NodeSet2"}) {
        if (stem.size() > suffix.size() &&
            stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0) {
            stem.resize(stem.size() - suffix.size());
        }
    }
    return stem + ".ttl";
}

int run(const Nodeset2OwlOptions& o) {
    std::vector<kb::owl::NodeSetText> inputs;
    for (const auto& f : o.files) {
        std::ifstream in(f, std::ios::binary);
        if (!in) {
            std::cerr << "nodeset2owl: cannot read " << f << "\n";
            return 1;
        }
        std::ostringstream text;
        text << in.rdbuf();
        inputs.push_back({f, text.str()});
    }
    auto converted =
        o.embedded ? kb::owl::embeddedModelOntologies() : kb::owl::convertNodeSets(inputs, o.base);
    if (!converted) {
        std::cerr << "nodeset2owl: " << converted.error() << "\n";
        return 1;
    }
    std::vector<std::pair<std::string, std::string>> outputs;  // file name, Turtle
    for (const auto& ontology : *converted) {
        const std::string name = ontology.source.empty() ? ontology.iri : ontology.source;
        outputs.emplace_back(turtleName(name), kb::owl::toTurtle(ontology));
    }
    if (o.core) outputs.emplace_back("opcua-core.ttl", std::string(kb::owl::coreOntologyTurtle()));

    if (o.outputDir.empty()) {
        if (outputs.size() != 1) {
            std::cerr << "nodeset2owl: " << outputs.size()
                      << " ontologies: give --output-dir to write one file each\n";
            return 2;
        }
        std::cout << outputs.front().second;
        return std::cout.good() ? 0 : 1;
    }
    std::error_code ec;
    fs::create_directories(o.outputDir, ec);
    if (ec) {
        std::cerr << "nodeset2owl: cannot create " << o.outputDir << ": " << ec.message() << "\n";
        return 1;
    }
    for (const auto& [name, turtle] : outputs) {
        const fs::path path = fs::path(o.outputDir) / name;
        // Atomic, so that a crash never leaves half an ontology for a loader to read.
        if (!writeFileAtomically(path, turtle, 0644)) {
            std::cerr << "nodeset2owl: cannot write " << path.string() << "\n";
            return 1;
        }
        std::cout << "WROTE " << path.string() << "\n";
    }
    return 0;
}

}  // namespace

Command addNodeset2OwlCommand(CLI::App& app) {
    auto o = std::make_shared<Nodeset2OwlOptions>();
    auto* cmd = app.add_subcommand(
        "nodeset2owl",
        "Convert NodeSet2 files to OWL 2 ontologies (Turtle), one per NodeSet. Give the files "
        "in dependency order; namespace 0 is compiled in.");
    cmd->add_option("files", o->files, "NodeSet2 XML files, each after the ones it requires")
        ->check(CLI::ExistingFile);
    cmd->add_flag("--embedded", o->embedded,
                  "convert the NodeSets compiled into skillcell (namespace 0 and the companion "
                  "models of models/) instead of files");
    cmd->add_flag("--base", o->base, "also write namespace 0's ontology (Opc.Ua.NodeSet2.Base)");
    cmd->add_flag("--core", o->core,
                  "also write skillcell's core OPC UA ontology (opcua-core.ttl), which every "
                  "converted ontology imports");
    cmd->add_option("-o,--output-dir", o->outputDir,
                    "directory for one <name>.ttl per ontology (default: stdout, one ontology)");
    return {cmd, [cmd, o]() {
                if (o->embedded == !o->files.empty()) {
                    std::cerr << "nodeset2owl: give NodeSet2 files or --embedded (one of them)\n"
                              << cmd->help();
                    return 2;
                }
                return run(*o);
            }};
}

}  // namespace skillcell::apps
