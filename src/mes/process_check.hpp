#pragma once
// The process check: a process's mistakes found before any motion (`skillcell process
// check`, `process add`, and the MES when a run starts). It reads a process as written
// (Turtle) against the skill models (the OWL of the NodeSets: each skill type, its supertypes
// and the parameters of its ParameterSet) and lists every problem at once, each at its line
// in the file when there is one:
//  - a step without a skill type, or with one that no model defines or that is no SkillType;
//  - a parameter that the type's ParameterSet lacks, a parameter without a value, a value of
//    the wrong data type, a derivedFrom resource that lacks what the parameter needs;
//  - a broken firstStep/next chain, a cycle, a step that the chain never reaches;
//  - a dependsOn that points outside the process, or to a step that comes later;
//  - a requirement on a property that nothing records for a skill.
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"
#include "kb/store/sparql_store.hpp"
#include "mes/process_description.hpp"

namespace skillcell::mes {

/// A parameter of a skill type's ParameterSet.
struct ParameterModel {
    std::string name;         // its BrowseName
    std::string dataTypeIri;  // "http://opcfoundation.org/UA/i=18814" (3DFrame)
};

/// An ObjectType as the models describe it.
struct TypeModel {
    std::string iri;
    std::string name;                        // its BrowseName
    std::vector<std::string> supertypes;     // direct (rdfs:subClassOf)
    std::vector<ParameterModel> parameters;  // its own ParameterSet's
};

/// The skill models a process is checked against.
class SkillModels {
public:
    /// From the OWL of converted NodeSets (what the KB holds).
    [[nodiscard]] static SkillModels fromTriples(const std::vector<kb::rdf::Triple>& triples);
    /// skillcell's own: the NodeSets compiled in, converted as the KB converts them.
    [[nodiscard]] static kb::Expected<SkillModels> embedded();
    /// The CONSTRUCT query for what fromTriples reads, as fromStore asks it (for a KB
    /// reached another way: its OPC UA Query method).
    [[nodiscard]] static std::string query();
    /// Those a knowledge base holds (every model it loaded, companions included).
    [[nodiscard]] static kb::Expected<SkillModels> fromStore(kb::SparqlStore& store);

    [[nodiscard]] const TypeModel* find(const std::string& iri) const;
    /// True for SkillType and its subtypes.
    [[nodiscard]] bool isSkillType(const std::string& iri) const;
    /// Its parameters and those it inherits; a subtype's parameter hides a supertype's of the
    /// same name.
    [[nodiscard]] std::vector<ParameterModel> parameters(const std::string& iri) const;
    /// The skill type whose name is nearest `iri`'s last segment (a misspelling), or empty.
    [[nodiscard]] std::string nearestSkillType(const std::string& iri) const;
    [[nodiscard]] std::size_t size() const { return types_.size(); }

private:
    std::map<std::string, TypeModel> types_;
};

/// Lines of a Turtle text, to say where a resource or a value is written.
class TurtleLocator {
public:
    TurtleLocator() = default;  // no text: every line is 0
    explicit TurtleLocator(std::string_view text);
    /// The line where `iri` starts a statement (it is a subject), else where it first
    /// appears; 0 when it does not.
    [[nodiscard]] int subjectLine(const std::string& iri) const;
    /// The first line at or after `from` where `iri` appears, written in full or with a
    /// prefix; 0 when none.
    [[nodiscard]] int iriLine(const std::string& iri, int from) const;
    /// The first line at or after `from` that contains `text`; 0 when none.
    [[nodiscard]] int textLine(std::string_view text, int from) const;

private:
    [[nodiscard]] std::vector<std::string> spellings(const std::string& iri) const;
    std::vector<std::string> lines_;
    std::vector<std::pair<std::string, std::string>> prefixes_;  // name, namespace IRI
};

struct ProcessProblem {
    int line = 0;  // 0: no line (a process read from the KB)
    std::string message;
};

/// Every problem of every proc:Process in `triples`, sorted by line; empty for a clean
/// process. `where` gives the lines. No process at all is a problem too.
[[nodiscard]] std::vector<ProcessProblem> checkProcesses(
    const std::vector<kb::rdf::Triple>& triples, const SkillModels& models,
    const TurtleLocator& where = {});

/// The CONSTRUCT query for the resources a knowledge base holds that processes derive values
/// from: docks, tools and objects, with their poses (a cell's scene). Their triples are the
/// `context` of checkProcessText for a process headed for that KB.
[[nodiscard]] std::string resourceQuery();

/// Reads a process file's Turtle and checks it; a syntax error is one problem, at its line.
/// The triples read go to `triples` when given.
/// `context` describes what the process refers to without describing it (a cell's scene:
/// its docks and tools).
[[nodiscard]] std::vector<ProcessProblem> checkProcessText(
    std::string_view text, const SkillModels& models,
    std::vector<kb::rdf::Triple>* triples = nullptr,
    const std::vector<kb::rdf::Triple>& context = {});

/// Reads the process `processIri` from a knowledge base and checks it against the skill
/// models the KB holds: BadInput listing every problem (nothing has moved yet), or its
/// description. Unavailable when the KB cannot be reached.
[[nodiscard]] kb::Expected<ProcessDescription> readCheckedProcess(kb::SparqlStore& store,
                                                                  const std::string& processIri);

/// The IRIs of the properties the knowledge base records for a skill instance, which a
/// proc:FactRequirement may ask about.
[[nodiscard]] const std::vector<std::string>& recordedSkillProperties();

}  // namespace skillcell::mes
