#pragma once
// ArmModel: what makes one robot arm different from another to the arm stack (kinematics,
// motion planning, the simulated arm, the component): its kinematic chain from the
// manufacturer's published parameters, its joint limits, where the simulation starts, how far
// it reaches, and how the Robotics model names it and its axes. Two models exist: the
// Universal Robots UR5 (6 axes) and the KUKA LBR iiwa 7 R800 (7 axes).
#include <cstddef>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

namespace skillcell::devices {

/// Joint positions (rad), one per axis from the base to the flange.
using Joints = std::vector<double>;

/// Per-joint bounds, radians.
struct JointBounds {
    Joints lower;
    Joints upper;
    /// Every one of `joints` joints within [lo, hi].
    [[nodiscard]] static JointBounds uniform(std::size_t joints, double lo, double hi);
    [[nodiscard]] std::size_t size() const { return lower.size(); }
    /// False also when `q` has another number of joints.
    [[nodiscard]] bool contains(const Joints& q, double tolerance = 1e-9) const;
    /// These bounds narrowed by `other` (an empty range when they do not overlap).
    [[nodiscard]] JointBounds intersect(const JointBounds& other) const;
};

/// The limits a move uses when MaxVelocity / MaxAcceleration are zero.
struct MoveDefaults {
    double linearVelocity = 0.25;     // m/s
    double linearAcceleration = 1.2;  // m/s^2
    double jointVelocity = 1.05;      // rad/s
    double jointAcceleration = 1.4;   // rad/s^2
};

struct ArmModel {
    std::string name;  // the component's object (Objects/<name>) and the Robotics model's
    std::string manufacturer;
    std::string model;
    std::string productCode;
    std::vector<std::string> axes;  // the Robotics model's axis names, base to flange
    KDL::Chain chain;               // revolute joints, base to flange
    JointBounds bounds;             // the arm's own joint limits
    Joints home;                    // where the simulated arm starts: folded, flange down
    KDL::Vector shoulder;           // a point the reach is measured from
    double reach = 0;               // m: no flange position farther from `shoulder` can be reached
    MoveDefaults defaults;
    /// The arm measures the force its tool meets (joint torque sensors), so it offers
    /// force-limited moves.
    bool sensesForce = false;

    [[nodiscard]] std::size_t joints() const { return axes.size(); }

    /// Universal Robots UR5: the published Denavit-Hartenberg parameters (standard
    /// convention) d1 = 0.089159, a2 = -0.425, a3 = -0.39225, d4 = 0.10915, d5 = 0.09465,
    /// d6 = 0.0823 m, alpha = (pi/2, 0, 0, pi/2, -pi/2, 0); every joint +-2 pi; linear moves
    /// 250 mm/s and 1.2 m/s^2, joints 60 deg/s and 80 deg/s^2 by default.
    [[nodiscard]] static ArmModel ur5();
    /// KUKA LBR iiwa 7 R800: seven revolute axes with intersecting wrist and shoulder axes;
    /// from KUKA's data sheet, 340 mm from the base to axis 2, 400 mm from axis 2 to axis 4
    /// and from axis 4 to axis 6, 126 mm from axis 6 to the flange (standard DH: d = 0.34,
    /// 0, 0.4, 0, 0.4, 0, 0.126 m; alpha = -pi/2, pi/2, pi/2, -pi/2, -pi/2, pi/2, 0); axis
    /// limits +-170, +-120, +-170, +-120, +-170, +-120, +-175 deg.
    [[nodiscard]] static ArmModel lbrIiwa7();
};

}  // namespace skillcell::devices
