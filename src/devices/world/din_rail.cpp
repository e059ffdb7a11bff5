#include "devices/world/din_rail.hpp"

#include <cmath>

namespace skillcell::devices {
namespace {

/// The block's upper foot, in the block's frame: its bottom face's edge that hooks over the
/// rail's upper edge.
KDL::Vector upperFoot(const DinRail& rail, const BoxSize& block) {
    return {0, rail.width / 2, -block.z / 2};
}

}  // namespace

KDL::Frame mountedPose(const DinRail& rail, double position, const BoxSize& block) {
    return rail.pose * KDL::Frame(KDL::Vector(position, 0, block.z / 2));
}

KDL::Frame hookedPose(const DinRail& rail, double position, const BoxSize& block, double tilt) {
    // Rotate the mounted block about the rail's upper edge (a line along x through the
    // upper foot), lifting its lower side: a rotation about -x.
    const KDL::Frame edge(KDL::Vector(position, rail.width / 2, 0));
    const KDL::Frame footToCentre(-upperFoot(rail, block));
    return rail.pose * edge * KDL::Frame(KDL::Rotation::RotX(-tilt)) * footToCentre;
}

std::optional<RailContact> railContact(const DinRail& rail, const KDL::Frame& blockPose,
                                       const BoxSize& block, double tolerance) {
    const KDL::Frame local = rail.pose.Inverse() * blockPose;
    const KDL::Vector foot = local * upperFoot(rail, block);
    if (std::abs(foot.y() - rail.width / 2) > tolerance || std::abs(foot.z()) > tolerance) {
        return std::nullopt;
    }
    const double position = foot.x();
    if (position - block.x / 2 < -tolerance || position + block.x / 2 > rail.length + tolerance) {
        return std::nullopt;
    }
    // The block's x axis must lie along the rail (it may only be tilted about it).
    const KDL::Vector x = local.M.UnitX();
    if (x.x() < std::cos(kMaxSkew)) return std::nullopt;
    const KDL::Vector z = local.M.UnitZ();
    const double tilt = std::atan2(z.y(), z.z());
    if (tilt < -kSnapTilt || tilt > kMaxHookTilt) return std::nullopt;
    return RailContact{position, tilt};
}

bool spansOverlap(double a, double wa, double b, double wb, double tolerance) {
    return std::abs(a - b) < (wa + wb) / 2 - tolerance;
}

}  // namespace skillcell::devices
