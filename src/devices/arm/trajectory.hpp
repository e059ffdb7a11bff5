#pragma once
// Trajectory: joint positions as a function of simulated time: a polyline through joint
// samples, walked along its path parameter by a trapezoidal profile. A point-to-point
// move is a polyline of two samples whose parameter is the lead joint's angle; a linear
// move samples the Cartesian line and its parameter is the tool centre point's path.
#include <vector>

#include "devices/arm/arm_kinematics.hpp"
#include "devices/arm/trapezoidal_profile.hpp"

namespace skillcell::devices {

class Trajectory {
public:
    Trajectory() = default;
    /// `samples` (at least one) at path parameters `arc` (non-decreasing, from 0), walked
    /// with the given limits on the parameter's velocity and acceleration.
    Trajectory(std::vector<Joints> samples, std::vector<double> arc, double maxVelocity,
               double maxAcceleration);
    /// Joint space straight line; the lead joint (largest change) moves at the limits, the
    /// others in proportion, so all joints start and stop together.
    [[nodiscard]] static Trajectory jointSpace(const Joints& from, const Joints& to,
                                               double maxVelocity, double maxAcceleration);

    [[nodiscard]] double duration() const { return profile_.duration(); }
    [[nodiscard]] Joints at(double t) const;
    [[nodiscard]] const Joints& end() const { return samples_.back(); }
    [[nodiscard]] const TrapezoidalProfile& profile() const { return profile_; }
    [[nodiscard]] const std::vector<Joints>& samples() const { return samples_; }
    /// A force-limited motion stops where the force its tool meets exceeds `newtons`
    /// (0: no limit).
    void limitForce(double newtons) { forceLimit_ = newtons; }
    [[nodiscard]] double forceLimit() const { return forceLimit_; }

private:
    std::vector<Joints> samples_{Joints{}};
    std::vector<double> arc_{0.0};
    TrapezoidalProfile profile_;
    double forceLimit_ = 0;
};

}  // namespace skillcell::devices
