#include "devices/arm/motion_planner.hpp"

#include <algorithm>
#include <cmath>

#include "devices/common/frame.hpp"

namespace skillcell::devices {
namespace {

constexpr double kSampleSpacing = 0.002;  // m of path parameter between IK samples
// Two neighbouring samples differing by more than this in a joint mean the line passes a
// singularity or flips the arm's configuration: not a straight line any more.
constexpr double kMaxJointStep = 0.1;  // rad

std::string jointName(std::size_t i) {
    return "joint " + std::to_string(i + 1);
}

}  // namespace

std::variant<Trajectory, std::string> MotionPlanner::plan(const Joints& current,
                                                          const MoveRequest& request) const {
    const bool linear = request.kind == MoveKind::CartesianLinear ||
                        request.kind == MoveKind::JointLinear ||
                        request.kind == MoveKind::CartesianForceLimitedLinear;
    const double velocity = request.maxVelocity > 0 ? request.maxVelocity
                            : linear                ? defaults_.linearVelocity
                                                    : defaults_.jointVelocity;
    const double acceleration = request.maxAcceleration > 0 ? request.maxAcceleration
                                : linear                    ? defaults_.linearAcceleration
                                                            : defaults_.jointAcceleration;
    const ArmModel& arm = kinematics_.model();
    const JointBounds& limits = arm.bounds;
    if (current.size() != arm.joints()) {
        return "the arm reports " + std::to_string(current.size()) + " joints, the " + arm.name +
               " has " + std::to_string(arm.joints());
    }
    JointBounds bounds = limits;
    if (request.axisBounds) {
        if (request.axisBounds->size() != arm.joints()) {
            return "AxisBounds must hold one Range per joint (" + std::to_string(arm.joints()) +
                   "), not " + std::to_string(request.axisBounds->size());
        }
        bounds = limits.intersect(*request.axisBounds);
    }
    for (std::size_t i = 0; i < bounds.size(); ++i) {
        if (bounds.lower[i] > bounds.upper[i]) {
            return "AxisBounds of " + jointName(i) + " do not overlap the " + arm.name +
                   "'s joint range";
        }
    }

    switch (request.kind) {
        case MoveKind::JointPtp:
        case MoveKind::JointLinear:
            if (request.targetJoints.size() != arm.joints()) {
                return "TargetJointPosition must hold " + std::to_string(arm.joints()) +
                       " joint positions, not " + std::to_string(request.targetJoints.size());
            }
            for (std::size_t i = 0; i < arm.joints(); ++i) {
                if (!std::isfinite(request.targetJoints[i]) ||
                    request.targetJoints[i] < limits.lower[i] ||
                    request.targetJoints[i] > limits.upper[i]) {
                    return "TargetJointPosition of " + jointName(i) + " (" +
                           std::to_string(request.targetJoints[i]) +
                           " rad) is outside the joint range";
                }
            }
            if (request.kind == MoveKind::JointPtp) {
                return Trajectory::jointSpace(current, request.targetJoints, velocity,
                                              acceleration);
            }
            {
                auto planned = this->linear(
                    current, kinematics_.forward(request.targetJoints) * request.toolFrame,
                    request.toolFrame, limits, velocity, acceleration);
                if (auto* t = std::get_if<Trajectory>(&planned)) {
                    // The line must end in the configuration asked for, not just the pose.
                    for (std::size_t i = 0; i < arm.joints(); ++i) {
                        if (std::abs(t->end()[i] - request.targetJoints[i]) > 1e-3) {
                            return std::string(
                                "a straight line from the present configuration ends in "
                                "another arm configuration than TargetJointPosition");
                        }
                    }
                }
                return planned;
            }
        case MoveKind::CartesianPtp: {
            std::string why;
            const auto q = kinematics_.inverse(request.target * request.toolFrame.Inverse(),
                                               current, bounds, &why);
            if (!q) return "target unreachable: " + why;
            return Trajectory::jointSpace(current, *q, velocity, acceleration);
        }
        case MoveKind::CartesianLinear:
            return this->linear(current, request.target, request.toolFrame, bounds, velocity,
                                acceleration);
        case MoveKind::CartesianForceLimitedLinear: {
            if (!(request.forceLimit > 0)) {
                return std::string("ForceLimit must be above 0 N");
            }
            auto planned = this->linear(current, request.target, request.toolFrame, bounds,
                                        velocity, acceleration);
            if (auto* t = std::get_if<Trajectory>(&planned)) t->limitForce(request.forceLimit);
            return planned;
        }
    }
    return std::string("unknown move");
}

std::variant<Trajectory, std::string> MotionPlanner::linear(
    const Joints& current, const KDL::Frame& tcpTarget, const KDL::Frame& toolFrame,
    const JointBounds& bounds, double velocity, double acceleration) const {
    const KDL::Frame flangeTarget = tcpTarget * toolFrame.Inverse();
    // The end first: a target out of reach gets that reason, not a path failure.
    std::string why;
    if (!kinematics_.inverse(flangeTarget, current, bounds, &why)) {
        return "target unreachable: " + why;
    }
    const KDL::Frame start = kinematics_.forward(current) * toolFrame;
    const KDL::Vector move = tcpTarget.p - start.p;
    KDL::Vector axis;
    const double angle = (start.M.Inverse() * tcpTarget.M).GetRotAngle(axis);
    const double length = std::max(move.Norm(), std::abs(angle) * kRotationRadius);
    const auto steps = static_cast<std::size_t>(std::max(1.0, std::ceil(length / kSampleSpacing)));

    std::vector<Joints> samples{current};
    std::vector<double> arc{0.0};
    Joints previous = current;
    for (std::size_t k = 1; k <= steps; ++k) {
        const double f = static_cast<double>(k) / static_cast<double>(steps);
        const KDL::Frame tcp(start.M * KDL::Rotation::Rot(axis, angle * f), start.p + move * f);
        const auto q = kinematics_.inverseNear(tcp * toolFrame.Inverse(), previous, bounds);
        const std::string where =
            std::to_string(static_cast<int>(std::round(f * 100))) + "% of the line";
        if (!q) return "the straight line leaves the workspace at " + where;
        for (std::size_t i = 0; i < q->size(); ++i) {
            if (std::abs((*q)[i] - previous[i]) > kMaxJointStep) {
                return "the straight line passes a singularity at " + where + " (" + jointName(i) +
                       " would jump)";
            }
        }
        samples.push_back(*q);
        arc.push_back(length * f);
        previous = *q;
    }
    return Trajectory(std::move(samples), std::move(arc), velocity, acceleration);
}

}  // namespace skillcell::devices
