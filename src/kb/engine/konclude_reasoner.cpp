#include "kb/engine/konclude_reasoner.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <utility>

#include "kb/rdf/turtle.hpp"
#include "process/child_process.hpp"

namespace skillcell::kb::engine {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kOwlThing = "http://www.w3.org/2002/07/owl#Thing";
/// A tenth of a normal process's share of a contended core (CFS weights 110 vs 1024).
constexpr int kReasonerNiceness = 10;

/// A directory of our own for one run, removed with everything in it.
class TempDir {
public:
    static Expected<TempDir> create(const fs::path& root) {
        std::error_code ec;
        const fs::path base = root.empty() ? fs::temp_directory_path(ec) : root;
        std::string pattern = (base / "skillcell-konclude-XXXXXX").string();
        if (ec || ::mkdtemp(pattern.data()) == nullptr) {
            return Error{"cannot create a temporary directory in " + base.string() + ": " +
                         process::errnoText(errno)};
        }
        TempDir dir;
        dir.path_ = pattern;
        return dir;
    }
    TempDir(TempDir&& other) noexcept : path_(std::exchange(other.path_, {})) {}
    TempDir& operator=(TempDir&&) = delete;
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    ~TempDir() {
        std::error_code ec;
        if (!path_.empty()) fs::remove_all(path_, ec);
    }
    [[nodiscard]] const fs::path& path() const { return path_; }

private:
    TempDir() = default;
    fs::path path_;
};

/// Konclude's "{error}" lines: it reports failures (a file no parser accepts) there and
/// still exits 0 with a verdict on whatever it did read.
std::string errorLines(const std::string& console) {
    std::string lines;
    std::istringstream in(console);
    for (std::string line; std::getline(in, line);) {
        if (line.starts_with("{error}")) lines += line + "\n";
    }
    return lines;
}

std::string decodeXml(std::string_view text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '&') {
            out += text[i];
            continue;
        }
        const auto semi = text.find(';', i);
        if (semi == std::string_view::npos) {
            out += text.substr(i);
            break;
        }
        const std::string_view entity = text.substr(i + 1, semi - i - 1);
        if (entity == "amp") {
            out += '&';
        } else if (entity == "lt") {
            out += '<';
        } else if (entity == "gt") {
            out += '>';
        } else if (entity == "quot") {
            out += '"';
        } else if (entity == "apos") {
            out += '\'';
        } else if (entity.starts_with('#')) {
            const bool hex = entity.size() > 1 && (entity[1] == 'x' || entity[1] == 'X');
            const unsigned long cp =
                std::stoul(std::string(entity.substr(hex ? 2 : 1)), nullptr, hex ? 16 : 10);
            // UTF-8 encoding of the code point.
            if (cp < 0x80) {
                out += static_cast<char>(cp);
            } else if (cp < 0x800) {
                out += static_cast<char>(0xC0 | (cp >> 6));
                out += static_cast<char>(0x80 | (cp & 0x3F));
            } else if (cp < 0x10000) {
                out += static_cast<char>(0xE0 | (cp >> 12));
                out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
                out += static_cast<char>(0x80 | (cp & 0x3F));
            } else {
                out += static_cast<char>(0xF0 | (cp >> 18));
                out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
                out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
                out += static_cast<char>(0x80 | (cp & 0x3F));
            }
        } else {
            out += text.substr(i, semi - i + 1);  // unknown: keep as written
        }
        i = semi;
    }
    return out;
}

/// The value of attribute `name` in the tag text `tag`, decoded; nullopt if absent.
std::optional<std::string> attribute(std::string_view tag, std::string_view name) {
    const std::string key = " " + std::string(name) + "=\"";
    const auto at = tag.find(key);
    if (at == std::string_view::npos) return std::nullopt;
    const auto begin = at + key.size();
    const auto end = tag.find('"', begin);
    if (end == std::string_view::npos) return std::nullopt;
    return decodeXml(tag.substr(begin, end - begin));
}

/// The IRI of the first element `<element ...>` in `block`: IRI="..." or abbreviatedIRI.
std::optional<std::string> entityIri(std::string_view block, std::string_view element,
                                     const std::map<std::string, std::string>& prefixes) {
    const std::string open = "<" + std::string(element);
    for (auto at = block.find(open); at != std::string_view::npos; at = block.find(open, at + 1)) {
        const char next = at + open.size() < block.size() ? block[at + open.size()] : '\0';
        if (next != ' ' && next != '/' && next != '>') continue;  // <ClassAssertion is not <Class
        const auto end = block.find('>', at);
        const std::string_view tag =
            block.substr(at, end == std::string_view::npos ? end : end - at);
        if (auto iri = attribute(tag, "IRI")) return iri;
        if (auto abbreviated = attribute(tag, "abbreviatedIRI")) {
            const auto colon = abbreviated->find(':');
            const auto prefix = prefixes.find(abbreviated->substr(0, colon));
            if (colon == std::string::npos || prefix == prefixes.end()) return std::nullopt;
            return prefix->second + abbreviated->substr(colon + 1);
        }
        return std::nullopt;
    }
    return std::nullopt;
}

/// The triples of `units` selected by `chosen`, after `background`.
std::vector<rdf::Triple> assemble(const std::vector<rdf::Triple>& background,
                                  const std::vector<std::vector<rdf::Triple>>& units,
                                  const std::vector<std::size_t>& chosen) {
    std::vector<rdf::Triple> triples = background;
    for (std::size_t u : chosen) triples.insert(triples.end(), units[u].begin(), units[u].end());
    return triples;
}

std::vector<std::size_t> joined(std::vector<std::size_t> a, const std::vector<std::size_t>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

/// QuickXplain (Junker 2004) over groups of candidate triples, with a run budget.
class ConflictSearch {
public:
    using Check = std::function<Expected<bool>(const std::vector<std::size_t>&)>;

    ConflictSearch(Check inconsistent, std::size_t budget)
        : inconsistent_(std::move(inconsistent)), budget_(budget) {}

    /// Precondition: base ∪ candidates is inconsistent. Returns a subset X of candidates
    /// with base ∪ X inconsistent, minimal unless the budget ran out (then a superset of a
    /// minimal one: once out of runs, a branch keeps all its candidates).
    Expected<std::vector<std::size_t>> search(const std::vector<std::size_t>& base, bool baseGrew,
                                              const std::vector<std::size_t>& candidates) {
        if (baseGrew) {
            if (runs_ >= budget_) {
                budgetHit_ = true;
                return candidates;
            }
            ++runs_;
            auto bad = inconsistent_(base);
            if (!bad) return Error{bad.error()};
            if (*bad) return std::vector<std::size_t>{};
        }
        if (candidates.size() <= 1) return candidates;
        const auto half = static_cast<std::ptrdiff_t>(candidates.size() / 2);
        const std::vector<std::size_t> first(candidates.begin(), candidates.begin() + half);
        const std::vector<std::size_t> second(candidates.begin() + half, candidates.end());
        auto inSecond = search(joined(base, first), !first.empty(), second);
        if (!inSecond) return inSecond;
        auto inFirst = search(joined(base, *inSecond), !inSecond->empty(), first);
        if (!inFirst) return inFirst;
        return joined(std::move(*inFirst), *inSecond);
    }

    [[nodiscard]] std::size_t runs() const { return runs_; }
    [[nodiscard]] bool budgetHit() const { return budgetHit_; }

private:
    Check inconsistent_;
    std::size_t budget_;
    std::size_t runs_ = 0;
    bool budgetHit_ = false;
};

}  // namespace

Expected<std::vector<ClassAssertion>> parseRealization(std::string_view owlXml) {
    if (owlXml.find("<Ontology") == std::string_view::npos) {
        return Error{"Konclude realization output is not OWL/XML: " +
                     process::tail(std::string(owlXml), 300)};
    }
    std::map<std::string, std::string> prefixes;
    for (auto at = owlXml.find("<Prefix "); at != std::string_view::npos;
         at = owlXml.find("<Prefix ", at + 1)) {
        const std::string_view tag = owlXml.substr(at, owlXml.find('>', at) - at);
        auto name = attribute(tag, "name");
        auto iri = attribute(tag, "IRI");
        if (name && iri) prefixes[*name] = *iri;
    }
    std::vector<ClassAssertion> types;
    constexpr std::string_view kOpen = "<ClassAssertion>";
    constexpr std::string_view kClose = "</ClassAssertion>";
    for (auto at = owlXml.find(kOpen); at != std::string_view::npos;
         at = owlXml.find(kOpen, at + kOpen.size())) {
        const auto end = owlXml.find(kClose, at);
        if (end == std::string_view::npos) return Error{"Konclude realization output is truncated"};
        const std::string_view block = owlXml.substr(at + kOpen.size(), end - at - kOpen.size());
        auto cls = entityIri(block, "Class", prefixes);
        auto individual = entityIri(block, "NamedIndividual", prefixes);
        // Anonymous individuals and class expressions have no IRI to report.
        if (!cls || !individual || *cls == kOwlThing) continue;
        types.push_back({std::move(*individual), std::move(*cls)});
    }
    std::sort(types.begin(), types.end());
    types.erase(std::unique(types.begin(), types.end()), types.end());
    return types;
}

std::vector<std::vector<rdf::Triple>> blankNodeGroups(const std::vector<rdf::Triple>& triples) {
    // Union-find over triple indices; a blank node joins every triple it appears in.
    std::vector<std::size_t> parent(triples.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    auto root = [&parent](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::map<std::string, std::size_t> firstUse;
    for (std::size_t i = 0; i < triples.size(); ++i) {
        for (const rdf::Term* term : {&triples[i].subject, &triples[i].object}) {
            if (term->kind != rdf::Term::Kind::Blank) continue;
            const auto [it, fresh] = firstUse.emplace(term->value, i);
            if (!fresh) parent[root(i)] = root(it->second);
        }
    }
    std::vector<std::vector<rdf::Triple>> groups;
    std::map<std::size_t, std::size_t> groupOfRoot;  // in order of first appearance
    for (std::size_t i = 0; i < triples.size(); ++i) {
        const auto [it, fresh] = groupOfRoot.emplace(root(i), groups.size());
        if (fresh) groups.emplace_back();
        groups[it->second].push_back(triples[i]);
    }
    return groups;
}

KoncludeReasoner::KoncludeReasoner(KoncludeConfig config) : config_(std::move(config)) {}

Expected<KoncludeReasoner::Output> KoncludeReasoner::run(std::string_view command,
                                                         std::string_view turtle,
                                                         bool wantResult) const {
    auto dir = TempDir::create(config_.tempRoot);
    if (!dir) return Error{dir.error()};
    const fs::path input = dir->path() / "ontology.ttl";
    const fs::path result = dir->path() / "result.owl.xml";
    {
        std::ofstream out(input, std::ios::binary);
        out << turtle;
        if (!out.flush()) return Error{"cannot write " + input.string()};
    }
    // Without -w Konclude hangs at "Precomputing" (measured on 0.7).
    std::vector<std::string> argv{config_.binary, std::string(command), "-w", "AUTO",
                                  "-i",           input.string()};
    if (wantResult) {
        argv.emplace_back("-o");
        argv.push_back(result.string());
    }
    process::ProcessOptions options;
    options.workingDir = dir->path();
    // Reasoning is batch work: a component plugged in meanwhile, and the detectors
    // connecting to it, come first (they shared two cores with it in the demo).
    options.niceness = kReasonerNiceness;
    auto ran = process::runToCompletion(argv, config_.timeout, options);
    if (!ran) return Error{"Konclude " + std::string(command) + ": " + ran.error()};
    Output output{ran->out + ran->err, {}};
    if (ran->exitCode != 0) {
        return Error{"Konclude " + std::string(command) + " failed (exit code " +
                     std::to_string(ran->exitCode) + "): " + process::tail(output.console)};
    }
    // An inconsistent ontology makes Konclude log its precomputation steps as failed.
    const bool inconsistent = output.console.find(" is inconsistent.") != std::string::npos;
    if (const std::string errors = errorLines(output.console); !errors.empty() && !inconsistent) {
        return Error{"Konclude " + std::string(command) + " reported errors:\n" +
                     process::tail(errors)};
    }
    if (wantResult) {
        std::ifstream in(result, std::ios::binary);
        if (!in) {
            return Error{"Konclude " + std::string(command) +
                         " wrote no result: " + process::tail(output.console)};
        }
        std::ostringstream text;
        text << in.rdbuf();
        output.result = text.str();
    }
    return output;
}

namespace {
/// The verdict Konclude prints ("Ontology '...' is consistent." / "... is inconsistent.").
std::optional<bool> verdict(const std::string& console) {
    if (console.find("' is inconsistent.") != std::string::npos) return false;
    if (console.find("' is consistent.") != std::string::npos) return true;
    return std::nullopt;
}
}  // namespace

Expected<bool> KoncludeReasoner::isConsistent(std::string_view turtle) const {
    auto output = run("consistency", turtle, false);
    if (!output) return Error{output.error()};
    if (auto consistent = verdict(output->console)) return *consistent;
    return Error{"Konclude consistency gave no verdict: " + process::tail(output->console)};
}

Expected<Realization> KoncludeReasoner::realize(std::string_view turtle) const {
    auto output = run("realization", turtle, true);
    if (!output) return Error{output.error()};
    // For an inconsistent ontology Konclude says so and types everyone owl:Nothing.
    if (output->console.find(" is inconsistent.") != std::string::npos) {
        return Realization{false, {}};
    }
    auto types = parseRealization(output->result);
    if (!types) return Error{types.error()};
    return Realization{true, std::move(*types)};
}

Expected<bool> KoncludeReasoner::consistencyOf(const std::vector<rdf::Triple>& triples) const {
    return isConsistent(rdf::writeTurtle(triples));
}

Expected<Explanation> KoncludeReasoner::explainInconsistency(
    const std::vector<rdf::Triple>& background, const std::vector<rdf::Triple>& candidates,
    ExplainOptions options) const {
    const auto units = blankNodeGroups(candidates);
    Explanation explanation;

    auto backgroundOk = consistencyOf(background);
    ++explanation.runs;
    if (!backgroundOk) return Error{backgroundOk.error()};
    if (!*backgroundOk) return Error{"the background alone is inconsistent: nothing to explain"};

    std::vector<std::size_t> all(units.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    auto allOk = consistencyOf(assemble(background, units, all));
    ++explanation.runs;
    if (!allOk) return Error{allOk.error()};
    if (*allOk) return explanation;  // consistent: inconsistent == false
    explanation.inconsistent = true;

    const std::size_t budget =
        options.maxRuns > explanation.runs ? options.maxRuns - explanation.runs : 0;
    ConflictSearch search(
        [&](const std::vector<std::size_t>& chosen) -> Expected<bool> {
            auto ok = consistencyOf(assemble(background, units, chosen));
            if (!ok) return Error{ok.error()};
            return !*ok;
        },
        budget);
    auto conflict = search.search({}, false, all);
    explanation.runs += search.runs();
    if (!conflict) return Error{conflict.error()};
    explanation.runLimitHit = search.budgetHit();
    std::sort(conflict->begin(), conflict->end());
    for (std::size_t u : *conflict) {
        explanation.conflict.insert(explanation.conflict.end(), units[u].begin(), units[u].end());
    }
    spdlog::debug("explained an inconsistency: {} of {} candidate triples, {} Konclude runs{}",
                  explanation.conflict.size(), candidates.size(), explanation.runs,
                  explanation.runLimitHit ? " (run limit hit: maybe not minimal)" : "");
    return explanation;
}

}  // namespace skillcell::kb::engine
