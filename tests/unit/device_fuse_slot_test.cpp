// Blade fuses and a fuse box's slots, in the world model alone: the force a fuse meets as it
// enters a slot (small and flat while its blades are in the terminals, steep once it bottoms
// out, steep at once when it is beside them or turned), and the World following a held fuse
// into a slot, seating it when released at the slot's depth and not otherwise.
#include <gtest/gtest.h>

#include <cmath>

#include "devices/common/frame.hpp"
#include "devices/world/fuse_slot.hpp"
#include "devices/world/world.hpp"

namespace skillcell::devices::device_fuse_slot_test {
namespace {

// The robot whose flange the tests move (the world has it by this id).
const std::string kArm = "arm";

using ua::status::BadInvalidArgument;
using ua::status::BadNodeIdExists;
using ua::status::Good;

constexpr BoxSize kAto{0.0191, 0.0051, 0.0185};  // an ATO blade fuse, blades included

FuseSlot slot() {
    // On the fuse box's top face, 5 cm above the table, facing up.
    FuseSlot s;
    s.id = "F1";
    s.pose = toFrame(Pose6{0.5, 0.2, 0.05});
    return s;
}

/// The fuse's pose with its blade tips `depth` below the slot's opening, moved `offset`
/// sideways and turned by `skew` about the slot's z.
KDL::Frame fuseAt(const FuseSlot& s, double depth, double offset = 0, double skew = 0) {
    return s.pose *
           KDL::Frame(KDL::Rotation::RotZ(skew), KDL::Vector(offset, 0, kAto.z / 2 - depth));
}

TEST(FuseSlot, AnAlignedFuseMeetsTheTerminalsThenTheBottom) {
    const FuseSlot s = slot();
    EXPECT_FALSE(slotContact(s, fuseAt(s, -0.001), kAto));       // above the opening
    EXPECT_FALSE(slotContact(s, fuseAt(s, 0.003, 0.02), kAto));  // beside this slot

    const auto sliding = slotContact(s, fuseAt(s, 0.003), kAto);
    ASSERT_TRUE(sliding);
    EXPECT_TRUE(sliding->aligned);
    EXPECT_NEAR(sliding->depth, 0.003, 1e-12);
    EXPECT_NEAR(sliding->force, kTerminalFriction, 1e-9);
    EXPECT_FALSE(sliding->seated(s));

    const auto seated = slotContact(s, fuseAt(s, s.depth), kAto);
    ASSERT_TRUE(seated);
    EXPECT_TRUE(seated->seated(s));
    EXPECT_NEAR(seated->force, kTerminalFriction, 1e-9);
    // Pushed 0.2 mm further: the box pushes back.
    const auto pressed = slotContact(s, fuseAt(s, s.depth + 0.0002), kAto);
    ASSERT_TRUE(pressed);
    EXPECT_NEAR(pressed->force, kTerminalFriction + kBottomStiffness * 0.0002, 1e-6);
    // Within the terminals' play it is still aligned.
    EXPECT_TRUE(slotContact(s, fuseAt(s, 0.003, 0.0003), kAto)->aligned);
    EXPECT_TRUE(near(seatedPose(s, kAto), fuseAt(s, s.depth), 1e-12, 1e-12));
}

TEST(FuseSlot, AMisalignedOrTurnedFuseMeetsTheBoxFace) {
    const FuseSlot s = slot();
    const auto beside = slotContact(s, fuseAt(s, 0.0005, 0.001), kAto);  // 1 mm off
    ASSERT_TRUE(beside);
    EXPECT_FALSE(beside->aligned);
    EXPECT_NEAR(beside->misalignment, 0.001, 1e-12);
    EXPECT_NEAR(beside->force, kFaceStiffness * 0.0005, 1e-9);  // 15 N at half a millimetre
    EXPECT_FALSE(beside->seated(s));

    const auto turned = slotContact(s, fuseAt(s, 0.0005, 0, 10 * M_PI / 180), kAto);
    ASSERT_TRUE(turned);
    EXPECT_FALSE(turned->aligned);
    // Turned by half a turn it is the same fuse: the blades still meet the terminals.
    EXPECT_TRUE(slotContact(s, fuseAt(s, 0.003, 0, M_PI), kAto)->aligned);
}

TEST(FuseSlot, ASlotOutOfToleranceIsMetWhereItReallyIs) {
    FuseSlot s = slot();
    s.misalignment = KDL::Vector(0.0015, 0, 0);  // the terminals 1.5 mm off the drawing
    // A fuse aligned with the drawing meets the box's face...
    const auto drawn = slotContact(s, fuseAt(s, 0.0005), kAto);
    ASSERT_TRUE(drawn);
    EXPECT_FALSE(drawn->aligned);
    EXPECT_NEAR(drawn->force, kFaceStiffness * 0.0005, 1e-9);
    // ...one aligned with the terminals goes in, and is seated where they are.
    const auto real = slotContact(s, fuseAt(s, 0.003, 0.0015), kAto);
    ASSERT_TRUE(real);
    EXPECT_TRUE(real->aligned);
    EXPECT_TRUE(near(seatedPose(s, kAto), fuseAt(s, s.depth, 0.0015), 1e-12, 1e-12));
}

// A world with the slot, a tool 0.15 m below the flange, mounted, and a fuse in a tray.
World cell() {
    World w;
    EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
    EXPECT_EQ(w.addFuseSlot(slot()), Good);
    EXPECT_EQ(w.addDock({"dock", toFrame(Pose6{0.0, -0.4, 0.3, M_PI, 0, 0}), {}}), Good);
    EXPECT_EQ(w.addTool({"gripper", toFrame(Pose6{0, 0, 0.15})}, "dock"), Good);
    w.setFlangePose(kArm, toFrame(Pose6{0.0, -0.4, 0.3, M_PI, 0, 0}));
    EXPECT_EQ(w.mountTool(kArm, "dock"), Good);
    EXPECT_EQ(w.addObject({"fuse1", kAto, toFrame(Pose6{0.3, 0.1, kAto.z / 2}), ObjectKind::Fuse}),
              Good);
    return w;
}

// The flange pose holding the fuse at `fusePose`, gripped from the top at its centre.
KDL::Frame flangeFor(const World& w, const KDL::Frame& fusePose) {
    const KDL::Frame gripInFuse(KDL::Rotation::RotX(M_PI), KDL::Vector::Zero());
    return fusePose * gripInFuse * w.tools().at("gripper").gripPoint.Inverse();
}

TEST(FuseSlot, TheWorldSeatsAFuseReleasedAtTheSlotsDepth) {
    World w = cell();
    w.setFlangePose(kArm, flangeFor(w, w.object("fuse1")->pose));
    ASSERT_EQ(w.grasp(kArm, "fuse1"), Good);
    const FuseSlot s = slot();
    w.setFlangePose(kArm, flangeFor(w, fuseAt(s, -0.01)));
    EXPECT_EQ(w.contactForce(kArm), 0);
    for (double depth : {0.001, 0.004, 0.008}) {
        w.setFlangePose(kArm, flangeFor(w, fuseAt(s, depth)));
        ASSERT_TRUE(w.flange(kArm).fuseContact) << depth;
        EXPECT_EQ(w.flange(kArm).fuseContact->first, "F1");
        EXPECT_NEAR(w.contactForce(kArm), kTerminalFriction, 1e-6) << depth;
    }
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_EQ(w.seatedFuses().at("fuse1"), "F1");
    EXPECT_TRUE(near(w.object("fuse1")->pose, seatedPose(s, kAto), 1e-9, 1e-9));
    EXPECT_EQ(w.contactForce(kArm), 0);

    // Taken again, it comes out of the slot.
    ASSERT_EQ(w.grasp(kArm, "fuse1"), Good);
    EXPECT_TRUE(w.seatedFuses().empty());
}

TEST(FuseSlot, AFuseStoppedOnTheFaceIsNotSeated) {
    World w = cell();
    w.setFlangePose(kArm, flangeFor(w, w.object("fuse1")->pose));
    ASSERT_EQ(w.grasp(kArm, "fuse1"), Good);
    const FuseSlot s = slot();
    w.setFlangePose(kArm, flangeFor(w, fuseAt(s, 0.0007, 0.0015)));  // 1.5 mm beside the terminals
    ASSERT_TRUE(w.flange(kArm).fuseContact);
    EXPECT_FALSE(w.flange(kArm).fuseContact->second.aligned);
    EXPECT_NEAR(w.contactForce(kArm), kFaceStiffness * 0.0007, 1e-6);
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_TRUE(w.seatedFuses().empty());
}

TEST(FuseSlot, ASlotNeedsAnIdADepthAndAClearanceOfItsOwn) {
    World w;
    EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
    FuseSlot s = slot();
    s.id.clear();
    EXPECT_EQ(w.addFuseSlot(s), BadInvalidArgument);
    s = slot();
    s.depth = 0;
    EXPECT_EQ(w.addFuseSlot(s), BadInvalidArgument);
    s = slot();
    s.clearance = std::nan("");
    EXPECT_EQ(w.addFuseSlot(s), BadInvalidArgument);
    EXPECT_EQ(w.addObject({"box", {0.1, 0.1, 0.1}, {}}), Good);
    s = slot();
    s.id = "box";
    std::string why;
    EXPECT_EQ(w.addFuseSlot(s, &why), BadNodeIdExists);
    EXPECT_NE(why.find("taken"), std::string::npos);
}

}  // namespace
}  // namespace skillcell::devices::device_fuse_slot_test
