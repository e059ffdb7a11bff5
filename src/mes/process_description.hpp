#pragma once
// ProcessDescription: a process as the knowledge base describes it (models/owl/process.ttl),
// read into values the MES runs: the steps in order, each with the skill type it requires and
// its parameters, given or to be derived from facts (a dock's pose, an object's id and target).
//
// readProcess() asks the KB one CONSTRUCT query (one response keeps the blank nodes of
// parameters, poses and requirements consistent) and checks what it gets: a process without
// steps, a broken proc:next chain, a step without a skill type, a dependency on a later step,
// a parameter without a value, or a requirement without a property or value are errors that
// name the step and the parameter.
#include <array>
#include <chrono>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "devices/common/frame.hpp"
#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"
#include "kb/store/sparql_store.hpp"

namespace skillcell::mes {

inline constexpr const char* kProcessNs = "http://skillcell.dev/ontology/process#";
/// The most retries a step may ask for (proc:retries).
inline constexpr int kMaxRetries = 10;

/// The facts of a resource or product a parameter is derived from.
struct DerivationSource {
    std::string iri;
    std::optional<devices::Pose6> pose;         // proc:pose (a dock)
    std::optional<devices::Pose6> targetPose;   // proc:targetPose (where an object goes)
    std::string objectId;                       // proc:objectId
    std::string applicationUri;                 // proc:applicationUri
    std::string gripType;                       // proc:gripType
    std::optional<double> mass;                 // proc:mass (kg), of the object in the cell
    std::optional<std::array<double, 3>> size;  // proc:sizeX, Y, Z (m), likewise
    /// The literal facts of what it proc:holds (a dock's tool: its proc:gripType), by
    /// property IRI: what a step that takes the tool from there brings into the cell.
    std::vector<std::pair<std::string, std::string>> held;
    friend bool operator==(const DerivationSource&, const DerivationSource&) = default;
};

/// A fact the knowledge base must hold for a skill to suit a step (proc:requiresFact): the
/// skill instance has `propertyIri` with `value`. With a `skillTypeIri` it concerns the cell:
/// some available skill of that type (or a subtype) must have the fact; without a property,
/// any available one of that type will do.
struct FactRequirement {
    std::string propertyIri;   // empty: none (a requirement on the cell by type alone)
    std::string value;         // its lexical form; numbers compare by value
    std::string skillTypeIri;  // empty: the skill that runs the step
    friend bool operator==(const FactRequirement&, const FactRequirement&) = default;

    /// 'gripType "parallel"', or 'an available GraspGripperSkillType with gripType
    /// "parallel"': how messages name it.
    [[nodiscard]] std::string describe() const;
};

/// A parameter whose value is the endpoint URL of the skill that meets one of the step's
/// requirements on the cell (proc:endpointOf): the gripper a pick was checked against is the
/// one it uses.
struct RequirementEndpoint {
    std::size_t requirement = 0;  // its index in ProcessStep::requirements
    friend bool operator==(const RequirementEndpoint&, const RequirementEndpoint&) = default;
};

struct StepParameter {
    std::string name;  // the BrowseName in the skill's ParameterSet
    std::variant<std::string, double, devices::Pose6, DerivationSource, RequirementEndpoint> value;
    friend bool operator==(const StepParameter&, const StepParameter&) = default;
};

struct ProcessStep {
    std::string iri;
    int index = 0;  // position in the process, from 1 (proc:next order)
    std::string skillTypeIri;
    std::vector<StepParameter> parameters;      // by name
    std::vector<std::string> dependsOn;         // step IRIs, each earlier in the order
    std::vector<FactRequirement> requirements;  // in a stable order (RequirementEndpoint)
    /// How often the step runs again after its skill ended Halted (proc:retries).
    int retries = 0;
    friend bool operator==(const ProcessStep&, const ProcessStep&) = default;

    /// "step 2 (PickAndPlaceSkillType)": how messages name it.
    [[nodiscard]] std::string label() const;
};

/// The longest a process may ask its steps to wait for a skill (proc:skillWaitSeconds).
inline constexpr double kMaxSkillWaitSeconds = 3600;

struct ProcessDescription {
    std::string iri;
    std::vector<ProcessStep> steps;  // in execution order
    /// How long a step waits for a suitable skill to appear (proc:skillWaitSeconds); none:
    /// the MES's own setting.
    std::optional<std::chrono::milliseconds> skillWait;
};

/// The process `processIri` from triples (what readProcess parses; tests feed it directly).
[[nodiscard]] kb::Expected<ProcessDescription> parseProcess(
    const std::string& processIri, const std::vector<kb::rdf::Triple>& triples);

/// The SPARQL query readProcess sends.
[[nodiscard]] kb::Expected<std::string> processQuery(const std::string& processIri);

/// Runs a CONSTRUCT `query` on the KB and parses its answer (N-Triples). Unavailable when the
/// KB cannot be reached.
[[nodiscard]] kb::Expected<std::vector<kb::rdf::Triple>> constructTriples(kb::SparqlStore& store,
                                                                          const std::string& query);

/// Reads the process `processIri` from the KB. Unavailable when the KB cannot be reached;
/// BadInput when the IRI names no process or the description is incomplete.
[[nodiscard]] kb::Expected<ProcessDescription> readProcess(kb::SparqlStore& store,
                                                           const std::string& processIri);

/// The IRIs of every process the KB holds (rdf:type proc:Process), sorted.
[[nodiscard]] kb::Expected<std::vector<std::string>> processIris(kb::SparqlStore& store);

/// A number in a literal's lexical form ("0.85", "-2", "1e-3"); nothing when it is not one.
[[nodiscard]] std::optional<double> parseNumber(const std::string& text);

/// The last segment of an IRI ("ChangeToolSkillType"), for messages.
[[nodiscard]] std::string shortName(const std::string& iri);

}  // namespace skillcell::mes
