#pragma once
// The world kept on disk while it runs, so that a world model restarted after a crash goes on
// from the cell as it was (a box in a gripper stays in it, a mounted tool stays mounted), as
// the physics it stands for does. A small JSON document, every frame as its position and
// rotation matrix (exact, not angles):
//
//   {"format": "skillcell world 1", "revision": 812,
//    "objects": {"boxA": {"size": [0.05, 0.05, 0.05], "pose": [x, y, z, r00, ..., r22],
//                         "kind": "box", "grasps": 1}},
//    "docks": {...}, "tools": {...}, "rails": {...}, "railMounts": {...},
//    "robots": {"ur5": {"base": [...], "pose": [...], "tool": "parallel", "held": "boxA",
//                       "toHeld": [...], ...}},
//    "fuseSlots": {...}, "seatedFuses": {...}}
//
// Written to a temporary file and renamed over the old one: a world killed at any moment
// leaves the last whole state, never half of one.
#include <filesystem>

#include "common/expected.hpp"
#include "devices/world/world.hpp"

namespace skillcell::devices {

/// The world saved in `file`; an Error naming the file and what is wrong in it.
[[nodiscard]] Expected<WorldContents> loadWorldFile(const std::filesystem::path& file);

/// Replaces `file` with `world`, atomically; an Error says why not.
[[nodiscard]] Status saveWorldFile(const std::filesystem::path& file, const World& world);

}  // namespace skillcell::devices
