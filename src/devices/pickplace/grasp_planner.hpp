#pragma once
// Grasp planning for the pick-and-place composite skill: from an object's box and pose, the
// mounted tool's grip point and the place position, the six flange poses of one pick and
// place. Pure geometry (no I/O, no state, no exceptions), so a plan can be checked and
// refused before anything moves.
//
// Conventions (every pose in the cell's base frame):
// - The move skill moves the flange, so the plan holds flange poses:
//   flange = gripPoint * gripPointOffset.Inverse().
// - Top face: the box face whose outward normal is closest to base +z. It must be within
//   kMaxTopFaceTilt of +z, or the box is refused (it is neither resting on a face nor
//   reachable from above).
// - Vacuum: the grip point sits at the top face's centre with z along the face's inward
//   normal (down, into the box) and x along the object's x axis (its y axis when x is the
//   box's up axis); both lie in the face, so no projection is needed. Approach and retreat
//   are the grasp moved back along the grip point's -z (straight up off the face).
// - Parallel (the fingers close along the grip point's y): the grip point sits at the box's
//   centre with y along the narrower of the two horizontal box axes (the fingers close
//   across the narrow width), z along the wider one and x along the top face's outward
//   normal (up), so x = y x z is right-handed. z points into the box from the side facing
//   base -x (from the side facing base -y when the wide axis is perpendicular to base x).
//   The axes follow the box, so on a slightly tilted box they tilt with it and the fingers
//   still meet its faces squarely. Approach is the grasp moved back along the grip point's
//   -z (horizontally, from the side); retreat lifts the grasp by the approach distance
//   along base +z, taking the object off the surface it stands on.
// - Place: the object keeps its pose relative to the grip point while held; the place pose
//   puts the object's centre and orientation at the place position. Place approach and
//   place retreat are the same pose: for vacuum the place pose moved back along the grip
//   point's -z, for parallel the place pose raised along base +z (lowering the object onto
//   the surface, lifting the opened fingers off it).
#include <kdl/frames.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "devices/gripper/gripper_skills.hpp"
#include "devices/world/world.hpp"

namespace skillcell::devices::pickplace {

inline constexpr double kDefaultApproachDistance = 0.05;                  // m
inline constexpr double kMaxTopFaceTilt = 10.0 * std::numbers::pi / 180;  // rad
/// How far an input rotation may be from orthonormal with determinant +1.
inline constexpr double kRotationTolerance = 1e-6;

struct GraspRequest {
    BoxSize size;                // the object's box, m
    KDL::Frame objectPose;       // the box's centre and orientation
    KDL::Frame gripPointOffset;  // the grip point relative to the flange
    GripPointType type = GripPointType::Vacuum;
    KDL::Frame placePosition;  // where the object's centre and orientation should end up
    double approachDistance = kDefaultApproachDistance;  // m, >= 0
    double maxOpening = 0;  // parallel: widest finger opening, m; 0 = unlimited
};

/// Flange poses, in the order they are visited.
struct GraspPlan {
    KDL::Frame approach, grasp, retreat, placeApproach, place, placeRetreat;
    /// Parallel: the box's extent between the fingers (open wider than this before the
    /// approach); 0 for vacuum.
    double width = 0;
};

/// The plan, or nullopt with the reason in `why` when the object cannot be picked: an edge
/// that is not positive, a parallel grasp wider than `maxOpening`, a box tilted beyond
/// kMaxTopFaceTilt, a grip point type other than Vacuum or Parallel, a negative approach
/// distance or opening, a non-finite pose or a rotation that is not proper.
[[nodiscard]] std::optional<GraspPlan> planGrasp(const GraspRequest& request,
                                                 std::string* why = nullptr);

/// The rest of a pick and place whose object is held already (its run was cut short): the
/// object stays as it is held, wherever the grasp put it. `grasp` is the flange where it is,
/// `retreat` lifts it by the approach distance along base +z; the place poses are planGrasp's,
/// for the held object. (approach = grasp: there is nothing to approach.)
[[nodiscard]] GraspPlan planCarryOn(const KDL::Frame& flange, const GraspRequest& request);

/// The plan's poses named "approach", "grasp", "retreat", "place-approach", "place",
/// "place-retreat", in that order, for publishing the current step.
[[nodiscard]] std::vector<std::pair<std::string, KDL::Frame>> steps(const GraspPlan& plan);

}  // namespace skillcell::devices::pickplace
