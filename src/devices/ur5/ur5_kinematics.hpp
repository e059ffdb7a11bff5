#pragma once
// Ur5Kinematics: forward and inverse kinematics of a Universal Robots UR5 on Orocos KDL,
// built from the published Denavit-Hartenberg parameters (standard convention) of the
// UR5: d1 = 0.089159, a2 = -0.425, a3 = -0.39225, d4 = 0.10915, d5 = 0.09465,
// d6 = 0.0823 m; alpha = (pi/2, 0, 0, pi/2, -pi/2, 0). Poses are the flange (tool
// mounting plate) in the robot's base frame.
//
// Inverse kinematics: KDL's Levenberg-Marquardt solver from several starting points (the
// caller's seed first, then a fixed set spread over the joint space), each solution
// checked against forward kinematics and moved by whole turns into the joint bounds
// (the UR5's +-2 pi, narrowed by the move's AxisBounds); among the valid solutions the
// one nearest the seed wins. Not thread-safe: KDL's solvers keep working buffers.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

namespace KDL {
class ChainFkSolverPos_recursive;
class ChainIkSolverPos_LMA;
}  // namespace KDL

namespace skillcell::devices {

inline constexpr std::size_t kUr5Joints = 6;
using Joints = std::array<double, kUr5Joints>;

/// Per-joint bounds, radians.
struct JointBounds {
    Joints lower{};
    Joints upper{};
    /// The UR5's own limits: every joint +-2 pi.
    [[nodiscard]] static JointBounds ur5();
    [[nodiscard]] bool contains(const Joints& q, double tolerance = 1e-9) const;
    /// These bounds narrowed by `other` (an empty range when they do not overlap).
    [[nodiscard]] JointBounds intersect(const JointBounds& other) const;
};

class Ur5Kinematics {
public:
    Ur5Kinematics();
    ~Ur5Kinematics();
    Ur5Kinematics(const Ur5Kinematics&) = delete;
    Ur5Kinematics& operator=(const Ur5Kinematics&) = delete;

    /// The flange pose for joint positions `q`.
    [[nodiscard]] KDL::Frame forward(const Joints& q) const;
    /// Joint positions within `bounds` that put the flange at `flange`, nearest `seed`.
    /// nullopt when there is none; `why` (if given) says whether the pose is out of reach
    /// or only out of the bounds.
    [[nodiscard]] std::optional<Joints> inverse(const KDL::Frame& flange, const Joints& seed,
                                                const JointBounds& bounds,
                                                std::string* why = nullptr) const;
    /// Like inverse() but starting from `seed` only (continuous paths: a solution from
    /// another start could jump to another arm configuration).
    [[nodiscard]] std::optional<Joints> inverseNear(const KDL::Frame& flange, const Joints& seed,
                                                    const JointBounds& bounds) const;

    /// Distance from the shoulder axis intersection within which a flange position can be
    /// reachable (an upper bound: used to refuse far targets quickly with a clear reason).
    static constexpr double kReach = 0.425 + 0.39225 + 0.10915 + 0.09465 + 0.0823;

private:
    /// One LMA run from `start`, verified by forward kinematics and shifted into `bounds`.
    [[nodiscard]] std::optional<Joints> solveFrom(const KDL::Frame& flange, const Joints& start,
                                                  const Joints& reference,
                                                  const JointBounds& bounds, bool* converged) const;

    KDL::Chain chain_;
    std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk_;
    std::unique_ptr<KDL::ChainIkSolverPos_LMA> ik_;
    std::vector<Joints> starts_;  // the fixed starting points after the seed
};

}  // namespace skillcell::devices
