#pragma once
// The gripper skills: Grasp (GraspGripperSkillType) and Release (ReleaseGripperSkillType)
// of any Gripper, and MoveGripper (MoveGripperSkillType) of a ParallelGripper, each a thin
// SkillBehaviour, and the grip point they publish in their read-only parameters
// GripPointOffset and GripPointType, with what the gripper can hold (its rating) in
// MaxPayload and MaxGripWidth.
#include <kdl/frames.hpp>

#include "devices/gripper/parallel_gripper.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::devices {

enum class GripPointType : std::int32_t { Parallel = 0, Vacuum = 1, MultiFinger = 2 };

/// Adds Grasp and Release for `gripper` to `skills`, with the grip point's `offset` (from
/// the tool mounting plate) and `type` in their parameters.
ua::StatusCode addGripperSkills(skills::SkillServer& skills, Gripper& gripper,
                                const KDL::Frame& offset, GripPointType type,
                                std::string* error = nullptr);
/// The same, and MoveGripper.
ua::StatusCode addGripperSkills(skills::SkillServer& skills, ParallelGripper& gripper,
                                const KDL::Frame& offset, GripPointType type,
                                std::string* error = nullptr);

}  // namespace skillcell::devices
