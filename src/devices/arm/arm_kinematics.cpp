#include "devices/arm/arm_kinematics.hpp"

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
    KDL::JntArray a(static_cast<unsigned>(q.size()));
    for (std::size_t i = 0; i < q.size(); ++i) a(static_cast<unsigned>(i)) = q[i];
    return a;
}

}  // namespace

ArmKinematics::ArmKinematics(ArmModel model, const KDL::Frame& base)
    : model_(std::move(model)), base_(base), fromCell_(base.Inverse()) {
    fk_ = std::make_unique<KDL::ChainFkSolverPos_recursive>(model_.chain);
    ik_ = std::make_unique<KDL::ChainIkSolverPos_LMA>(model_.chain, 1e-12, 500, 1e-15);
    // Starting points spread over the joint bounds (within +-pi), fixed so results are
    // reproducible.
    std::mt19937 random(5);
    for (std::size_t k = 0; k < kStarts; ++k) {
        Joints q(joints());
        for (std::size_t i = 0; i < q.size(); ++i) {
            std::uniform_real_distribution<double> angle(std::max(-M_PI, model_.bounds.lower[i]),
                                                         std::min(M_PI, model_.bounds.upper[i]));
            q[i] = angle(random);
        }
        starts_.push_back(q);
    }
}

ArmKinematics::~ArmKinematics() = default;

KDL::Frame ArmKinematics::forward(const Joints& q) const {
    KDL::Frame f;
    if (q.size() != joints()) return f;  // no pose for the wrong number of joints
    fk_->JntToCart(toJnt(q), f);
    return base_ * f;
}

std::optional<Joints> ArmKinematics::solveFrom(const KDL::Frame& flange, const Joints& start,
                                               const Joints& reference, const JointBounds& bounds,
                                               bool* converged) const {
    if (start.size() != joints() || reference.size() != joints() || bounds.size() != joints()) {
        return std::nullopt;
    }
    KDL::JntArray out(static_cast<unsigned>(joints()));
    (void)ik_->CartToJnt(toJnt(start), fromCell_ * flange, out);
    Joints q(joints());
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = out(static_cast<unsigned>(i));
    if (!near(forward(q), flange, kPositionTolerance, kAngleTolerance)) return std::nullopt;
    *converged = true;
    // Revolute joints: a solution plus whole turns is a solution. Take the turn nearest
    // the reference (the arm's present position) that lies within the bounds.
    for (std::size_t i = 0; i < q.size(); ++i) {
        double v = q[i] + kTwoPi * std::round((reference[i] - q[i]) / kTwoPi);
        if (v < bounds.lower[i]) v += kTwoPi * std::ceil((bounds.lower[i] - v) / kTwoPi);
        if (v > bounds.upper[i]) v -= kTwoPi * std::ceil((v - bounds.upper[i]) / kTwoPi);
        if (v < bounds.lower[i] - 1e-9 || v > bounds.upper[i] + 1e-9) return std::nullopt;
        q[i] = v;
    }
    return q;
}

std::optional<Joints> ArmKinematics::inverseNear(const KDL::Frame& flange, const Joints& seed,
                                                 const JointBounds& bounds) const {
    bool converged = false;
    return solveFrom(flange, seed, seed, bounds, &converged);
}

std::optional<Joints> ArmKinematics::inverse(const KDL::Frame& flange, const Joints& seed,
                                             const JointBounds& bounds, std::string* why) const {
    if ((flange.p - shoulder()).Norm() > model_.reach) {
        if (why != nullptr) {
            *why = "the flange pose " + describe(flange) + " is out of the " + model_.name +
                   "'s reach";
        }
        return std::nullopt;
    }
    if (seed.empty()) return inverse(flange, Joints(joints(), 0.0), bounds, why);
    if (seed.size() != joints()) {
        if (why != nullptr) {
            *why = "the seed has " + std::to_string(seed.size()) + " joints, the " + model_.name +
                   " " + std::to_string(joints());
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
        for (std::size_t i = 0; i < q->size(); ++i) {
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
                         : "the flange pose " + describe(flange) + " is out of the " + model_.name +
                               "'s reach";
    }
    return best;
}

}  // namespace skillcell::devices
