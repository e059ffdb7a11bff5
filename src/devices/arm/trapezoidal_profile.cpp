#include "devices/arm/trapezoidal_profile.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices {

TrapezoidalProfile::TrapezoidalProfile(double distance, double maxVelocity, double maxAcceleration)
    : distance_(std::max(distance, 0.0)), acceleration_(maxAcceleration) {
    if (distance_ * maxAcceleration < maxVelocity * maxVelocity) {
        peak_ = std::sqrt(distance_ * maxAcceleration);  // never reaches the limit
        accelTime_ = peak_ / maxAcceleration;
        cruiseTime_ = 0;
    } else {
        peak_ = maxVelocity;
        accelTime_ = maxVelocity / maxAcceleration;
        cruiseTime_ = (distance_ - maxVelocity * accelTime_) / maxVelocity;
    }
}

double TrapezoidalProfile::position(double t) const {
    t = std::clamp(t, 0.0, duration());
    const double ta = accelTime_;
    if (t <= ta) return 0.5 * acceleration_ * t * t;
    const double accelDistance = 0.5 * acceleration_ * ta * ta;
    if (t <= ta + cruiseTime_) return accelDistance + peak_ * (t - ta);
    const double left = duration() - t;
    return std::min(distance_, distance_ - 0.5 * acceleration_ * left * left);
}

double TrapezoidalProfile::velocity(double t) const {
    if (t <= 0 || t >= duration()) return 0;
    if (t <= accelTime_) return acceleration_ * t;
    if (t <= accelTime_ + cruiseTime_) return peak_;
    return acceleration_ * (duration() - t);
}

}  // namespace skillcell::devices
