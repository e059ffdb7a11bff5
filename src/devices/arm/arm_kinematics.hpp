#pragma once
// ArmKinematics: forward and inverse kinematics of a serial robot arm (arm_model.hpp: the
// UR5, the KUKA LBR iiwa 7 R800) on Orocos KDL, from the arm's chain. Poses are the flange
// (tool mounting plate) in the cell's frame, in which the robot's base stands at `base` (a
// cell with several robots has one frame for all of them).
//
// Inverse kinematics: KDL's Levenberg-Marquardt solver from several starting points (the
// caller's seed first, then a fixed set spread over the joint bounds), each solution
// checked against forward kinematics and moved by whole turns into the joint bounds (the
// arm's own, narrowed by the move's AxisBounds); among the valid solutions the one nearest
// the seed wins. For a redundant arm (7 axes) that is the solution the solver reaches from
// the seed, so a motion keeps its elbow where it was. Not thread-safe: KDL's solvers keep
// working buffers.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

#include "devices/arm/arm_model.hpp"

namespace KDL {
class ChainFkSolverPos_recursive;
class ChainIkSolverPos_LMA;
}  // namespace KDL

namespace skillcell::devices {

class ArmKinematics {
public:
    explicit ArmKinematics(ArmModel model, const KDL::Frame& base = KDL::Frame::Identity());
    ~ArmKinematics();
    ArmKinematics(const ArmKinematics&) = delete;
    ArmKinematics& operator=(const ArmKinematics&) = delete;

    /// The flange pose for joint positions `q`.
    [[nodiscard]] KDL::Frame forward(const Joints& q) const;
    /// Joint positions within `bounds` that put the flange at `flange`, nearest `seed` (an
    /// empty seed: all joints at zero).
    /// nullopt when there is none; `why` (if given) says whether the pose is out of reach
    /// or only out of the bounds.
    [[nodiscard]] std::optional<Joints> inverse(const KDL::Frame& flange, const Joints& seed,
                                                const JointBounds& bounds,
                                                std::string* why = nullptr) const;
    /// Like inverse() but starting from `seed` only (continuous paths: a solution from
    /// another start could jump to another arm configuration).
    [[nodiscard]] std::optional<Joints> inverseNear(const KDL::Frame& flange, const Joints& seed,
                                                    const JointBounds& bounds) const;

    [[nodiscard]] const ArmModel& model() const { return model_; }
    /// Where the base stands in the cell's frame.
    [[nodiscard]] const KDL::Frame& base() const { return base_; }
    /// The centre of the arm's reach (its shoulder) in the cell's frame.
    [[nodiscard]] KDL::Vector shoulder() const { return base_ * model_.shoulder; }
    [[nodiscard]] std::size_t joints() const { return model_.joints(); }

private:
    /// One LMA run from `start`, verified by forward kinematics and shifted into `bounds`.
    [[nodiscard]] std::optional<Joints> solveFrom(const KDL::Frame& flange, const Joints& start,
                                                  const Joints& reference,
                                                  const JointBounds& bounds, bool* converged) const;

    ArmModel model_;
    KDL::Frame base_;
    KDL::Frame fromCell_;  // the cell's frame to the base's: base_.Inverse()
    std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk_;
    std::unique_ptr<KDL::ChainIkSolverPos_LMA> ik_;
    std::vector<Joints> starts_;  // the fixed starting points after the seed
};

}  // namespace skillcell::devices
