#pragma once
// The gripper skills of a parallel gripper: Grasp (GraspGripperSkillType), Release
// (ReleaseGripperSkillType) and MoveGripper (MoveGripperSkillType), each a thin
// SkillBehaviour over a ParallelGripper, and the grip point they publish in their
// read-only parameters GripPointOffset and GripPointType (PARALLEL).
#include <kdl/frames.hpp>

#include "devices/gripper/parallel_gripper.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::devices {

enum class GripPointType : std::int32_t { Parallel = 0, Vacuum = 1, MultiFinger = 2 };

/// Adds Grasp, Release and MoveGripper for `gripper` to `skills`, with the grip point's
/// `offset` (from the tool mounting plate) and `type` in their parameters.
ua::StatusCode addGripperSkills(skills::SkillServer& skills, ParallelGripper& gripper,
                                const KDL::Frame& offset, GripPointType type,
                                std::string* error = nullptr);

}  // namespace skillcell::devices
