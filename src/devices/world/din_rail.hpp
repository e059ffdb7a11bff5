#pragma once
// A DIN rail (EN 60715, TS35 top hat) and how a terminal block sits on it: pure geometry,
// shared by the world model (which decides whether a block has hooked and snapped) and by
// the composite skill that places blocks (which plans the same poses), so both hold one
// definition.
//
// Frames. The rail's frame has its origin at the rail's start, on the centre line of its
// face; x runs along the rail, y across it towards its upper edge, z out of its face. A
// terminal block is a box whose x edge is its width along the rail, y its depth across the
// rail and z its height off the rail. Mounted at position s, the block's centre is at
// (s, 0, height / 2) in the rail's frame, its axes the rail's.
//
// Mounting, as on a real rail: the block's upper foot (its bottom face's edge at y = +w/2,
// w the rail's width) is hooked over the rail's upper edge with the block tilted back by an
// angle about that edge, then the block is rotated down about the edge until its spring
// foot snaps over the lower edge. The tilt is the rotation about the rail's -x axis: a
// block tilted by t has its lower side lifted off the rail.
#include <kdl/frames.hpp>
#include <numbers>
#include <optional>
#include <string>

#include "devices/world/box_size.hpp"

namespace skillcell::devices {

inline constexpr double kTs35Width = 0.035;  // m, the rail's width (EN 60715)
/// The tilt at which a block is hooked before it is rotated down.
inline constexpr double kHookTilt = 15.0 * std::numbers::pi / 180;  // rad
/// Tilts at which a block still counts as hooked (it rests on the upper edge).
inline constexpr double kMaxHookTilt = 35.0 * std::numbers::pi / 180;  // rad
/// Below this tilt the spring foot snaps over the lower edge.
inline constexpr double kSnapTilt = 1.0 * std::numbers::pi / 180;  // rad
/// How far a block may be turned out of square with the rail (about its height axis) and
/// still engage: the foot's hook is a slot that only admits the edge nearly square.
inline constexpr double kMaxSkew = 2.0 * std::numbers::pi / 180;  // rad

struct DinRail {
    std::string id;
    KDL::Frame pose;  // the rail's frame in the cell's base frame
    double length = 0;
    double width = kTs35Width;
};

/// The block's pose when it is mounted at `position` along `rail`.
[[nodiscard]] KDL::Frame mountedPose(const DinRail& rail, double position, const BoxSize& block);
/// The block's pose hooked over the upper edge at `position`, tilted by `tilt` (rad).
[[nodiscard]] KDL::Frame hookedPose(const DinRail& rail, double position, const BoxSize& block,
                                    double tilt);

/// Where a block is on a rail: hooked over its upper edge at a position, with a tilt.
struct RailContact {
    double position = 0;  // the block's centre along the rail
    double tilt = 0;      // rad; about 0 when the block lies flat on the rail
};

/// The block's contact with the rail when its upper foot rests on the rail's upper edge
/// (within `tolerance` metres, the block's width inside the rail, its x axis along the rail
/// within kMaxSkew and its tilt between 0 and kMaxHookTilt); nullopt when it does not touch the
/// rail so.
[[nodiscard]] std::optional<RailContact> railContact(const DinRail& rail,
                                                     const KDL::Frame& blockPose,
                                                     const BoxSize& block, double tolerance);

/// Whether the spans [a - wa/2, a + wa/2] and [b - wb/2, b + wb/2] overlap by more than
/// `tolerance` (blocks side by side touch; they do not overlap).
[[nodiscard]] bool spansOverlap(double a, double wa, double b, double wb, double tolerance);

}  // namespace skillcell::devices
