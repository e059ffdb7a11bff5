// `skillcell process`: processes (Turtle, docs/processes.md) checked before any motion.
//  - `process check FILE...` lists every problem of each file with FILE:LINE, against the
//    skill models compiled in, or a knowledge base's with --kb. Exit 0 when every file is
//    clean, 1 when one has problems, 2 when a file or the KB cannot be read.
//  - `process list --kb URL` shows the processes a knowledge base holds, with their steps.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "kb/rdf/turtle.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "mes/process_check.hpp"
#include "mes/process_description.hpp"

namespace skillcell::apps {
namespace {

struct ProcessOptions {
    std::vector<std::string> files;
    std::string kbUrl;  // the KB's SPARQL endpoint
};

/// The skill models: the KB's when `kbUrl` is given, else those compiled in.
kb::Expected<mes::SkillModels> skillModels(const std::string& kbUrl) {
    if (kbUrl.empty()) return mes::SkillModels::embedded();
    auto endpoint = kb::HttpSparqlEndpoint::fromUrl(kbUrl);
    if (!endpoint) return endpoint.failure();
    kb::HttpSparqlStore store(*endpoint);
    auto models = mes::SkillModels::fromStore(store);
    if (models && models->size() == 0) {
        return kb::Error{kbUrl + " holds no skill models (is it a skillcell knowledge base?)"};
    }
    return models;
}

/// The problems of one file, printed as FILE:LINE: MESSAGE; false when it has any.
bool checkFile(const std::string& file, const mes::SkillModels& models) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "%s: cannot open\n", file.c_str());
        return false;
    }
    std::ostringstream text;
    text << in.rdbuf();
    std::vector<kb::rdf::Triple> triples;
    const auto problems = mes::checkProcessText(text.str(), models, &triples);
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
        auto p = mes::parseProcess(iri, triples);
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
    auto models = skillModels(o.kbUrl);
    if (!models) {
        std::cerr << "process check: the skill models: " << models.error() << "\n";
        return 2;
    }
    bool clean = true;
    for (const auto& f : o.files) clean = checkFile(f, *models) && clean;
    return clean ? 0 : 1;
}

int list(const ProcessOptions& o) {
    auto endpoint = kb::HttpSparqlEndpoint::fromUrl(o.kbUrl);
    if (!endpoint) {
        std::cerr << "process list: " << endpoint.error() << "\n";
        return 2;
    }
    kb::HttpSparqlStore store(*endpoint);
    const std::string type = std::string(kb::rdf::vocab::kRdf) + "type";
    auto found = mes::constructTriples(store, "CONSTRUCT { ?p <" + type + "> <" +
                                                  std::string(mes::kProcessNs) +
                                                  "Process> } WHERE { ?p <" + type + "> <" +
                                                  std::string(mes::kProcessNs) + "Process> }");
    if (!found) {
        std::cerr << "process list: " << o.kbUrl << ": " << found.error() << "\n";
        return 2;
    }
    std::vector<std::string> iris;
    for (const auto& t : *found) iris.push_back(t.subject.value);
    std::sort(iris.begin(), iris.end());
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
    checkCmd->add_option("--kb", o->kbUrl,
                         "check against this knowledge base's models (its SPARQL endpoint, as "
                         "`skillcell kb` prints it) instead of those compiled in");
    CLI::App* listCmd = cmd->add_subcommand(
        "list", "List the processes a knowledge base holds, with their steps and parameters");
    listCmd->add_option("--kb", o->kbUrl, "the knowledge base's SPARQL endpoint")->required();
    return {cmd, [=] { return listCmd->parsed() ? list(*o) : check(*o); }};
}

}  // namespace skillcell::apps
