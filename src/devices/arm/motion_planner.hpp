#pragma once
// MotionPlanner: turns a move request (one of the four move skills' parameters) into a
// Trajectory from the arm's present joints, or says why it cannot: a target out of
// reach, outside the joint bounds or AxisBounds, or a straight line that leaves the
// workspace or passes a singularity. Planning is complete before the arm moves, so an
// unreachable target never starts a motion. Pure computation (no clock, no I/O).
#include <optional>
#include <string>
#include <variant>

#include "devices/arm/arm_kinematics.hpp"
#include "devices/arm/trajectory.hpp"

namespace skillcell::devices {

enum class MoveKind : std::uint8_t {
    CartesianLinear,
    CartesianPtp,
    JointLinear,
    JointPtp,
    CartesianForceLimitedLinear,  // a linear move that stops above a contact force
};

struct MoveRequest {
    MoveKind kind = MoveKind::JointPtp;
    KDL::Frame toolFrame = KDL::Frame::Identity();  // TCP relative to the flange
    double maxVelocity = 0;                         // 0: the default
    double maxAcceleration = 0;
    KDL::Frame target = KDL::Frame::Identity();  // Cartesian moves: the TCP's target
    Joints targetJoints;                         // joint moves
    std::optional<JointBounds> axisBounds;       // Cartesian moves: narrows the joint limits
    double forceLimit = 0;                       // N, force-limited moves
};

/// Path parameter of a linear move: the TCP's distance, or for a turn in place the arc a
/// point this far from the TCP travels, whichever is longer (so a pure rotation has a
/// duration and respects the same limits).
inline constexpr double kRotationRadius = 0.1;

class MotionPlanner {
public:
    /// Moves without limits of their own use `defaults` (the arm model's own).
    MotionPlanner(const ArmKinematics& kinematics, MoveDefaults defaults)
        : kinematics_(kinematics), defaults_(defaults) {}

    /// A trajectory from `current`, or the reason there is none.
    [[nodiscard]] std::variant<Trajectory, std::string> plan(const Joints& current,
                                                             const MoveRequest& request) const;

private:
    [[nodiscard]] std::variant<Trajectory, std::string> linear(
        const Joints& current, const KDL::Frame& tcpTarget, const KDL::Frame& toolFrame,
        const JointBounds& bounds, double velocity, double acceleration) const;

    const ArmKinematics& kinematics_;
    MoveDefaults defaults_;
};

}  // namespace skillcell::devices
