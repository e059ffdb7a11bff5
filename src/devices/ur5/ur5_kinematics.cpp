#include "devices/ur5/ur5_kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <random>

#include "devices/common/frame.hpp"

namespace skillcell::devices {
namespace {

constexpr double kTwoPi = 2 * M_PI;
// A solution must reproduce the target this closely (the solver's own criterion is a
// weighted error; this is the check in metres and radians).
constexpr double kPositionTolerance = 1e-6;
constexpr double kAngleTolerance = 1e-6;
constexpr std::size_t kStarts = 32;

KDL::JntArray toJnt(const Joints& q) {
    KDL::JntArray a(kUr5Joints);
    for (std::size_t i = 0; i < kUr5Joints; ++i) a(static_cast<unsigned>(i)) = q[i];
    return a;
}

}  // namespace

JointBounds JointBounds::ur5() {
    JointBounds b;
    b.lower.fill(-kTwoPi);
    b.upper.fill(kTwoPi);
    return b;
}

bool JointBounds::contains(const Joints& q, double tolerance) const {
    for (std::size_t i = 0; i < kUr5Joints; ++i) {
        if (q[i] < lower[i] - tolerance || q[i] > upper[i] + tolerance) return false;
    }
    return true;
}

JointBounds JointBounds::intersect(const JointBounds& other) const {
    JointBounds b;
    for (std::size_t i = 0; i < kUr5Joints; ++i) {
        b.lower[i] = std::max(lower[i], other.lower[i]);
        b.upper[i] = std::min(upper[i], other.upper[i]);
    }
    return b;
}

Ur5Kinematics::Ur5Kinematics() {
    struct Dh {
        double a, alpha, d;
    };
    const Dh dh[kUr5Joints] = {{0, M_PI / 2, 0.089159}, {-0.425, 0, 0},          {-0.39225, 0, 0},
                               {0, M_PI / 2, 0.10915},  {0, -M_PI / 2, 0.09465}, {0, 0, 0.0823}};
    for (const Dh& j : dh) {
        chain_.addSegment(
            KDL::Segment(KDL::Joint(KDL::Joint::RotZ), KDL::Frame::DH(j.a, j.alpha, j.d, 0)));
    }
    fk_ = std::make_unique<KDL::ChainFkSolverPos_recursive>(chain_);
    ik_ = std::make_unique<KDL::ChainIkSolverPos_LMA>(chain_, 1e-12, 500, 1e-15);
    // Starting points spread over the usual working range, fixed so results are
    // reproducible.
    std::mt19937 random(5);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    for (std::size_t i = 0; i < kStarts; ++i) {
        Joints q;
        for (double& v : q) v = angle(random);
        starts_.push_back(q);
    }
}

Ur5Kinematics::~Ur5Kinematics() = default;

KDL::Frame Ur5Kinematics::forward(const Joints& q) const {
    KDL::Frame f;
    fk_->JntToCart(toJnt(q), f);
    return f;
}

std::optional<Joints> Ur5Kinematics::solveFrom(const KDL::Frame& flange, const Joints& start,
                                               const Joints& reference, const JointBounds& bounds,
                                               bool* converged) const {
    KDL::JntArray out(kUr5Joints);
    (void)ik_->CartToJnt(toJnt(start), flange, out);
    Joints q;
    for (std::size_t i = 0; i < kUr5Joints; ++i) q[i] = out(static_cast<unsigned>(i));
    if (!near(forward(q), flange, kPositionTolerance, kAngleTolerance)) return std::nullopt;
    *converged = true;
    // Revolute joints: a solution plus whole turns is a solution. Take the turn nearest
    // the reference (the arm's present position) that lies within the bounds.
    for (std::size_t i = 0; i < kUr5Joints; ++i) {
        double v = q[i] + kTwoPi * std::round((reference[i] - q[i]) / kTwoPi);
        if (v < bounds.lower[i]) v += kTwoPi * std::ceil((bounds.lower[i] - v) / kTwoPi);
        if (v > bounds.upper[i]) v -= kTwoPi * std::ceil((v - bounds.upper[i]) / kTwoPi);
        if (v < bounds.lower[i] - 1e-9 || v > bounds.upper[i] + 1e-9) return std::nullopt;
        q[i] = v;
    }
    return q;
}

std::optional<Joints> Ur5Kinematics::inverseNear(const KDL::Frame& flange, const Joints& seed,
                                                 const JointBounds& bounds) const {
    bool converged = false;
    return solveFrom(flange, seed, seed, bounds, &converged);
}

std::optional<Joints> Ur5Kinematics::inverse(const KDL::Frame& flange, const Joints& seed,
                                             const JointBounds& bounds, std::string* why) const {
    const KDL::Vector shoulder(0, 0, 0.089159);
    if ((flange.p - shoulder).Norm() > kReach) {
        if (why != nullptr) {
            *why = "the flange pose " + describe(flange) + " is out of the UR5's reach";
        }
        return std::nullopt;
    }
    bool converged = false;
    std::optional<Joints> best;
    double bestDistance = 0;
    auto consider = [&](const Joints& start) {
        const auto q = solveFrom(flange, start, seed, bounds, &converged);
        if (!q) return;
        double distance = 0;
        for (std::size_t i = 0; i < kUr5Joints; ++i) {
            distance = std::max(distance, std::abs((*q)[i] - seed[i]));
        }
        if (!best || distance < bestDistance) {
            best = q;
            bestDistance = distance;
        }
    };
    consider(seed);
    // A solution that barely moves the arm needs no other candidates.
    if (!best || bestDistance > 0.5) {
        for (const Joints& start : starts_) consider(start);
    }
    if (!best && why != nullptr) {
        *why = converged ? "no solution for the flange pose " + describe(flange) +
                               " lies within the joint bounds"
                         : "the flange pose " + describe(flange) + " is out of the UR5's reach";
    }
    return best;
}

}  // namespace skillcell::devices
