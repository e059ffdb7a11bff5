#pragma once
// Planning for placing a terminal block on a DIN rail: from the block's box and pose, the
// mounted tool's grip point, the rail and the position along it, the flange poses of one
// pick and placement. Pure geometry, like grasp_planner.hpp, so a placement is checked and
// refused before anything moves.
//
// The block is gripped from the top and held so through the placement: the grip point's z
// points down the block's height (-z of the block), its y along the block's width (x), so
// parallel fingers close across the block's narrow side, and its x along the block's depth.
// A parallel grip point sits at the block's centre, a vacuum one on its top face.
//
// The poses, in the order they are visited:
//   approach, grasp, retreat   above the block, on it, lifted off its tray;
//   hook-approach              above the hooked pose, along the rail's face normal;
//   hook                       the block tilted by kHookTilt, its upper foot on the edge;
//   rotate-down (several)      the block rotated about the edge in equal steps to flat,
//                              where the spring foot snaps;
//   rail-retreat               after the release, the fingers lifted off along the normal.
// The rotation is split so that a straight-line move between two poses keeps the foot
// within the world's contact tolerance of the edge (the flange sweeps an arc).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

#include "devices/gripper/gripper_skills.hpp"
#include "devices/pickplace/grasp_planner.hpp"
#include "devices/world/din_rail.hpp"

namespace skillcell::devices::pickplace {

/// Rotation steps from kHookTilt to flat: 5 degrees each.
inline constexpr int kRotateDownSteps = 3;

struct RailPlacementRequest {
    BoxSize size;                // the block's box: width, depth, height (m)
    KDL::Frame blockPose;        // where it stands now
    KDL::Frame gripPointOffset;  // the grip point relative to the flange
    GripPointType type = GripPointType::Parallel;
    DinRail rail;
    double position = 0;  // the block's centre along the rail (m)
    double approachDistance = kDefaultApproachDistance;
};

struct RailPlacementPlan {
    KDL::Frame approach, grasp, retreat, hookApproach, hook;
    std::vector<KDL::Frame> rotateDown;  // the last one lies flat
    KDL::Frame railRetreat;
    double width = 0;  // parallel: the block's width between the fingers
};

/// The plan, or nullopt with the reason in `why`: an edge that is not positive, a block not
/// standing upright (beyond kMaxTopFaceTilt), a position whose block would not lie wholly on
/// the rail, a grip point type other than Parallel or Vacuum, non-finite input.
[[nodiscard]] std::optional<RailPlacementPlan> planRailPlacement(const RailPlacementRequest& r,
                                                                 std::string* why = nullptr);

/// Where the next block goes: side by side after the block that ends furthest along the
/// rail, or at the rail's start when it is empty. `mounted` holds each block's centre and
/// width. Nullopt when the block would not fit before the rail's end.
[[nodiscard]] std::optional<double> nextFreePosition(
    const DinRail& rail, double width, const std::vector<std::pair<double, double>>& mounted);

}  // namespace skillcell::devices::pickplace
