#pragma once
// Step binding: which live skill instances can run a process step, and the values of the
// step's parameters for one of them. Nothing here talks to a server: the instances come
// from the SkillDetector, with the parameters (names and data types) it browsed.
//
// A skill instance suits a step when its type chain holds the step's skill type (any subtype
// counts) and its ParameterSet declares every parameter the step gives. A derived value takes
// the form the skill's parameter declares: a 3DFrame from a resource's target pose or pose,
// a String from an object's id or a resource's application URI.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "kb/expected.hpp"
#include "mes/process_description.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::mes {

/// A skill instance, as (component URI, node id text).
using SkillKey = std::pair<std::string, std::string>;
[[nodiscard]] SkillKey keyOf(const skills::SkillInstance& skill);

/// A skill instance in one life of its component (its StartTime): what the MES remembers it
/// tried for a step. A component that restarted is a new life and may take the step again;
/// what its former life left, the next run settles (docs/mes.md, "Settling").
struct TriedKey {
    SkillKey skill;
    std::int64_t life = 0;  // the component's StartTime, ticks
    // NOLINTNEXTLINE(modernize-use-nullptr): the check misreads std::pair's synthesised <=>
    friend auto operator<=>(const TriedKey&, const TriedKey&) = default;
};
[[nodiscard]] TriedKey triedKeyOf(const skills::SkillInstance& skill);

/// "Skills/Grasp of urn:...": how messages name a skill instance.
[[nodiscard]] std::string where(const skills::SkillInstance& skill);

/// Whether `skill` is of the type `typeIri` or a subtype of it (its browsed type chain).
[[nodiscard]] bool isOfType(const skills::SkillInstance& skill, const std::string& typeIri);

/// Why `skill` cannot run `step`; empty when it can.
[[nodiscard]] std::string unsuitability(const ProcessStep& step,
                                        const skills::SkillInstance& skill);

/// The instances among `live` that suit `step`, leaving out `excluded`; in a stable order
/// (component URI, then browse path) so that runs are reproducible. Pointers into `live`:
/// a MES with many orders looks through every instance at each step, and keeps one.
[[nodiscard]] std::vector<const skills::SkillInstance*> candidates(
    const ProcessStep& step, const std::vector<skills::SkillInstance>& live,
    const std::set<TriedKey>& excluded);

/// The values to write before `skill` runs `step`. `cellMatches`: for each of the step's
/// requirements on the cell, the instance that meets it (skill_facts.hpp), whose endpoint a
/// RequirementEndpoint parameter takes. BadInput when a value cannot take the form the
/// parameter declares (a pose for a String, nothing to derive a 3DFrame from, no instance
/// for an endpoint).
[[nodiscard]] kb::Expected<std::map<std::string, ua::Variant>> parameterValues(
    const ProcessStep& step, const skills::SkillInstance& skill,
    const std::vector<std::optional<skills::SkillInstance>>& cellMatches = {});

}  // namespace skillcell::mes
