#include "devices/pickplace/rail_planner.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "devices/common/frame.hpp"
#include "devices/pickplace/plan_refusal.hpp"

namespace skillcell::devices::pickplace {
namespace {

// The grip point in the block's frame: from the top, fingers across the width.
KDL::Frame gripInBlock(const BoxSize& size, GripPointType type) {
    const KDL::Rotation down(KDL::Vector(0, 1, 0), KDL::Vector(1, 0, 0), KDL::Vector(0, 0, -1));
    const double z = type == GripPointType::Vacuum ? size.z / 2 : 0.0;
    return {down, KDL::Vector(0, 0, z)};
}

KDL::Frame raised(const KDL::Frame& f, const KDL::Vector& by) {
    return {f.M, f.p + by};
}

}  // namespace

std::optional<RailPlacementPlan> planRailPlacement(const RailPlacementRequest& r,
                                                   std::string* why) {
    if (r.type != GripPointType::Parallel && r.type != GripPointType::Vacuum) {
        return refuse(why, "only vacuum and parallel grip points can place a terminal block");
    }
    for (double edge : {r.size.x, r.size.y, r.size.z}) {
        if (!std::isfinite(edge) || edge <= 0) {
            return refuse(why, fmt::format("every edge of the block must be positive ({} x {} x "
                                           "{} m)",
                                           r.size.x, r.size.y, r.size.z));
        }
    }
    if (!isFinite(r.blockPose) || !isFinite(r.gripPointOffset) || !isFinite(r.rail.pose) ||
        !std::isfinite(r.position) || !std::isfinite(r.approachDistance) ||
        r.approachDistance < 0) {
        return refuse(why, "a pose, the position or the approach distance is not finite");
    }
    // Upright: gripped from the top, it must stand on its foot.
    const double up = r.blockPose.M.UnitZ().z();
    if (up < std::cos(kMaxTopFaceTilt)) {
        return refuse(why,
                      fmt::format("the block is tilted by {:.1f} degrees; it must stand "
                                  "upright (within {:.0f})",
                                  std::acos(std::clamp(up, -1.0, 1.0)) * 180 / std::numbers::pi,
                                  kMaxTopFaceTilt * 180 / std::numbers::pi));
    }
    if (r.position - r.size.x / 2 < -1e-9 || r.position + r.size.x / 2 > r.rail.length + 1e-9) {
        return refuse(
            why, fmt::format("a block {:.1f} mm wide at {:.1f} mm does not lie on rail "
                             "{} ({:.1f} mm long)",
                             r.size.x * 1000, r.position * 1000, r.rail.id, r.rail.length * 1000));
    }

    const KDL::Frame grip = gripInBlock(r.size, r.type);
    const KDL::Frame toFlange = grip * r.gripPointOffset.Inverse();
    const double d = r.approachDistance;
    const KDL::Vector baseUp(0, 0, d);
    const KDL::Vector railNormal = r.rail.pose.M.UnitZ() * d;

    RailPlacementPlan plan;
    plan.width = r.size.x;
    plan.grasp = r.blockPose * toFlange;
    plan.approach = raised(plan.grasp, baseUp);
    plan.retreat = plan.approach;
    plan.hook = hookedPose(r.rail, r.position, r.size, kHookTilt) * toFlange;
    plan.hookApproach = raised(plan.hook, railNormal);
    for (int i = 1; i <= kRotateDownSteps; ++i) {
        const double tilt = kHookTilt * (kRotateDownSteps - i) / kRotateDownSteps;
        plan.rotateDown.push_back(hookedPose(r.rail, r.position, r.size, tilt) * toFlange);
    }
    plan.railRetreat = raised(plan.rotateDown.back(), railNormal);
    return plan;
}

std::optional<double> nextFreePosition(const DinRail& rail, double width,
                                       const std::vector<std::pair<double, double>>& mounted) {
    double end = 0;  // where the blocks so far end
    for (const auto& [centre, w] : mounted) end = std::max(end, centre + w / 2);
    const double position = end + width / 2;
    if (position + width / 2 > rail.length + 1e-9) return std::nullopt;
    return position;
}

}  // namespace skillcell::devices::pickplace
