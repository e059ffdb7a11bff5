#pragma once
// KoncludeReasoner: OWL 2 DL reasoning by the Konclude command-line tool, one process per
// question, each in a private temporary directory that is removed afterwards.
//
// Konclude reads the ontology's RDF with the OWL mapping, so classes and properties must be
// declared (`:C a owl:Class`, `:p a owl:ObjectProperty`): undeclared ones are ignored.
// A file it cannot parse is reported as an error here (Konclude itself would call the empty
// ontology it fell back to "consistent").
#include <chrono>
#include <compare>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"

namespace skillcell::kb::engine {

struct KoncludeConfig {
    std::string binary = "/usr/bin/Konclude";
    std::chrono::milliseconds timeout{60'000};  // per Konclude run
    std::filesystem::path tempRoot;             // empty: the system's temporary directory
};

/// One inferred type: `individual` rdf:type `cls` (IRIs).
struct ClassAssertion {
    std::string individual;
    std::string cls;
    // clang-tidy 14 takes the 0 of the synthesised comparison of a <=> result for a pointer.
    // NOLINTNEXTLINE(modernize-use-nullptr)
    friend auto operator<=>(const ClassAssertion&, const ClassAssertion&) = default;
    friend bool operator==(const ClassAssertion&, const ClassAssertion&) = default;
};

struct Realization {
    bool consistent = true;
    /// Sorted; every named individual's asserted and inferred types except owl:Thing.
    /// Empty when the ontology is inconsistent (then everything is of every type).
    std::vector<ClassAssertion> types;
};

struct ExplainOptions {
    std::size_t maxRuns = 64;  // Konclude runs at most, including the two initial checks
};

struct Explanation {
    /// False: background and candidates together are consistent; nothing to explain.
    bool inconsistent = false;
    /// Candidates that with the background are inconsistent; minimal (removing any one
    /// blank-node group makes it consistent) unless runLimitHit.
    std::vector<rdf::Triple> conflict;
    /// The run budget ran out: `conflict` is still inconsistent, but may not be minimal.
    bool runLimitHit = false;
    std::size_t runs = 0;
};

class KoncludeReasoner {
public:
    explicit KoncludeReasoner(KoncludeConfig config = {});

    /// Whether the ontology (Turtle or N-Triples) is consistent.
    [[nodiscard]] Expected<bool> isConsistent(std::string_view turtle) const;
    /// Every named individual's types, inferred ones included.
    [[nodiscard]] Expected<Realization> realize(std::string_view turtle) const;
    /// A minimal subset of `candidates` that makes `background` inconsistent (QuickXplain:
    /// about k·log(n/k) runs for k culprits among n). Triples linked by blank nodes (an
    /// owl:Restriction, an rdf:List) move as one unit. Fails if `background` alone is
    /// inconsistent or Konclude fails.
    [[nodiscard]] Expected<Explanation> explainInconsistency(
        const std::vector<rdf::Triple>& background, const std::vector<rdf::Triple>& candidates,
        ExplainOptions options = {}) const;

private:
    struct Output {
        std::string console;  // Konclude's stdout and stderr
        std::string result;   // the -o file; empty when not asked for
    };
    Expected<Output> run(std::string_view command, std::string_view turtle, bool wantResult) const;
    Expected<bool> consistencyOf(const std::vector<rdf::Triple>& triples) const;

    KoncludeConfig config_;
};

/// Parses Konclude's realization output (OWL/XML ClassAssertion axioms on named
/// individuals); owl:Thing is left out. Exposed for tests.
[[nodiscard]] Expected<std::vector<ClassAssertion>> parseRealization(std::string_view owlXml);

/// The candidate triples grouped so that triples sharing a blank node are in one group.
/// Exposed for tests.
[[nodiscard]] std::vector<std::vector<rdf::Triple>> blankNodeGroups(
    const std::vector<rdf::Triple>& triples);

}  // namespace skillcell::kb::engine
