#include "devices/arm/trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices {

Trajectory::Trajectory(std::vector<Joints> samples, std::vector<double> arc, double maxVelocity,
                       double maxAcceleration)
    : samples_(std::move(samples)),
      arc_(std::move(arc)),
      profile_(arc_.back(), maxVelocity, maxAcceleration) {}

Trajectory Trajectory::jointSpace(const Joints& from, const Joints& to, double maxVelocity,
                                  double maxAcceleration) {
    double lead = 0;
    for (std::size_t i = 0; i < from.size() && i < to.size(); ++i) {
        lead = std::max(lead, std::abs(to[i] - from[i]));
    }
    return Trajectory({from, to}, {0.0, lead}, maxVelocity, maxAcceleration);
}

Joints Trajectory::at(double t) const {
    const double s = profile_.position(t);
    if (samples_.size() == 1 || s >= arc_.back()) return samples_.back();
    // The segment holding s, then linear interpolation inside it.
    const auto upper = std::upper_bound(arc_.begin(), arc_.end(), s);
    const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, upper - arc_.begin()));
    const double length = arc_[i] - arc_[i - 1];
    const double f = length > 0 ? (s - arc_[i - 1]) / length : 1.0;
    Joints q(samples_[i].size());
    for (std::size_t j = 0; j < q.size(); ++j) {
        q[j] = samples_[i - 1][j] + f * (samples_[i][j] - samples_[i - 1][j]);
    }
    return q;
}

}  // namespace skillcell::devices
