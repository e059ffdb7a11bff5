#include "devices/pickplace/fuse_planner.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "devices/common/frame.hpp"
#include "devices/pickplace/plan_refusal.hpp"

namespace skillcell::devices::pickplace {
namespace {

/// The grip point in the fuse's frame: z down its height, y across its thickness (the
/// fingers close along y), on the body a quarter of its height above the centre.
KDL::Frame gripInFuse(const BoxSize& size) {
    const KDL::Rotation down(KDL::Vector(-1, 0, 0), KDL::Vector(0, 1, 0), KDL::Vector(0, 0, -1));
    return {down, KDL::Vector(0, 0, size.z / 4)};
}

double angleBetween(const KDL::Rotation& a, const KDL::Rotation& b) {
    KDL::Vector axis;
    return (a.Inverse() * b).GetRotAngle(axis);
}

}  // namespace

std::optional<FuseInsertionPlan> planFuseInsertion(const FuseInsertionRequest& r,
                                                   std::string* why) {
    if (r.type != GripPointType::Parallel) {
        return refuse(why,
                      "a fuse is gripped by parallel fingers across its thickness; the "
                      "mounted tool's grip point is not parallel");
    }
    for (double edge : {r.size.x, r.size.y, r.size.z, r.slotDepth}) {
        if (!std::isfinite(edge) || edge <= 0) {
            return refuse(why, fmt::format("the fuse's edges ({} x {} x {} m) and the slot's "
                                           "depth ({} m) must be positive",
                                           r.size.x, r.size.y, r.size.z, r.slotDepth));
        }
    }
    if (!isFinite(r.fusePose) || !isFinite(r.gripPointOffset) || !isFinite(r.slotPose) ||
        !std::isfinite(r.approachDistance) || r.approachDistance < 0 ||
        !std::isfinite(r.maxOpening) || r.maxOpening < 0) {
        return refuse(why, "a pose, the approach distance or the opening is not finite");
    }
    if (r.maxOpening > 0 && r.size.y > r.maxOpening) {
        return refuse(why, fmt::format("the fuse is {:.1f} mm thick; the fingers open to {:.1f} mm",
                                       r.size.y * 1000, r.maxOpening * 1000));
    }
    const double up = r.fusePose.M.UnitZ().z();
    if (up < std::cos(kMaxTopFaceTilt)) {
        return refuse(why,
                      fmt::format("the fuse is tilted by {:.1f} degrees; it must stand blades "
                                  "down (within {:.0f})",
                                  std::acos(std::clamp(up, -1.0, 1.0)) * 180 / std::numbers::pi,
                                  kMaxTopFaceTilt * 180 / std::numbers::pi));
    }

    const KDL::Frame toFlange = gripInFuse(r.size) * r.gripPointOffset.Inverse();
    const double d = r.approachDistance;
    FuseInsertionPlan plan;
    plan.thickness = r.size.y;
    plan.grasp = r.fusePose * toFlange;
    plan.approach = KDL::Frame(plan.grasp.M, plan.grasp.p + KDL::Vector(0, 0, d));
    plan.retreat = plan.approach;

    // Seated as the drawing says, either way round; the one nearer the grasp's orientation.
    FuseSlot drawn;
    drawn.pose = r.slotPose;
    drawn.depth = r.slotDepth;
    const KDL::Frame seated = seatedPose(drawn, r.size);
    const KDL::Frame turned = seated * KDL::Frame(KDL::Rotation::RotZ(std::numbers::pi));
    const KDL::Frame a = seated * toFlange;
    const KDL::Frame b = turned * toFlange;
    plan.insert = angleBetween(plan.grasp.M, a.M) <= angleBetween(plan.grasp.M, b.M) ? a : b;
    // Back along the slot's axis until the blade tips are `d` above the opening.
    const KDL::Vector axis = r.slotPose.M.UnitZ();
    plan.insertApproach = KDL::Frame(plan.insert.M, plan.insert.p + axis * (r.slotDepth + d));
    plan.preInsert = KDL::Frame(plan.insert.M,
                                plan.insert.p + axis * (r.slotDepth + std::min(d, kPreInsertGap)));
    plan.insertRetreat = plan.insertApproach;
    return plan;
}

}  // namespace skillcell::devices::pickplace
