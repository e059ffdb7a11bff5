#include "devices/pickplace/grasp_planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "devices/common/frame.hpp"
#include "devices/pickplace/plan_refusal.hpp"

namespace skillcell::devices::pickplace {
namespace {

// Below this, the wide axis counts as perpendicular to base x and the approach side is
// chosen by base y instead, so rounding cannot flip the side of a yaw-90 box.
constexpr double kSideTie = 1e-9;

std::string number(double value) {
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), "%.4g", value);
    return text.data();
}

KDL::Vector column(const KDL::Rotation& r, int i) {
    return {r(0, i), r(1, i), r(2, i)};
}

// Orthonormal with determinant +1: anything else would make the plan's poses meaningless
// to the robot, so it is refused rather than silently re-orthonormalised.
bool proper(const KDL::Rotation& r) {
    for (int i = 0; i < 3; ++i) {
        for (int j = i; j < 3; ++j) {
            const double expected = i == j ? 1.0 : 0.0;
            if (!(std::abs(KDL::dot(column(r, i), column(r, j)) - expected) <=
                  kRotationTolerance)) {
                return false;
            }
        }
    }
    const double det = KDL::dot(column(r, 0) * column(r, 1), column(r, 2));
    return std::abs(det - 1.0) <= kRotationTolerance;
}

// A grip point frame moved by `offset` (base frame), keeping its orientation.
KDL::Frame shifted(const KDL::Frame& grip, const KDL::Vector& offset) {
    return {grip.M, grip.p + offset};
}

}  // namespace

std::optional<GraspPlan> planGrasp(const GraspRequest& request, std::string* why) {
    const bool vacuum = request.type == GripPointType::Vacuum;
    if (!vacuum && request.type != GripPointType::Parallel) {
        return refuse(why, "only vacuum and parallel grip points can be planned");
    }
    const std::array<double, 3> size{request.size.x, request.size.y, request.size.z};
    for (double edge : size) {
        if (!std::isfinite(edge) || edge <= 0) {
            return refuse(why, "every edge of the box must be positive (" + number(size[0]) +
                                   " x " + number(size[1]) + " x " + number(size[2]) + " m)");
        }
    }
    const double d = request.approachDistance;
    if (!std::isfinite(d) || d < 0) {
        return refuse(why, "the approach distance must not be negative (" + number(d) + " m)");
    }
    if (!std::isfinite(request.maxOpening) || request.maxOpening < 0) {
        return refuse(
            why, "the maximum opening must not be negative (" + number(request.maxOpening) + " m)");
    }
    const std::array<std::pair<const char*, const KDL::Frame*>, 3> frames{{
        {"object pose", &request.objectPose},
        {"grip point offset", &request.gripPointOffset},
        {"place position", &request.placePosition},
    }};
    for (const auto& [name, frame] : frames) {
        if (!isFinite(*frame)) return refuse(why, std::string("the ") + name + " is not finite");
        if (!proper(frame->M)) {
            return refuse(why, std::string("the ") + name + "'s rotation is not a proper rotation");
        }
    }

    // The top face: the box axis closest to base +z (or -z), with the sign that makes it
    // point up.
    const KDL::Frame& object = request.objectPose;
    int up = 0;
    double upDot = 0;
    for (int i = 0; i < 3; ++i) {
        const double dz = column(object.M, i).z();
        if (std::abs(dz) > std::abs(upDot)) {
            up = i;
            upDot = dz;
        }
    }
    if (std::abs(upDot) < std::cos(kMaxTopFaceTilt)) {
        const double tilt = std::acos(std::min(1.0, std::abs(upDot))) * 180 / std::numbers::pi;
        return refuse(why, "the box is tilted by " + number(tilt) + " degrees; no face is within " +
                               number(kMaxTopFaceTilt * 180 / std::numbers::pi) +
                               " degrees of horizontal");
    }
    const KDL::Vector normal = column(object.M, up) * (upDot > 0 ? 1.0 : -1.0);
    const KDL::Vector baseUp(0, 0, 1);

    GraspPlan plan;
    KDL::Frame grip, approach, retreat;
    if (vacuum) {
        const KDL::Vector z = -normal;
        const KDL::Vector x = column(object.M, up == 0 ? 1 : 0);
        grip = KDL::Frame(KDL::Rotation(x, z * x, z), object.p + normal * (size[up] / 2));
        approach = shifted(grip, -d * z);
        retreat = approach;
    } else {
        // The two horizontal axes; on a tie the lower-numbered one is the narrow one.
        const int a = up == 0 ? 1 : 0;
        const int b = up == 2 ? 1 : 2;
        const int narrow = size[a] <= size[b] ? a : b;
        const int wide = narrow == a ? b : a;
        plan.width = size[narrow];
        if (request.maxOpening > 0 && plan.width > request.maxOpening) {
            return refuse(why, "the box is " + number(plan.width) +
                                   " m wide between the fingers; they open to " +
                                   number(request.maxOpening) + " m");
        }
        KDL::Vector z = column(object.M, wide);
        const bool flip = std::abs(z.x()) > kSideTie ? z.x() < 0 : z.y() < 0;
        if (flip) z = -z;
        // x is the top face's normal (up): with y = z * x the frame is right-handed.
        grip = KDL::Frame(KDL::Rotation(normal, z * normal, z), object.p);
        approach = shifted(grip, -d * z);
        retreat = shifted(grip, d * baseUp);
    }

    // Held, the object stays where it is relative to the grip point.
    const KDL::Frame objectInGrip = grip.Inverse() * object;
    const KDL::Frame placeGrip = request.placePosition * objectInGrip.Inverse();
    const KDL::Frame placeApproach =
        vacuum ? shifted(placeGrip, -d * placeGrip.M.UnitZ()) : shifted(placeGrip, d * baseUp);

    const KDL::Frame toFlange = request.gripPointOffset.Inverse();
    plan.approach = approach * toFlange;
    plan.grasp = grip * toFlange;
    plan.retreat = retreat * toFlange;
    plan.placeApproach = placeApproach * toFlange;
    plan.place = placeGrip * toFlange;
    plan.placeRetreat = plan.placeApproach;
    return plan;
}

GraspPlan planCarryOn(const KDL::Frame& flange, const GraspRequest& request) {
    const double d = request.approachDistance;
    const KDL::Vector baseUp(0, 0, 1);
    const KDL::Frame grip = flange * request.gripPointOffset;
    const KDL::Frame objectInGrip = grip.Inverse() * request.objectPose;
    const KDL::Frame placeGrip = request.placePosition * objectInGrip.Inverse();
    const KDL::Frame placeApproach = request.type == GripPointType::Vacuum
                                         ? shifted(placeGrip, -d * placeGrip.M.UnitZ())
                                         : shifted(placeGrip, d * baseUp);
    const KDL::Frame toFlange = request.gripPointOffset.Inverse();
    GraspPlan plan;
    plan.approach = flange;
    plan.grasp = flange;
    plan.retreat = shifted(grip, d * baseUp) * toFlange;
    plan.placeApproach = placeApproach * toFlange;
    plan.place = placeGrip * toFlange;
    plan.placeRetreat = plan.placeApproach;
    return plan;
}

std::vector<std::pair<std::string, KDL::Frame>> steps(const GraspPlan& plan) {
    return {{"approach", plan.approach}, {"grasp", plan.grasp},
            {"retreat", plan.retreat},   {"place-approach", plan.placeApproach},
            {"place", plan.place},       {"place-retreat", plan.placeRetreat}};
}

}  // namespace skillcell::devices::pickplace
