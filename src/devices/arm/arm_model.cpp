#include "devices/arm/arm_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace skillcell::devices {
namespace {

constexpr double kPi = std::numbers::pi;

double degrees(double d) {
    return d * kPi / 180;
}

struct Dh {
    double a, alpha, d;
};

KDL::Chain chainOf(const std::vector<Dh>& dh) {
    KDL::Chain chain;
    for (const Dh& j : dh) {
        chain.addSegment(
            KDL::Segment(KDL::Joint(KDL::Joint::RotZ), KDL::Frame::DH(j.a, j.alpha, j.d, 0)));
    }
    return chain;
}

}  // namespace

JointBounds JointBounds::uniform(std::size_t joints, double lo, double hi) {
    return {Joints(joints, lo), Joints(joints, hi)};
}

bool JointBounds::contains(const Joints& q, double tolerance) const {
    if (q.size() != lower.size()) return false;
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (q[i] < lower[i] - tolerance || q[i] > upper[i] + tolerance) return false;
    }
    return true;
}

JointBounds JointBounds::intersect(const JointBounds& other) const {
    JointBounds b = *this;
    for (std::size_t i = 0; i < b.size() && i < other.size(); ++i) {
        b.lower[i] = std::max(lower[i], other.lower[i]);
        b.upper[i] = std::min(upper[i], other.upper[i]);
    }
    return b;
}

ArmModel ArmModel::ur5() {
    ArmModel m;
    m.name = "UR5";
    m.manufacturer = "Universal Robots";
    m.model = "UR5";
    m.productCode = "UR5";
    m.axes = {"Base", "Shoulder", "Elbow", "Wrist1", "Wrist2", "Wrist3"};
    m.chain = chainOf({{0, kPi / 2, 0.089159},
                       {-0.425, 0, 0},
                       {-0.39225, 0, 0},
                       {0, kPi / 2, 0.10915},
                       {0, -kPi / 2, 0.09465},
                       {0, 0, 0.0823}});
    m.bounds = JointBounds::uniform(6, -2 * kPi, 2 * kPi);
    m.home = {0, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0};
    m.shoulder = KDL::Vector(0, 0, 0.089159);
    m.reach = 0.425 + 0.39225 + 0.10915 + 0.09465 + 0.0823;
    return m;
}

ArmModel ArmModel::lbrIiwa7() {
    ArmModel m;
    m.name = "LBRiiwa7";
    m.manufacturer = "KUKA";
    m.model = "LBR iiwa 7 R800";
    m.productCode = "LBR iiwa 7 R800";
    m.axes = {"A1", "A2", "A3", "A4", "A5", "A6", "A7"};
    m.chain = chainOf({{0, -kPi / 2, 0.34},
                       {0, kPi / 2, 0},
                       {0, kPi / 2, 0.4},
                       {0, -kPi / 2, 0},
                       {0, -kPi / 2, 0.4},
                       {0, kPi / 2, 0},
                       {0, 0, 0.126}});
    const double limits[] = {170, 120, 170, 120, 170, 120, 175};
    for (double l : limits) {
        m.bounds.lower.push_back(-degrees(l));
        m.bounds.upper.push_back(degrees(l));
    }
    // Shoulder forward, elbow bent, wrist bent back: the flange points down in front.
    m.home = {0, degrees(30), 0, degrees(-90), 0, degrees(60), 0};
    m.shoulder = KDL::Vector(0, 0, 0.34);
    m.reach = 0.4 + 0.4 + 0.126;
    // The LBR's own defaults are gentler than the UR5's (a collaborative arm near people).
    m.defaults.linearVelocity = 0.2;
    m.defaults.linearAcceleration = 1.0;
    m.defaults.jointVelocity = 1.0;
    m.defaults.jointAcceleration = 1.2;
    m.sensesForce = true;  // a torque sensor in every axis
    return m;
}

}  // namespace skillcell::devices
