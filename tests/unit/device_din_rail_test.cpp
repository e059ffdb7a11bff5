// Terminal blocks on a DIN rail, in the world model alone: the rail's geometry (the hooked
// and mounted poses, the contact a pose makes), and the World following a held block as it
// is hooked over the upper edge and rotated down until it snaps; refusing a block rotated
// down over another one, and one pressed down flat without hooking first.
#include <gtest/gtest.h>

#include <cmath>

#include "devices/common/frame.hpp"
#include "devices/world/din_rail.hpp"
#include "devices/world/world.hpp"

namespace skillcell::devices::device_din_rail_test {
namespace {

// The robot whose flange the tests move (the world has it by this id).
const std::string kArm = "arm";

using ua::status::BadInvalidArgument;
using ua::status::BadNodeIdExists;
using ua::status::Good;

constexpr BoxSize kBlock{0.0052, 0.045, 0.035};  // a 2.5 mm2 feed-through terminal block

DinRail rail() {
    // Lying on the table along the base's x axis, its upper edge towards +y.
    return DinRail{"rail1", toFrame(Pose6{0.4, 0.3, 0.0}), 0.2, kTs35Width};
}

// A world with a rail, a tool whose grip point is 0.15 m below the flange, mounted (so the
// flange may grasp), and blocks in a tray.
World cell(int blocks = 2) {
    World w;
    EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
    EXPECT_EQ(w.addRail(rail()), Good);
    EXPECT_EQ(w.addDock({"dock", toFrame(Pose6{0.0, -0.4, 0.3, M_PI, 0, 0}), {}}), Good);
    EXPECT_EQ(w.addTool({"gripper", toFrame(Pose6{0, 0, 0.15})}, "dock"), Good);
    w.setFlangePose(kArm, toFrame(Pose6{0.0, -0.4, 0.3, M_PI, 0, 0}));
    EXPECT_EQ(w.mountTool(kArm, "dock"), Good);
    for (int i = 0; i < blocks; ++i) {
        const std::string id = "tb" + std::to_string(i + 1);
        EXPECT_EQ(w.addObject({id, kBlock, toFrame(Pose6{0.3 + 0.02 * i, -0.1, kBlock.z / 2}),
                               ObjectKind::TerminalBlock}),
                  Good);
    }
    return w;
}

// The flange pose that holds a block at `blockPose`, gripped from the top at its centre.
KDL::Frame flangeFor(const World& w, const KDL::Frame& blockPose) {
    const KDL::Frame gripInBlock(KDL::Rotation::RotX(M_PI), KDL::Vector::Zero());
    return blockPose * gripInBlock * w.tools().at("gripper").gripPoint.Inverse();
}

// Grasps `id` where it stands.
void pick(World& w, const std::string& id) {
    w.setFlangePose(kArm, flangeFor(w, w.object(id)->pose));
    ASSERT_EQ(w.grasp(kArm, id), Good);
}

// Hooks the held block at `position`, then rotates it down in `steps` steps.
void hookAndRotateDown(World& w, const std::string& id, double position, int steps = 3) {
    const DinRail r = rail();
    for (int i = 0; i <= steps; ++i) {
        const double tilt = kHookTilt * (steps - i) / steps;
        w.setFlangePose(kArm, flangeFor(w, hookedPose(r, position, kBlock, tilt)));
        ASSERT_TRUE(w.flange(kArm).hooked.has_value()) << id << " left the rail at step " << i;
        EXPECT_NEAR(w.flange(kArm).hooked->position, position, 1e-9);
    }
    (void)id;
}

TEST(DinRail, TheHookedPoseRestsTheUpperFootOnTheEdgeAndTheMountedOneLiesFlat) {
    const DinRail r = rail();
    const KDL::Frame flat = mountedPose(r, 0.05, kBlock);
    EXPECT_TRUE(near(flat, toFrame(Pose6{0.45, 0.3, kBlock.z / 2}), 1e-12, 1e-12));
    EXPECT_TRUE(near(hookedPose(r, 0.05, kBlock, 0), flat, 1e-12, 1e-12));

    const KDL::Frame hooked = hookedPose(r, 0.05, kBlock, kHookTilt);
    const auto contact = railContact(r, hooked, kBlock, 0.001);
    ASSERT_TRUE(contact.has_value());
    EXPECT_NEAR(contact->position, 0.05, 1e-12);
    EXPECT_NEAR(contact->tilt, kHookTilt, 1e-12);
    // The lower side is lifted off the rail, the upper foot stays on the edge.
    const KDL::Vector lowerFoot = hooked * KDL::Vector(0, -r.width / 2, -kBlock.z / 2);
    EXPECT_GT(lowerFoot.z(), 0.005);

    // Off the edge, beyond the rail's end, turned across the rail, or tilted forwards: no
    // contact.
    EXPECT_FALSE(railContact(r, KDL::Frame(KDL::Vector(0, 0, 0.01)) * hooked, kBlock, 0.001));
    EXPECT_FALSE(railContact(r, hookedPose(r, 0.199, kBlock, kHookTilt), kBlock, 0.001));
    EXPECT_FALSE(railContact(r, hooked * KDL::Frame(KDL::Rotation::RotZ(0.3)), kBlock, 0.001));
    EXPECT_FALSE(railContact(r, hookedPose(r, 0.05, kBlock, -0.2), kBlock, 0.001));

    EXPECT_TRUE(spansOverlap(0.0, 0.0052, 0.005, 0.0052, 0.0001));
    EXPECT_FALSE(spansOverlap(0.0, 0.0052, 0.0052, 0.0052, 0.0001));  // side by side
}

TEST(DinRail, ARailNeedsAnIdAndALengthOfItsOwn) {
    World w;
    EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
    EXPECT_EQ(w.addRail({"", {}, 0.2}), BadInvalidArgument);
    EXPECT_EQ(w.addRail({"r", {}, 0}), BadInvalidArgument);
    EXPECT_EQ(w.addRail({"r", {}, std::nan("")}), BadInvalidArgument);
    EXPECT_EQ(w.addObject({"box", {0.1, 0.1, 0.1}, {}}), Good);
    std::string why;
    EXPECT_EQ(w.addRail({"box", {}, 0.2}, &why), BadNodeIdExists);
    EXPECT_NE(why.find("taken"), std::string::npos);
}

TEST(DinRail, ABlockHookedAndRotatedDownSnapsAndStaysMountedWhenReleased) {
    World w = cell();
    pick(w, "tb1");
    hookAndRotateDown(w, "tb1", 0.0026);
    EXPECT_TRUE(w.flange(kArm).snapped) << w.flange(kArm).railRefusal;
    ASSERT_EQ(w.release(kArm), Good);
    ASSERT_TRUE(w.railMounts().contains("tb1"));
    EXPECT_EQ(w.railMounts().at("tb1").rail, "rail1");
    EXPECT_NEAR(w.railMounts().at("tb1").position, 0.0026, 1e-9);
    EXPECT_TRUE(near(w.object("tb1")->pose, mountedPose(rail(), 0.0026, kBlock), 1e-9, 1e-9));

    // The next block side by side, at the first one's width.
    pick(w, "tb2");
    hookAndRotateDown(w, "tb2", 0.0026 + kBlock.x);
    EXPECT_TRUE(w.flange(kArm).snapped) << w.flange(kArm).railRefusal;
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_EQ(w.railMounts().size(), 2u);

    // Grasped again, a block comes off the rail.
    pick(w, "tb2");
    EXPECT_FALSE(w.railMounts().contains("tb2"));
}

TEST(DinRail, ABlockRotatedDownOverAnotherDoesNotSnap) {
    World w = cell();
    pick(w, "tb1");
    hookAndRotateDown(w, "tb1", 0.01);
    ASSERT_EQ(w.release(kArm), Good);

    pick(w, "tb2");
    hookAndRotateDown(w, "tb2", 0.012);  // 2 mm into tb1's span
    EXPECT_FALSE(w.flange(kArm).snapped);
    EXPECT_NE(w.flange(kArm).railRefusal.find("would sit over terminal block tb1 at 10.0 mm"),
              std::string::npos)
        << w.flange(kArm).railRefusal;
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_FALSE(w.railMounts().contains("tb2"));
    EXPECT_EQ(w.railMounts().size(), 1u);
}

TEST(DinRail, ABlockPressedDownFlatWithoutHookingDoesNotSnap) {
    World w = cell();
    pick(w, "tb1");
    const KDL::Frame flat = mountedPose(rail(), 0.05, kBlock);
    w.setFlangePose(kArm, flangeFor(w, KDL::Frame(KDL::Vector(0, 0, 0.03)) * flat));  // above
    EXPECT_FALSE(w.flange(kArm).hooked.has_value());
    w.setFlangePose(kArm, flangeFor(w, flat));
    EXPECT_FALSE(w.flange(kArm).snapped);
    EXPECT_NE(w.flange(kArm).railRefusal.find("without hooking"), std::string::npos)
        << w.flange(kArm).railRefusal;
    // Reported again there, and pressed 1 mm further: still not.
    w.setFlangePose(kArm, flangeFor(w, flat));
    EXPECT_FALSE(w.flange(kArm).snapped);
    w.setFlangePose(kArm, flangeFor(w, KDL::Frame(KDL::Vector(0, 0, -0.001)) * flat));
    EXPECT_FALSE(w.flange(kArm).snapped);
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_TRUE(w.railMounts().empty());
}

TEST(DinRail, ABoxIsNoTerminalBlock) {
    World w = cell(0);
    ASSERT_EQ(w.addObject({"box", kBlock, toFrame(Pose6{0.3, -0.1, kBlock.z / 2})}), Good);
    pick(w, "box");
    const DinRail r = rail();
    w.setFlangePose(kArm, flangeFor(w, hookedPose(r, 0.05, kBlock, kHookTilt)));
    EXPECT_FALSE(w.flange(kArm).hooked.has_value());
    w.setFlangePose(kArm, flangeFor(w, mountedPose(r, 0.05, kBlock)));
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_TRUE(w.railMounts().empty());
}

}  // namespace
}  // namespace skillcell::devices::device_din_rail_test
