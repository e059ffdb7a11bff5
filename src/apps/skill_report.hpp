#pragma once
// The lines a SkillDetector's changes and snapshots are printed as, the same for
// `skillcell detect` and for a component run with --detect, so that scripts parse one format.
//
// Text (fields separated by one space; a NodeId is printed last because it may contain one):
//   SKILL ADDED <type browse name> <component application URI> <endpoint> <node id>
//   SKILL REMOVED <type browse name> <component application URI> <endpoint> <reason> <node id>
//   snapshot: SNAPSHOT <n>, then n lines SKILL <type> <component> <endpoint> <node id>, END
// JSON (--json): one object per line, "event" is "added", "removed", "skill" (snapshot) or
//   "end" ({"event":"end","count":n}); a skill has type, typeId, types (the chain up to
//   SkillType, as "nsu=..." ids), typeNames, component, endpoint, nodeId, browsePath,
//   startTime, parameters ([{name, namespace, dataType, valueRank}]), and "reason" when
//   removed.
#include <ostream>
#include <vector>

#include "skills/skill_detector.hpp"

namespace skillcell::apps {

void printSkillEvent(std::ostream& out, const skills::SkillEvent& event, bool json);
/// Sorted by component, then node id; flushed.
void printSkillSnapshot(std::ostream& out, std::vector<skills::SkillInstance> instances, bool json);

}  // namespace skillcell::apps
