#pragma once
// ComponentGraphs: what discovery says about the cell's components, as RDF for the knowledge
// base (process ontology, models/owl/process.ttl). One named graph per component (by its
// application URI) with the component and every skill it has offered: a skill that went
// away stays, with proc:available false, so that a process can still say which skill it
// lacks (the knowledge base forgets nothing because a gripper was unplugged).
//
// Each skill also carries the values its parameters had when the component was last read
// (proc:hasParameterValue), and a gripper skill its proc:gripType, proc:maxPayload (kg) and
// proc:maxGripWidth (m, 0: not limited by width), and a gripper's or tool changer's skill the
// robot it is on (proc:onRobot, its RobotUri). The values are plain data
// (ParameterValue): reading them from the component is kb/component_reader.hpp's job.
//
// Not thread-safe: feed it from one thread (the KB's discovery worker).
#include <map>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "kb/knowledge_base.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::kb {

inline constexpr const char* kProcessVocabulary = "http://skillcell.dev/ontology/process#";

/// The properties recorded here for each skill instance (beyond its type and parameter
/// values), which a process's proc:FactRequirement may ask about: proc:available,
/// proc:gripType, proc:maxGripWidth, proc:maxPayload, proc:onRobot, proc:skillName,
/// proc:skillNodeId.
[[nodiscard]] const std::vector<std::string>& recordedSkillProperties();

/// "urn:skillcell:component:<application URI, percent-encoded>".
[[nodiscard]] std::string componentIri(const std::string& applicationUri);
/// The graph that holds what discovery says about a component.
[[nodiscard]] std::string componentGraphIri(const std::string& applicationUri);
/// The IRI of a skill type as the NodeSet converter names it (kb/owl/node_iri.hpp): what a
/// process's proc:requiresSkillType holds.
[[nodiscard]] std::string skillTypeIri(const skills::SkillTypeRef& type);

/// A pose as a 3DFrame holds it: metres, and radians about the fixed X, Y, Z axes.
struct PoseValue {
    double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
    friend bool operator==(const PoseValue&, const PoseValue&) = default;
};

/// The value one variable of a skill's ParameterSet had when it was read.
struct ParameterValue {
    std::string name;  // its browse name (without namespace)
    /// Its DataType attribute (for an enumeration: the enumeration, not Int32).
    skills::GlobalNodeId dataType;
    /// A text (a String, or an enumeration's name), a number, or a pose (a 3DFrame).
    std::variant<std::string, double, PoseValue> value;
    friend bool operator==(const ParameterValue&, const ParameterValue&) = default;
};

/// The parameter values read from one component, by the skill's NodeId on its server.
using SkillParameterValues = std::map<ua::NodeId, std::vector<ParameterValue>>;

/// GripPointTypeEnumeration (GripperSkills model, i=3001): the data type of a gripper
/// skill's GripPointType, which says how its gripper holds an object (PARALLEL, VACUUM,
/// MULTIFINGER). The name of such a parameter's value, in lower case, is the skill's
/// proc:gripType ("parallel", "vacuum").
[[nodiscard]] skills::GlobalNodeId gripPointTypeEnumeration();

class ComponentGraphs {
public:
    /// Takes the skills `live` (what the detector offers now for `applicationUri`; empty
    /// when the component is gone) and their parameter values as just read from the
    /// component (`values`; empty when it could not be read), and returns the component's
    /// graph: every skill seen, each with proc:available. A live skill has the values given
    /// now, none if it has none here; a skill that went away keeps the values it had.
    [[nodiscard]] GraphData update(const std::string& applicationUri,
                                   const std::vector<skills::SkillInstance>& live,
                                   const SkillParameterValues& values = {});
    /// The namespace URIs of the skill types seen (the models the KB needs).
    [[nodiscard]] std::set<std::string> typeNamespaces() const;

private:
    struct Component {
        std::string endpointUrl;
        std::map<std::string, skills::SkillInstance> skills;        // by node id text
        std::map<std::string, std::vector<ParameterValue>> values;  // by node id text
    };
    std::map<std::string, Component> components_;
};

}  // namespace skillcell::kb
