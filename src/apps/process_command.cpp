// `skillcell process`: processes (Turtle, docs/processes.md) checked before any motion.
//  - `process check FILE...` lists every problem of each file with FILE:LINE, against the
//    skill models compiled in, or a knowledge base's with --kb. Exit 0 when every file is
//    clean, 1 when one has problems, 2 when a file or the KB cannot be read.
//  - `process add FILE --kb OPC-URL` checks a file against a running knowledge base's models
//    and loads it through the KB's Load method, as an Engineer: the KB's reasoner checks it and
//    the KB takes all of it or nothing, so a bad process changes nothing.
//  - `process list --kb URL` shows the processes a knowledge base holds, with their steps.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cell/cell_file.hpp"
#include "cell/scene_graph.hpp"
#include "client_security_options.hpp"
#include "commands.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/rdf/turtle.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "mes/process_check.hpp"
#include "mes/process_description.hpp"
#include "sparql_client_options.hpp"
#include "ua/client/blocking_client.hpp"

namespace skillcell::apps {
namespace {

struct ProcessOptions {
    std::vector<std::string> files;
    std::string kbUrl;  // the KB's SPARQL endpoint; `add`: its OPC UA endpoint
    ClientSecurityOptions security;
    std::string cellFile;  // whose scene the processes refer to
};

std::string readText(const std::string& file, bool* ok) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    *ok = static_cast<bool>(in) || in.eof();
    return text.str();
}

/// The KB's SPARQL endpoint of --kb; over https trusted and used with the command's
/// security options, as an OPC UA server would be.
kb::Expected<kb::HttpSparqlEndpoint> kbEndpoint(const ProcessOptions& o) {
    auto endpoint = kb::HttpSparqlEndpoint::fromUrl(o.kbUrl);
    if (!endpoint || !endpoint->url.tls) return endpoint;
    std::string uri;
    std::string error;
    auto security = commandClientSecurity(o.security, &uri, &error);
    if (!security) return kb::Error{error};
    endpoint->client = sparqlClientOptions(*security);
    return endpoint;
}

/// The skill models: the KB's when --kb is given, else those compiled in.
kb::Expected<mes::SkillModels> skillModels(const ProcessOptions& o) {
    const std::string& kbUrl = o.kbUrl;
    if (kbUrl.empty()) return mes::SkillModels::embedded();
    auto endpoint = kbEndpoint(o);
    if (!endpoint) return endpoint.failure();
    kb::HttpSparqlStore store(std::move(*endpoint));
    auto models = mes::SkillModels::fromStore(store);
    if (models && models->size() == 0) {
        return kb::Error{kbUrl + " holds no skill models (is it a skillcell knowledge base?)"};
    }
    return models;
}

/// The problems of one file, printed as FILE:LINE: MESSAGE; false when it has any.
bool checkFile(const std::string& file, const mes::SkillModels& models,
               const std::vector<kb::rdf::Triple>& scene) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "%s: cannot open\n", file.c_str());
        return false;
    }
    std::ostringstream text;
    text << in.rdbuf();
    std::vector<kb::rdf::Triple> triples;
    const auto problems = mes::checkProcessText(text.str(), models, &triples, scene);
    for (const auto& p : problems) {
        if (p.line > 0) {
            std::fprintf(stderr, "%s:%d: %s\n", file.c_str(), p.line, p.message.c_str());
        } else {
            std::fprintf(stderr, "%s: %s\n", file.c_str(), p.message.c_str());
        }
    }
    if (!problems.empty()) {
        std::fprintf(stderr, "%s: %zu problem%s\n", file.c_str(), problems.size(),
                     problems.size() == 1 ? "" : "s");
        return false;
    }
    // Clean: what it runs, step by step, as the MES reads it.
    std::vector<std::string> processes;
    for (const auto& t : triples) {
        if (t.predicate.value == std::string(kb::rdf::vocab::kRdf) + "type" &&
            t.object.value == std::string(mes::kProcessNs) + "Process") {
            processes.push_back(t.subject.value);
        }
    }
    for (const auto& iri : processes) {
        std::vector<kb::rdf::Triple> all = triples;
        all.insert(all.end(), scene.begin(), scene.end());
        auto p = mes::parseProcess(iri, all);
        if (!p) {
            std::fprintf(stderr, "%s: %s\n", file.c_str(), p.error().c_str());
            return false;
        }
        std::printf("%s: process <%s>, %zu steps, clean\n", file.c_str(), iri.c_str(),
                    p->steps.size());
        for (const auto& s : p->steps) {
            std::printf("  %d %s", s.index, mes::shortName(s.skillTypeIri).c_str());
            for (const auto& param : s.parameters) std::printf(" %s", param.name.c_str());
            std::printf("\n");
        }
    }
    return true;
}

int check(const ProcessOptions& o) {
    auto models = skillModels(o);
    if (!models) {
        std::cerr << "process check: the skill models: " << models.error() << "\n";
        return 2;
    }
    std::vector<kb::rdf::Triple> scene;
    if (!o.kbUrl.empty()) {
        // What the KB holds of the cell's scene, as the MES will see it.
        auto endpoint = kbEndpoint(o);
        if (!endpoint) {
            std::cerr << "process check: " << endpoint.error() << "\n";
            return 2;
        }
        kb::HttpSparqlStore store(std::move(*endpoint));
        auto resources = mes::constructTriples(store, mes::resourceQuery());
        if (!resources) {
            std::cerr << "process check: the knowledge base's resources: " << resources.error()
                      << "\n";
            return 2;
        }
        scene = std::move(*resources);
    }
    if (!o.cellFile.empty()) {
        const auto read = cell::readCellFile(o.cellFile);
        if (!read.cell) {
            for (const auto& p : read.problems) std::cerr << p.describe() << "\n";
            return 2;
        }
        const auto triples = cell::sceneTriples(*read.cell);
        scene.insert(scene.end(), triples.begin(), triples.end());
    }
    bool clean = true;
    for (const auto& f : o.files) clean = checkFile(f, *models, scene) && clean;
    return clean ? 0 : 1;
}

int list(const ProcessOptions& o) {
    auto endpoint = kbEndpoint(o);
    if (!endpoint) {
        std::cerr << "process list: " << endpoint.error() << "\n";
        return 2;
    }
    kb::HttpSparqlStore store(std::move(*endpoint));
    auto found = mes::processIris(store);
    if (!found) {
        std::cerr << "process list: " << o.kbUrl << ": " << found.error() << "\n";
        return 2;
    }
    const std::vector<std::string>& iris = *found;
    if (iris.empty()) std::printf("no processes in %s\n", o.kbUrl.c_str());
    int rc = 0;
    for (const auto& iri : iris) {
        auto p = mes::readProcess(store, iri);
        if (!p) {
            std::printf("%s: %s\n", iri.c_str(), p.error().c_str());
            rc = 1;
            continue;
        }
        std::printf("%s (%zu steps)\n", iri.c_str(), p->steps.size());
        for (const auto& s : p->steps) {
            std::printf("  %d %-28s", s.index, mes::shortName(s.skillTypeIri).c_str());
            for (const auto& param : s.parameters) std::printf(" %s", param.name.c_str());
            std::printf("\n");
        }
    }
    return rc;
}

/// The KB's Objects/KnowledgeBase methods (`skillcell kb`).
const ua::NodeId kKnowledgeBase(1, ua::String("KnowledgeBase"));

int add(const ProcessOptions& o) {
    const std::string& file = o.files.front();
    bool readable = false;
    const std::string text = readText(file, &readable);
    if (!readable) {
        std::cerr << "process add: cannot read " << file << "\n";
        return 2;
    }
    auto config = commandClientConfig(o.security, "skillcell process add");
    if (!config) return 2;
    ua::BlockingClient client;
    if (const auto s = client.connect(o.kbUrl, *config); s.isBad()) {
        std::cerr << "process add: cannot connect to " << o.kbUrl << ": "
                  << explainConnectFailure(s) << "\n";
        return 2;
    }
    struct Disconnect {
        ua::BlockingClient& c;
        ~Disconnect() { (void)c.disconnect(); }
    } disconnect{client};
    // The KB's own models: what the MES will check the process against.
    auto answer = client.call(kKnowledgeBase, ua::NodeId(1, ua::String("KnowledgeBase.Query")),
                              {ua::Variant(ua::String(mes::SkillModels::query())),
                               ua::Variant(ua::String(kb::media::kNTriples))});
    const auto* body = answer && !answer->empty() ? (*answer)[0].get<ua::String>() : nullptr;
    if (body == nullptr) {
        std::cerr << "process add: the knowledge base's models: "
                  << (answer ? "no result" : ua::statusName(answer.status())) << "\n";
        return 2;
    }
    auto modelTriples = kb::rdf::readTurtle(*body);
    if (!modelTriples) {
        std::cerr << "process add: the knowledge base's models: " << modelTriples.error() << "\n";
        return 2;
    }
    const auto models = mes::SkillModels::fromTriples(*modelTriples);
    // The cell's scene in the KB: the docks and tools a process refers to.
    auto resources = client.call(kKnowledgeBase, ua::NodeId(1, ua::String("KnowledgeBase.Query")),
                                 {ua::Variant(ua::String(mes::resourceQuery())),
                                  ua::Variant(ua::String(kb::media::kNTriples))});
    const auto* sceneText =
        resources && !resources->empty() ? (*resources)[0].get<ua::String>() : nullptr;
    auto scene = sceneText != nullptr ? kb::rdf::readTurtle(*sceneText)
                                      : kb::Expected<std::vector<kb::rdf::Triple>>(
                                            kb::Error{"the knowledge base gave no resources"});
    if (!scene) {
        std::cerr << "process add: the knowledge base's resources: " << scene.error() << "\n";
        return 2;
    }
    std::vector<kb::rdf::Triple> triples;
    const auto problems = mes::checkProcessText(text, models, &triples, *scene);
    for (const auto& p : problems) {
        std::fprintf(stderr, "%s:%d: %s\n", file.c_str(), p.line, p.message.c_str());
    }
    if (!problems.empty()) {
        std::fprintf(stderr, "%s: %zu problem%s; nothing was added\n", file.c_str(),
                     problems.size(), problems.size() == 1 ? "" : "s");
        return 1;
    }
    // The KB's Load: checked by its reasoner, the file's graph replaced, all or nothing.
    const std::string graph =
        std::string(kb::kProcessGraphPrefix) + std::filesystem::path(file).stem().string();
    auto done = client.call(kKnowledgeBase, ua::NodeId(1, ua::String("KnowledgeBase.Load")),
                            {ua::Variant(ua::String(graph)), ua::Variant(ua::String(text))});
    if (!done) {
        const auto s = done.status();
        std::cerr << "process add: the knowledge base refused the process: " << ua::statusName(s)
                  << (s == ua::status::BadUserAccessDenied
                          ? " (adding a process is an Engineer's task: --user engineer)"
                          : " (see the KB's log)")
                  << "; nothing was added\n";
        return 1;
    }
    std::printf("%s: added to %s as graph <%s> (%zu triples)\n", file.c_str(), o.kbUrl.c_str(),
                graph.c_str(), triples.size());
    return 0;
}

}  // namespace

Command addProcessCommand(CLI::App& app) {
    auto o = std::make_shared<ProcessOptions>();
    CLI::App* cmd = app.add_subcommand(
        "process", "Processes (Turtle, docs/processes.md): checked before any motion");
    cmd->require_subcommand(1);
    CLI::App* checkCmd = cmd->add_subcommand(
        "check",
        "Check process files against the skill models and list every problem as FILE:LINE: an "
        "unknown skill type, a parameter its ParameterSet lacks, a value of the wrong data "
        "type, a derivedFrom that lacks what the parameter needs, a broken firstStep/next "
        "chain, a cycle, an unreachable step, a dependsOn outside the process, a requirement "
        "on a property nothing records. Exit 0 when every file is clean, 1 when one has "
        "problems, 2 when the models cannot be read.");
    checkCmd->add_option("FILE", o->files, "process files (Turtle)")
        ->required()
        ->check(CLI::ExistingFile);
    checkCmd
        ->add_option("--cell", o->cellFile,
                     "the cell file whose scene (docks, tools, objects) the processes refer to, "
                     "as a cell's knowledge base holds it")
        ->check(CLI::ExistingFile);
    checkCmd->add_option("--kb", o->kbUrl,
                         "check against this knowledge base's models (its SPARQL endpoint, as "
                         "`skillcell kb` prints it) instead of those compiled in");
    addClientSecurityOptions(checkCmd, o->security);
    CLI::App* addCmd = cmd->add_subcommand(
        "add",
        "Check a process file against a running knowledge base's skill models, then load it "
        "(replacing an earlier version of the same file) through the KB's Load method, as "
        "an Engineer. A process with problems changes nothing. Exit 0 when added, 1 when it "
        "has problems or the KB refused it, 2 when the file or the KB cannot be reached.");
    addCmd->add_option("FILE", o->files, "the process file (Turtle)")
        ->required()
        ->expected(1)
        ->check(CLI::ExistingFile);
    addCmd->add_option("--kb", o->kbUrl, "the knowledge base's OPC UA endpoint")->required();
    addClientSecurityOptions(addCmd, o->security);
    CLI::App* listCmd = cmd->add_subcommand(
        "list", "List the processes a knowledge base holds, with their steps and parameters");
    listCmd->add_option("--kb", o->kbUrl, "the knowledge base's SPARQL endpoint")->required();
    addClientSecurityOptions(listCmd, o->security);
    return {cmd, [=] {
                if (listCmd->parsed()) return list(*o);
                if (addCmd->parsed()) return add(*o);
                return check(*o);
            }};
}

}  // namespace skillcell::apps
