#pragma once
// A slot for an ATO blade fuse in a fuse box, and the force a fuse meets as it goes in: pure
// physics, shared by the world model (which reports the force and seats the fuse) and by
// whoever plans an insertion, so both hold one definition.
//
// Frames. The slot's frame has its origin at the centre of its opening on the box's face, z
// out of the box (a fuse goes in along -z), x along the fuse's width (the line through its
// two blades). A fuse is a box whose x edge is its width, y its thickness and z its height,
// blades down: its blade tips are at (0, 0, -height / 2) in its own frame.
//
// The force, along the slot's +z (pushing the fuse back out), once the blade tips are below
// the opening:
// - aligned (tips within the terminals' lateral play, the fuse square with the slot): the
//   terminals' spring contacts rub, kTerminalFriction, until the fuse bottoms out at the
//   slot's depth, from where the box pushes back with kBottomStiffness;
// - misaligned: the blades meet the box's face beside the terminals, which does not give:
//   kFaceStiffness per metre pushed into it, so a force-limited insertion stops within a
//   fraction of a millimetre.
#include <numbers>
#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "devices/world/box_size.hpp"

namespace skillcell::devices {

inline constexpr double kTerminalFriction = 6.0;      // N, the blades sliding into the terminals
inline constexpr double kFaceStiffness = 30'000.0;    // N/m, a blade on the box's face
inline constexpr double kBottomStiffness = 50'000.0;  // N/m, a seated fuse pushed further
/// How far a fuse may be turned out of square with its slot and still enter it.
inline constexpr double kMaxFuseSkew = 3.0 * std::numbers::pi / 180;  // rad
/// A fuse counts as seated within this of the slot's depth.
inline constexpr double kSeatTolerance = 0.0005;  // m

struct FuseSlot {
    std::string id;
    KDL::Frame pose;            // the opening's centre, z out of the box, as drawn
    double depth = 0.008;       // m the blades go in when the fuse is seated
    double clearance = 0.0004;  // m of lateral play the terminals admit
    /// Where the terminals really are, from `pose`, in its frame: a box made out of
    /// tolerance. Only the physics knows it; whoever plans an insertion sees `pose`.
    KDL::Vector misalignment = KDL::Vector::Zero();
    /// The opening as it really is.
    [[nodiscard]] KDL::Frame truePose() const { return pose * KDL::Frame(misalignment); }
};

/// A fuse's contact with a slot.
struct SlotContact {
    double depth = 0;         // m the blade tips are below the opening (> 0)
    double misalignment = 0;  // m, the tips' lateral distance from the slot's centre
    bool aligned = false;     // the blades are in the terminals (else on the box's face)
    double force = 0;         // N along the slot's +z
    [[nodiscard]] bool seated(const FuseSlot& slot) const {
        return aligned && depth >= slot.depth - kSeatTolerance;
    }
};

/// The fuse's contact with `slot` when its blade tips are below the opening within `reach`
/// metres of the slot's centre (laterally); nullopt when it does not touch this slot.
[[nodiscard]] std::optional<SlotContact> slotContact(const FuseSlot& slot,
                                                     const KDL::Frame& fusePose,
                                                     const BoxSize& fuse, double reach = 0.01);

/// The fuse's pose seated in `slot` (where it really is).
[[nodiscard]] KDL::Frame seatedPose(const FuseSlot& slot, const BoxSize& fuse);

}  // namespace skillcell::devices
