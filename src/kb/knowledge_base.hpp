#pragma once
// KnowledgeBase: the cell's models in a SPARQL store, kept consistent by a reasoner.
//
// Models arrive as named graphs (an ontology per NodeSet, the process models, a component's
// instance data). A load replaces its graphs only if the knowledge base stays consistent:
// the union of what is loaded and what arrives is checked by the reasoner first; an
// inconsistent load is refused with the statements that conflict (a minimal set, found by
// the reasoner), and the store is not touched. A load that passes is written in one SPARQL
// update (all or nothing), together with the reasoner's inferred types, which live in their
// own graph (kInferredGraph) so that queries can take them or leave them.
//
// Models and instances. What a component says about itself (kb/component_graph) is an
// instance graph, written by record(): it is checked against the models alone (every graph
// that is not an instance graph), so that recording a component costs in proportion to its
// own graph and the models, not to the number of components recorded before it. Instance
// graphs are assumed independent of each other (each describes its own individuals).
//
// Threading: every method may be called from any thread. Loads and updates are serialized
// (a load's check must see the store it writes to); a recording reasons without any lock
// and takes the write lock only to write; queries never take a lock.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "kb/engine/konclude_reasoner.hpp"
#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"
#include "kb/store/sparql_store.hpp"

namespace skillcell::kb {

inline constexpr const char* kRegistryGraph = "urn:skillcell:kb:graphs";
inline constexpr const char* kInferredGraph = "urn:skillcell:kb:inferred";
/// Graphs a load writes before it moves them in (cleared by the next load).
inline constexpr const char* kStagingGraphPrefix = "urn:skillcell:kb:staging:";
inline constexpr const char* kKbVocabulary = "http://skillcell.dev/ontology/kb#";
/// The graph of a process file (`kb --process`, `process add`): this, then the file's name
/// without .ttl; adding the file again replaces it.
inline constexpr const char* kProcessGraphPrefix = "http://skillcell.dev/processes/";

/// A named graph and its content.
struct GraphData {
    std::string iri;
    std::vector<rdf::Triple> triples;
};

class KnowledgeBase {
public:
    /// `reasoner` null: loads are not checked and nothing is inferred (for stores that are
    /// checked elsewhere, and for benchmarks of the store alone).
    KnowledgeBase(SparqlStore& store, const engine::KoncludeReasoner* reasoner)
        : store_(store), reasoner_(reasoner) {}

    /// Graphs one load may replace: its final request has a few operations per graph, and
    /// Virtuoso refuses requests of too many (SQ200).
    static constexpr std::size_t kMaxGraphsPerLoad = 64;

    /// Replaces each graph of `graphs` (as one transaction) if the result is consistent.
    /// More than kMaxGraphsPerLoad graphs: BadInput.
    [[nodiscard]] Status load(const std::vector<GraphData>& graphs);
    /// Loads `parts` (each one or more graphs) in as few loads as it can: all in one when
    /// they fit (kMaxGraphsPerLoad graphs, none twice), since the reasoner's check costs about
    /// as much for one new graph as for fifty; when that load is refused, or cannot be one,
    /// each part alone, so that the part at fault is named and the others load all the same.
    /// One status per part. A store that fails (not a refusal) fails every part at once.
    [[nodiscard]] std::vector<Status> loadParts(const std::vector<std::vector<GraphData>>& parts);
    /// Records instance graphs (what components say about themselves): each is checked
    /// against the models alone, and its individuals' inferred types replace those of its
    /// previous version. The reasoner runs without the write lock, over the models and these
    /// graphs only; a load or update that changes the models meanwhile makes the recording
    /// reason again. Everything accepted is written in one update. One status per graph: a
    /// graph inconsistent with the models is refused (Refused, naming the statements that
    /// conflict), the others are recorded. More than kMaxGraphsPerLoad graphs: BadInput.
    [[nodiscard]] std::vector<Status> record(const std::vector<GraphData>& instances);
    /// load() of one graph given as Turtle; `baseIri` resolves relative IRIs (default: the
    /// graph's IRI).
    [[nodiscard]] Status loadTurtle(const std::string& graphIri, std::string_view turtle);
    /// Loads the project's ontologies: the core OPC UA ontology, the process ontology and
    /// every embedded NodeSet converted (graph = ontology IRI); and the demo process if asked.
    [[nodiscard]] Status loadBuiltInModels(bool withDemoProcess);
    /// The graphs loadBuiltInModels() loads, for a caller that loads them with others.
    [[nodiscard]] static Expected<std::vector<GraphData>> builtInModels(bool withDemoProcess);

    /// The graphs loaded (not the inferred one), sorted.
    [[nodiscard]] Expected<std::vector<std::string>> graphs();
    /// The content of one graph.
    [[nodiscard]] Expected<std::vector<rdf::Triple>> graphContent(const std::string& graphIri);

    [[nodiscard]] Expected<SparqlResponse> query(const std::string& sparql,
                                                 const std::string& accept);
    /// A SPARQL 1.1 Update, serialized with loads. Not checked by the reasoner: it is the
    /// operator's tool (and the KB's own, for facts such as a component's availability).
    [[nodiscard]] Status update(const std::string& sparqlUpdate);

private:
    /// The models (every graph but the instance graphs) as of one generation, shared by the
    /// recordings that reason over them.
    struct Models {
        std::uint64_t generation = 0;
        std::vector<rdf::Triple> triples;
        std::string text;                // N-Triples, for the reasoner
        std::set<std::string> subjects;  // IRIs the models say something about
    };
    Expected<std::vector<rdf::Triple>> everythingBut(const std::vector<std::string>& graphIris);
    Expected<std::shared_ptr<const Models>> models();
    /// The types inferred for the individuals of `instance` (its IRI subjects that the models
    /// do not describe), less those it states.
    static std::set<rdf::Triple> inferredFor(const GraphData& instance, const Models& models,
                                             const engine::Realization& realization);
    Status refusal(const std::vector<std::string>& names, const std::vector<rdf::Triple>& rest,
                   const std::vector<rdf::Triple>& incoming) const;
    /// Writes `graphs` (registered as instance graphs or as models) and the change to the
    /// inferred graph, as one transaction where it fits one request. Under writeMutex_.
    Status commit(const std::vector<GraphData>& graphs, bool instances,
                  const std::vector<rdf::Triple>& added, const std::vector<rdf::Triple>& removed);
    Status knowInferred();
    Status stage(const GraphData& graph, std::size_t number);
    static std::string insertText(const std::string& graphIri,
                                  const std::vector<rdf::Triple>& triples, std::size_t number);

    /// Triples per update request: Virtuoso compiles a request to SQL, and refuses one of
    /// more than 10000 lines (a few thousand triples).
    static constexpr std::size_t kTriplesPerRequest = 1000;

    SparqlStore& store_;
    const engine::KoncludeReasoner* reasoner_;
    std::mutex writeMutex_;
    // The inferred graph as last written (the KB is its only writer), so that a load
    // writes what changed; read from the store when not known.
    std::set<rdf::Triple> inferred_;
    bool inferredKnown_ = false;
    // Bumped (under writeMutex_) by every load of models and every update: a recording that
    // reasoned over an older generation reasons again.
    std::atomic<std::uint64_t> modelsGeneration_{0};
    std::mutex modelsMutex_;  // guards models_
    std::shared_ptr<const Models> models_;
};

/// "<iri>" with the characters SPARQL forbids in an IRI reference refused: an Error names
/// the IRI. For building queries from names that come from outside.
[[nodiscard]] Expected<std::string> sparqlIri(const std::string& iri);

}  // namespace skillcell::kb
