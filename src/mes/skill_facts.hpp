#pragma once
// SkillFacts: what the knowledge base says of the cell's skill instances beyond their type (a
// grasp skill's proc:gripType, ...), and whether they meet a step's requirements. The paper
// (section VII-C) selects skills by suitability, physical properties and availability; here
// suitability is the type and the facts, availability the SkillDetector's map.
//
// Facts come from the KB, liveness from the detector, never the other way round: the KB
// records a component about a second after discovery and keeps a departed one's facts, so
// an instance counts only when the detector lists it *and* the KB has the fact. Until the KB
// has recorded a new instance it has no facts, and the MES asks again (process_executor).
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"
#include "kb/store/sparql_store.hpp"
#include "mes/process_description.hpp"
#include "mes/step_binding.hpp"

namespace skillcell::mes {

class SkillFacts {
public:
    void add(const SkillKey& skill, const std::string& propertyIri, std::string value);
    /// Whether the KB says `skill` has the requirement's property with its value.
    [[nodiscard]] bool has(const SkillKey& skill, const FactRequirement& requirement) const;
    /// The values the KB gives `skill` for `propertyIri` (none when it has not recorded it).
    [[nodiscard]] std::vector<std::string> values(const SkillKey& skill,
                                                  const std::string& propertyIri) const;
    /// Whether the KB has recorded `skill` (it gives it proc:available, which factQuery always
    /// asks for): until then it says nothing of its reach or robot either.
    [[nodiscard]] bool recorded(const SkillKey& skill) const;
    /// A skill of the component `componentUri` that the KB gives `propertyIri` (the first by
    /// node id), if any.
    [[nodiscard]] std::optional<SkillKey> skillWith(const std::string& componentUri,
                                                    const std::string& propertyIri) const;

private:
    std::map<SkillKey, std::map<std::string, std::vector<std::string>>> values_;
};

/// The properties `step`'s requirements ask about (sorted, each once); with the gripper's
/// rating (proc:maxPayload, proc:maxGripWidth) when the step moves an object of known mass or
/// size, a manipulator's reach (proc:reach, proc:reachCentreX/Y/Z) when it names positions
/// (stepTargets), and the robot a skill is on (proc:onRobot) when it does either; and always
/// proc:available, which tells a recorded skill from one the KB has not recorded yet.
[[nodiscard]] std::vector<std::string> requiredProperties(const ProcessStep& step);

/// The CONSTRUCT query for every skill instance's values of `propertyIris` and of
/// proc:available (what SkillFacts::recorded reads), with the component's application URI and
/// the skill's node id (what SkillKey holds).
[[nodiscard]] kb::Expected<std::string> factQuery(const std::vector<std::string>& propertyIris);
/// The facts in factQuery's answer.
[[nodiscard]] SkillFacts parseFacts(const std::vector<kb::rdf::Triple>& triples);
/// Asks the KB (blocking). Unavailable when it cannot be reached.
[[nodiscard]] kb::Expected<SkillFacts> readFacts(kb::SparqlStore& store,
                                                 const std::vector<std::string>& propertyIris);

/// Why `skill` lacks `step`'s own requirements (those without a skill type), does not reach
/// the positions it names (cannotReach), or is on another robot than `robot` (the one the
/// step's other skills act through; empty: any); empty when it has them all.
[[nodiscard]] std::string unmetSkillRequirements(const ProcessStep& step,
                                                 const skills::SkillInstance& skill,
                                                 const SkillFacts& facts,
                                                 const std::string& robot = {});

/// How the cell meets `step`'s requirements on the cell (those with a skill type).
/// The object `step` moves: the first parameter derived from an object (proc:objectId) whose
/// mass or size the knowledge base gives; nullptr when there is none.
[[nodiscard]] const DerivationSource* movedObject(const ProcessStep& step);
/// Why the gripper skill `skill` cannot hold `object`, by its rating in the KB (proc:maxPayload
/// against the object's mass, proc:maxGripWidth against its narrower horizontal side); empty
/// when it can, or when the KB gives no rating.
[[nodiscard]] std::string cannotHold(const DerivationSource& object,
                                     const skills::SkillInstance& skill, const SkillFacts& facts);

/// A position a step sends a manipulator to, in the cell's frame, and what it is.
struct StepTarget {
    std::string what;  // "boxA", "boxA's target", "dockP", "TargetPosition"
    double x = 0, y = 0, z = 0;
};
/// The positions `step` names: its literal poses (not ToolFrame, which is relative to the
/// flange), an object's pose and target where a parameter derives from the object, a dock's
/// pose where one derives from the dock. Each once.
[[nodiscard]] std::vector<StepTarget> stepTargets(const ProcessStep& step);
/// The robot `skill` acts through, by its application URI: its own component when the KB
/// gives it a reach (a manipulator's move skill), else the robot the KB says it is on
/// (proc:onRobot: a tool changer's skill, a gripper's); empty when neither.
[[nodiscard]] std::string robotOf(const skills::SkillInstance& skill, const SkillFacts& facts);

/// Why the manipulator behind `skill` cannot reach every target of `step`, by its reach in the
/// KB (proc:reach from proc:reachCentreX/Y/Z, a move skill's Reach and ReachCentre; for a
/// skill on a robot, that robot's); empty when it can, or when the KB gives it no reach (not
/// a manipulator, or not published). A skill (or its robot) that the KB has not recorded yet
/// cannot be told to reach: that is a reason too, until it is recorded. A
/// sphere: a target inside may still be refused by the manipulator's own planner (a tool's
/// length, its wrist), which then fails the step as before.
[[nodiscard]] std::string cannotReach(const ProcessStep& step, const skills::SkillInstance& skill,
                                      const SkillFacts& facts);

struct CellMatch {
    /// Parallel to step.requirements: for a requirement on the cell, the live instance that
    /// meets it, can hold the object the step moves and reaches the positions it names (the
    /// first by component URI and browse path), all of them on one robot (a pick's gripper on
    /// the robot that moves it); nothing for one on the skill, or one unmet.
    std::vector<std::optional<skills::SkillInstance>> byRequirement;
    /// The robot the matches act through (robotOf); empty when none does.
    std::string robot;
    /// Why some are unmet, naming each and what the live instances of its type have
    /// instead; empty when all are met.
    std::string unmet;
    /// For the choice's reason: each met requirement, the instance that meets it, and why
    /// those before it did not ("an available CartesianLinearMoveSkillType: Skills/... of
    /// urn:b (passed over: Skills/... of urn:a: boxC at ... is 1.6 m from its reach centre,
    /// ...)").
    std::string chosen;
};
[[nodiscard]] CellMatch matchCellRequirements(const ProcessStep& step,
                                              const std::vector<skills::SkillInstance>& live,
                                              const SkillFacts& facts);

}  // namespace skillcell::mes
