#pragma once
// Feasibility: whether the cell, as it is now, can run a process, checked when a run starts
// and before its first motion (the paper's MES finds out at the step that cannot run, after
// the robot has moved). For every step:
//  - some live skill of the step's type (or a subtype) has every parameter the step sets;
//  - each requirement on the cell (a GraspGripperSkillType with gripType "vacuum") is met by
//    a live skill the knowledge base says has the fact, or is brought by an earlier step: a
//    step whose parameter derives from a resource that holds a tool with that fact (a
//    ChangeTool from the dock where the vacuum gripper is stored mounts it, and its adapter
//    appears then).
// It says nothing about what only running can tell (a dock that holds another gripper than
// the process says): the steps still check their skills when they run.
#include <string>
#include <vector>

#include "mes/process_description.hpp"
#include "mes/skill_facts.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::mes {

/// Every reason why the cell cannot run `process`, one per unmet need, each naming its step;
/// empty when it can. `facts` holds the KB's values of every property the requirements ask
/// about; without a KB (`facts` null) requirements are not checked here.
[[nodiscard]] std::vector<std::string> infeasibility(const ProcessDescription& process,
                                                     const std::vector<skills::SkillInstance>& live,
                                                     const SkillFacts* facts);

/// Every property a process's requirements ask about (sorted, each once).
[[nodiscard]] std::vector<std::string> requiredProperties(const ProcessDescription& process);

}  // namespace skillcell::mes
