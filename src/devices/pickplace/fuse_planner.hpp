#pragma once
// Planning for inserting a blade fuse into a fuse box's slot: from the fuse's box and pose,
// the mounted tool's grip point and the slot as drawn (fuse_slot.hpp), the flange poses of
// one pick and insertion. Pure geometry, like grasp_planner.hpp, so an insertion is checked
// and refused before anything moves.
//
// The fuse stands blades down in its tray and is gripped from the top by parallel fingers
// closing across its thickness (its y), on its body above the blades (a quarter of its
// height above its centre). It is inserted square with the slot along the slot's axis: of
// the two ways round (the fuse is symmetric), the one that turns the wrist less.
//
// The poses, in the order they are visited:
//   approach, grasp, retreat   above the fuse, on it, lifted out of the tray;
//   insert-approach            the blade tips `approachDistance` above the slot's opening;
//   pre-insert                 the blade tips kPreInsertGap above it, in a straight line;
//   insert                     the fuse seated at the slot's depth: the move there is the
//                              force-limited one, which stops short where the fuse meets
//                              more than the limit;
//   insert-retreat             after the release, the fingers back along the slot's axis.
#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "devices/gripper/gripper_skills.hpp"
#include "devices/pickplace/grasp_planner.hpp"
#include "devices/world/fuse_slot.hpp"

namespace skillcell::devices::pickplace {

/// Where the force-limited insertion begins: the blade tips this far above the opening.
inline constexpr double kPreInsertGap = 0.003;  // m

struct FuseInsertionRequest {
    BoxSize size;                // the fuse: width, thickness, height (m), blades down its -z
    KDL::Frame fusePose;         // where it stands now
    KDL::Frame gripPointOffset;  // the grip point relative to the flange
    GripPointType type = GripPointType::Parallel;
    double maxOpening = 0;  // the fingers' widest opening (m); 0: not limited
    KDL::Frame slotPose;    // the slot's opening as drawn, z out of the box
    double slotDepth = 0;   // m the blades go in when seated
    double approachDistance = kDefaultApproachDistance;
};

struct FuseInsertionPlan {
    KDL::Frame approach, grasp, retreat, insertApproach, preInsert, insert, insertRetreat;
    double thickness = 0;  // between the fingers
};

/// The plan, or nullopt with the reason in `why`: a grip point that is not parallel, an
/// edge or depth that is not positive, a fuse thicker than the fingers open, a fuse not
/// standing upright (beyond kMaxTopFaceTilt), non-finite input.
[[nodiscard]] std::optional<FuseInsertionPlan> planFuseInsertion(const FuseInsertionRequest& r,
                                                                 std::string* why = nullptr);

}  // namespace skillcell::devices::pickplace
