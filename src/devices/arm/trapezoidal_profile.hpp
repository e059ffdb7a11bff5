#pragma once
// TrapezoidalProfile: the time law of a motion over a distance with a velocity and an
// acceleration limit: accelerate at the limit, cruise at the velocity limit, decelerate
// at the limit; a triangle when the distance is too short to reach the velocity limit.
// Pure arithmetic on simulated seconds.
namespace skillcell::devices {

class TrapezoidalProfile {
public:
    TrapezoidalProfile() = default;
    /// `distance` >= 0; `maxVelocity` and `maxAcceleration` > 0.
    TrapezoidalProfile(double distance, double maxVelocity, double maxAcceleration);

    [[nodiscard]] double duration() const { return 2 * accelTime_ + cruiseTime_; }
    [[nodiscard]] double distance() const { return distance_; }
    /// Distance covered at time `t` (clamped to [0, duration]).
    [[nodiscard]] double position(double t) const;
    [[nodiscard]] double velocity(double t) const;
    /// The highest velocity reached (the limit, or the triangle's peak).
    [[nodiscard]] double peakVelocity() const { return peak_; }

private:
    double distance_ = 0;
    double acceleration_ = 1;
    double peak_ = 0;
    double accelTime_ = 0;
    double cruiseTime_ = 0;
};

}  // namespace skillcell::devices
