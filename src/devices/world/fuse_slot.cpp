#include "devices/world/fuse_slot.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices {

std::optional<SlotContact> slotContact(const FuseSlot& slot, const KDL::Frame& fusePose,
                                       const BoxSize& fuse, double reach) {
    const KDL::Frame local = slot.truePose().Inverse() * fusePose;
    const KDL::Vector tip = local * KDL::Vector(0, 0, -fuse.z / 2);
    if (tip.z() >= 0) return std::nullopt;  // above the opening
    const double misalignment = std::hypot(tip.x(), tip.y());
    if (misalignment > reach) return std::nullopt;  // beside this slot
    SlotContact c;
    c.depth = -tip.z();
    c.misalignment = misalignment;
    // Square with the slot: the fuse's height along the slot's z, and its width along the
    // slot's x either way round (the fuse is symmetric).
    const double tilt = std::acos(std::clamp(local.M.UnitZ().z(), -1.0, 1.0));
    const double skew = std::acos(std::clamp(std::abs(local.M.UnitX().x()), 0.0, 1.0));
    c.aligned = misalignment <= slot.clearance && tilt <= kMaxFuseSkew && skew <= kMaxFuseSkew;
    if (c.aligned) {
        c.force = kTerminalFriction + kBottomStiffness * std::max(0.0, c.depth - slot.depth);
    } else {
        c.force = kFaceStiffness * c.depth;
    }
    return c;
}

KDL::Frame seatedPose(const FuseSlot& slot, const BoxSize& fuse) {
    return slot.truePose() * KDL::Frame(KDL::Vector(0, 0, fuse.z / 2 - slot.depth));
}

}  // namespace skillcell::devices
