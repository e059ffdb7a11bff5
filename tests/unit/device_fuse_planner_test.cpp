// Planning a fuse insertion (fuse_planner.hpp), checked against the world's own physics
// (fuse_slot.hpp): the fuse, carried by the planned flange poses, is seated at the insertion's
// end and clear of the slot before it; the wrist takes the shorter way round; and what cannot
// be inserted is refused with its reason.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "devices/common/frame.hpp"
#include "devices/pickplace/fuse_planner.hpp"

namespace skillcell::devices::pickplace::fuse_planner_test {
namespace {

constexpr BoxSize kAto{0.0191, 0.0051, 0.0185};
constexpr double kPi = std::numbers::pi;

FuseInsertionRequest request(double fuseYaw = kPi) {
    FuseInsertionRequest r;
    r.size = kAto;
    r.fusePose = toFrame(Pose6{0.45, -0.05, kAto.z / 2, 0, 0, fuseYaw});  // in its tray
    r.gripPointOffset = KDL::Frame(KDL::Vector(0, 0, 0.15));
    r.type = GripPointType::Parallel;
    r.maxOpening = 0.085;
    r.slotPose = toFrame(Pose6{0.45, 0.25, 0.06});
    r.slotDepth = 0.008;
    return r;
}

/// Where the fuse is when the flange is at `flange`, held as it was gripped at `grasp`.
KDL::Frame carried(const FuseInsertionRequest& r, const KDL::Frame& grasp,
                   const KDL::Frame& flange) {
    return flange * (grasp.Inverse() * r.fusePose);
}

double angle(const KDL::Rotation& a, const KDL::Rotation& b) {
    KDL::Vector axis;
    return (a.Inverse() * b).GetRotAngle(axis);
}

TEST(FusePlanner, TheFuseCarriedByThePlanIsSeatedAtTheEndAndClearBefore) {
    const FuseInsertionRequest r = request();
    std::string why;
    const auto plan = planFuseInsertion(r, &why);
    ASSERT_TRUE(plan) << why;
    // Gripped from the top, on its body: the grip point a quarter of its height above its
    // centre, pointing down, the fingers (its y) across the fuse's thickness.
    const KDL::Frame grip = plan->grasp * r.gripPointOffset;
    EXPECT_NEAR((grip.p - r.fusePose.p).z(), kAto.z / 4, 1e-12);
    EXPECT_NEAR(grip.M.UnitZ().z(), -1, 1e-12);
    EXPECT_NEAR(std::abs(KDL::dot(grip.M.UnitY(), r.fusePose.M.UnitY())), 1, 1e-12);
    EXPECT_DOUBLE_EQ(plan->thickness, kAto.y);
    // Approach and retreat straight above it.
    EXPECT_TRUE(near(plan->approach,
                     KDL::Frame(plan->grasp.M, plan->grasp.p + KDL::Vector(0, 0, 0.05)), 1e-12,
                     1e-12));
    EXPECT_TRUE(near(plan->retreat, plan->approach, 1e-12, 1e-12));

    FuseSlot slot;
    slot.pose = r.slotPose;
    slot.depth = r.slotDepth;
    const auto seated = slotContact(slot, carried(r, plan->grasp, plan->insert), kAto);
    ASSERT_TRUE(seated);
    EXPECT_TRUE(seated->aligned);
    EXPECT_TRUE(seated->seated(slot));
    EXPECT_NEAR(seated->force, kTerminalFriction, 1e-6);  // seated, not pressed
    // Before the force-limited move, and after the release, the blades are out of the slot.
    for (const KDL::Frame& f : {plan->preInsert, plan->insertApproach, plan->insertRetreat}) {
        EXPECT_FALSE(slotContact(slot, carried(r, plan->grasp, f), kAto));
    }
    // The insertion is a straight line along the slot's axis.
    const KDL::Vector way = plan->preInsert.p - plan->insert.p;
    EXPECT_NEAR(way.Norm(), r.slotDepth + kPreInsertGap, 1e-12);
    EXPECT_NEAR(KDL::dot(way / way.Norm(), r.slotPose.M.UnitZ()), 1, 1e-12);
    EXPECT_NEAR(angle(plan->preInsert.M, plan->insert.M), 0, 1e-12);
}

TEST(FusePlanner, TheWristTakesTheShorterWayRound) {
    // The fuse is symmetric: turned half round in its tray or not, it is inserted so that the
    // flange turns by at most a quarter turn between the grasp and the insertion.
    for (double yaw : {0.0, kPi / 3, kPi, -2 * kPi / 3}) {
        const auto plan = planFuseInsertion(request(yaw));
        ASSERT_TRUE(plan);
        EXPECT_LE(angle(plan->grasp.M, plan->insert.M), kPi / 2 + 1e-9) << "yaw " << yaw;
    }
}

TEST(FusePlanner, WhatCannotBeInsertedIsRefusedWithItsReason) {
    auto refused = [](FuseInsertionRequest r) {
        std::string why;
        EXPECT_FALSE(planFuseInsertion(r, &why));
        return why;
    };
    FuseInsertionRequest vacuum = request();
    vacuum.type = GripPointType::Vacuum;
    EXPECT_NE(refused(vacuum).find("parallel fingers"), std::string::npos);

    FuseInsertionRequest tilted = request();
    tilted.fusePose = toFrame(Pose6{0.45, -0.05, 0.01, 0.5, 0, 0});
    EXPECT_NE(refused(tilted).find("tilted by 28.6 degrees"), std::string::npos);

    FuseInsertionRequest narrow = request();
    narrow.maxOpening = 0.004;
    EXPECT_EQ(refused(narrow), "the fuse is 5.1 mm thick; the fingers open to 4.0 mm");

    FuseInsertionRequest shallow = request();
    shallow.slotDepth = 0;
    EXPECT_NE(refused(shallow).find("must be positive"), std::string::npos);

    FuseInsertionRequest nowhere = request();
    nowhere.slotPose.p = KDL::Vector(std::nan(""), 0, 0);
    EXPECT_NE(refused(nowhere).find("not finite"), std::string::npos);
}

}  // namespace
}  // namespace skillcell::devices::pickplace::fuse_planner_test
