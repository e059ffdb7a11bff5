// The world model: the World value on its own (scene building, consistency checks, a
// grasped object moving with the flange, a released one staying), the 3DFrame codec, and
// the OPC UA face driven through WorldLink over a real server.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <thread>

#include "devices/common/frame.hpp"
#include "devices/world/world.hpp"
#include "devices/world/world_file.hpp"
#include "devices/world/world_link.hpp"
#include "devices/world/world_nodes.hpp"
#include "running_server.hpp"
#include "temp_dir.hpp"
#include "ua/client/blocking_client.hpp"

namespace skillcell::devices::device_world_test {
namespace {

// The robot whose flange the tests move (the world has it by this id).
const std::string kArm = "arm";

using namespace std::chrono_literals;
using ua::status::BadInvalidArgument;
using ua::status::BadInvalidState;
using ua::status::BadNodeIdExists;
using ua::status::BadNotFound;
using ua::status::Good;

KDL::Frame at(double x, double y, double z, double a = 0, double b = 0, double c = 0) {
    return toFrame(Pose6{x, y, z, a, b, c});
}

// A cell: a box on the table, a dock with a gripper whose grip point is 0.15 m in front
// of the flange.
World cell() {
    World w;
    EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
    EXPECT_EQ(w.addObject({"box1", {0.04, 0.04, 0.04}, at(0.5, 0.1, 0.02)}), Good);
    EXPECT_EQ(w.addDock({"dock1", at(0.3, -0.4, 0.3, M_PI, 0, 0), {}}), Good);
    EXPECT_EQ(w.addTool({"gripper", at(0, 0, 0.15)}, "dock1"), Good);
    return w;
}

TEST(DeviceWorldFrame, ThreeDFrameRoundTripsAndRejectsOtherValues) {
    const KDL::Frame f = at(0.1, -0.2, 0.3, 0.4, -0.5, 0.6);
    const ua::Variant v = frameToVariant(f);
    const auto* eo = v.get<ua::ExtensionObject>();
    ASSERT_NE(eo, nullptr);
    EXPECT_EQ(eo->typeId, ua::NodeId(18823u));  // 3DFrame's Default Binary
    EXPECT_EQ(eo->body.size(), 48u);
    const auto back = frameFromVariant(v);
    ASSERT_TRUE(back.ok());
    EXPECT_TRUE(near(*back, f, 1e-12, 1e-12));
    const Pose6 p = toPose6(*back);
    EXPECT_NEAR(p.a, 0.4, 1e-12);
    EXPECT_NEAR(p.b, -0.5, 1e-12);
    EXPECT_NEAR(p.c, 0.6, 1e-12);

    EXPECT_EQ(frameFromVariant(ua::Variant(1.0)).status(), ua::status::BadTypeMismatch);
    ua::ExtensionObject shorter = *eo;
    shorter.body.bytes.pop_back();
    EXPECT_EQ(frameFromVariant(ua::Variant(shorter)).status(), ua::status::BadTypeMismatch);
    ua::ExtensionObject nan = *eo;
    const double q = std::nan("");
    std::memcpy(nan.body.bytes.data(), &q, sizeof q);
    EXPECT_EQ(frameFromVariant(ua::Variant(nan)).status(), ua::status::BadOutOfRange);
}

TEST(DeviceWorldFrame, ParsesPosesFromText) {
    EXPECT_EQ(parsePose6("1,2,3"), (Pose6{1, 2, 3, 0, 0, 0}));
    EXPECT_EQ(parsePose6("1, 2, 3, 0.5, 0, -1"), (Pose6{1, 2, 3, 0.5, 0, -1}));
    EXPECT_FALSE(parsePose6("1,2"));
    EXPECT_FALSE(parsePose6("1,2,3,"));
    EXPECT_FALSE(parsePose6("1,x,3"));
    EXPECT_FALSE(parsePose6("1,2,3,4"));
    EXPECT_FALSE(parsePose6("nan,2,3"));
}

TEST(DeviceWorld, SceneIdsAreUniqueAndBoxesReal) {
    World w = cell();
    std::string why;
    EXPECT_EQ(w.addObject({"box1", {0.1, 0.1, 0.1}, at(0, 0, 0)}, &why), BadNodeIdExists);
    EXPECT_EQ(w.addObject({"dock1", {0.1, 0.1, 0.1}, at(0, 0, 0)}), BadNodeIdExists);
    EXPECT_EQ(w.addObject({"flat", {0.1, 0.0, 0.1}, at(0, 0, 0)}, &why), BadInvalidArgument);
    EXPECT_NE(why.find("positive"), std::string::npos) << why;
    EXPECT_EQ(w.addObject({"", {0.1, 0.1, 0.1}, at(0, 0, 0)}), BadInvalidArgument);
    EXPECT_EQ(w.addTool({"other", at(0, 0, 0)}, "dock1"), BadInvalidState);  // occupied
    EXPECT_EQ(w.addTool({"other", at(0, 0, 0)}, "nowhere"), BadNotFound);
    EXPECT_EQ(w.objects().size(), 1u);
    EXPECT_EQ(w.docks().at("dock1").tool, "gripper");
}

TEST(DeviceWorld, ToolsAreTakenAndLeftOnlyAtTheirDock) {
    World w = cell();
    std::string why;
    EXPECT_EQ(w.mountTool(kArm, "dock1", &why), BadInvalidState);  // the flange is elsewhere
    EXPECT_NE(why.find("not at dock"), std::string::npos) << why;
    w.setFlangePose(kArm, at(0.3, -0.4, 0.302, M_PI, 0, 0));  // within the 5 mm tolerance
    EXPECT_EQ(w.mountTool(kArm, "dock1"), Good);
    EXPECT_EQ(w.flange(kArm).tool, "gripper");
    EXPECT_TRUE(w.docks().at("dock1").tool.empty());
    EXPECT_EQ(w.mountTool(kArm, "dock1"), BadInvalidState);  // one tool at a time
    // The grip point follows the tool's offset: 0.15 m along the flange's z (pointing down).
    EXPECT_NEAR(w.gripPoint(kArm).p.z(), 0.302 - 0.15, 1e-9);

    w.setFlangePose(kArm, at(0, 0, 0.5));
    EXPECT_EQ(w.unmountTool(kArm, "dock1"), BadInvalidState);  // not at the dock
    w.setFlangePose(kArm, at(0.3, -0.4, 0.3, M_PI, 0, 0));
    EXPECT_EQ(w.unmountTool(kArm, "nowhere"), BadNotFound);
    EXPECT_EQ(w.unmountTool(kArm, "dock1"), Good);
    EXPECT_TRUE(w.flange(kArm).tool.empty());
    EXPECT_EQ(w.docks().at("dock1").tool, "gripper");
    EXPECT_EQ(w.unmountTool(kArm, "dock1"), BadInvalidState);  // nothing mounted
}

TEST(DeviceWorld, APersonMovesAStoredToolToAFreeDockButNotAMountedOne) {
    World w = cell();
    std::string why;
    ASSERT_EQ(w.addDock({"shelf", at(0.6, -0.4, 0.3, M_PI, 0, 0), {}}), Good);
    ASSERT_EQ(w.addDock({"shelf2", at(0.7, -0.4, 0.3, M_PI, 0, 0), {}}), Good);
    ASSERT_EQ(w.addTool({"other", at(0, 0, 0.16)}, "shelf"), Good);
    EXPECT_EQ(w.moveTool("gripper", "shelf", &why), BadInvalidState);  // occupied
    EXPECT_NE(why.find("holds tool other"), std::string::npos) << why;
    EXPECT_EQ(w.moveTool("nothing", "shelf2"), BadNotFound);
    EXPECT_EQ(w.moveTool("gripper", "nowhere"), BadNotFound);
    // The swap: the gripper out of dock1, the other model in.
    const auto before = w.revision();
    EXPECT_EQ(w.moveTool("gripper", "shelf2"), Good);
    EXPECT_EQ(w.moveTool("other", "dock1"), Good);
    EXPECT_GT(w.revision(), before);
    EXPECT_EQ(w.docks().at("dock1").tool, "other");
    EXPECT_EQ(w.docks().at("shelf2").tool, "gripper");
    EXPECT_TRUE(w.docks().at("shelf").tool.empty());
    // The changer now takes the other model from dock1, with its own grip point.
    w.setFlangePose(kArm, at(0.3, -0.4, 0.3, M_PI, 0, 0));
    ASSERT_EQ(w.mountTool(kArm, "dock1"), Good);
    EXPECT_EQ(w.flange(kArm).tool, "other");
    EXPECT_NEAR(w.gripPoint(kArm).p.z(), 0.3 - 0.16, 1e-9);
    EXPECT_EQ(w.moveTool("other", "shelf", &why), BadInvalidState);  // mounted
    EXPECT_NE(why.find("mounted"), std::string::npos) << why;
}

TEST(DeviceWorld, AGraspedObjectMovesWithTheFlangeAndAReleasedOneStays) {
    World w = cell();
    std::string why;
    EXPECT_EQ(w.grasp(kArm, "box1", &why), BadInvalidState);  // no tool
    w.setFlangePose(kArm, at(0.3, -0.4, 0.3, M_PI, 0, 0));
    ASSERT_EQ(w.mountTool(kArm, "dock1"), Good);
    EXPECT_EQ(w.grasp(kArm, "box1", &why), BadInvalidState);  // not at the grip point
    EXPECT_NE(why.find("grip point"), std::string::npos) << why;
    EXPECT_EQ(w.grasp(kArm, "nothing"), BadNotFound);

    // Flange pointing down, 0.15 m above the box centre: the grip point is in the box.
    w.setFlangePose(kArm, at(0.5, 0.1, 0.17, M_PI, 0, 0));
    EXPECT_EQ(w.objectAt(w.gripPoint(kArm).p), std::optional<std::string>("box1"));
    ASSERT_EQ(w.grasp(kArm, "box1"), Good);
    EXPECT_EQ(w.flange(kArm).held, "box1");
    EXPECT_EQ(w.grasp(kArm, "box1"), BadInvalidState);
    EXPECT_FALSE(w.objectAt(w.gripPoint(kArm).p));  // a held object is not "on the table"

    // Move and turn: the box keeps its pose relative to the flange.
    w.setFlangePose(kArm, at(0.2, 0.3, 0.4, M_PI, 0, M_PI / 2));
    const KDL::Frame moved = w.object("box1")->pose;
    EXPECT_NEAR(moved.p.x(), 0.2, 1e-9);
    EXPECT_NEAR(moved.p.y(), 0.3, 1e-9);
    EXPECT_NEAR(moved.p.z(), 0.25, 1e-9);
    EXPECT_EQ(w.unmountTool(kArm, "dock1"), BadInvalidState);  // still holding the box

    // The same pose reported again (an arm that stands) is no change.
    const std::uint64_t revision = w.revision();
    EXPECT_EQ(w.setFlangePose(kArm, at(0.2, 0.3, 0.4, M_PI, 0, M_PI / 2)), Good);
    EXPECT_EQ(w.revision(), revision);

    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_EQ(w.release(kArm), BadInvalidState);
    w.setFlangePose(kArm, at(0.6, 0.6, 0.6));
    EXPECT_TRUE(near(w.object("box1")->pose, moved, 1e-12, 1e-12));
}

// Two robots in one cell: each has its own flange, tool and held object; what one holds the
// other cannot take, and a tool mounted on either stays where it is.
TEST(DeviceWorld, TwoRobotsEachHaveTheirOwnFlangeToolAndObject) {
    World w = cell();  // kArm at the origin, the dock and the box
    std::string why;
    const std::string other = "other";
    ASSERT_EQ(w.addRobot(other, at(1.0, 0, 0), &why), Good) << why;
    EXPECT_EQ(w.addRobot(other, at(2.0, 0, 0)), BadNodeIdExists);
    EXPECT_EQ(w.addRobot("box1"), BadNodeIdExists);  // one set of names
    EXPECT_EQ(w.addRobot(""), BadInvalidArgument);
    EXPECT_TRUE(near(w.flange(other).pose, at(1.0, 0, 0), 1e-12, 1e-12));  // starts at its base
    EXPECT_EQ(w.setFlangePose("nobody", at(0, 0, 0), &why), BadNotFound);
    EXPECT_NE(why.find("no robot nobody"), std::string::npos) << why;

    // kArm takes the gripper and the box; the other robot, at the same grip point with no
    // tool, holds nothing and cannot take it.
    w.setFlangePose(kArm, at(0.3, -0.4, 0.3, M_PI, 0, 0));
    ASSERT_EQ(w.mountTool(kArm, "dock1"), Good);
    EXPECT_EQ(w.dockAtFlange(other), std::nullopt);
    w.setFlangePose(kArm, at(0.5, 0.1, 0.17, M_PI, 0, 0));
    ASSERT_EQ(w.grasp(kArm, "box1"), Good);
    EXPECT_EQ(w.holderOf("box1"), std::optional<std::string>(kArm));
    EXPECT_EQ(w.grasp(other, "box1"), BadInvalidState);  // no tool
    EXPECT_EQ(w.flange(other).tool, "");
    EXPECT_EQ(w.moveTool("gripper", "dock1", &why), BadInvalidState);  // mounted on kArm
    EXPECT_NE(why.find("mounted on robot " + kArm), std::string::npos) << why;
    EXPECT_EQ(w.removeObject("box1", &why), BadInvalidState);
    EXPECT_NE(why.find("held by robot " + kArm), std::string::npos) << why;

    // The other robot's flange moves without moving what kArm holds.
    const KDL::Frame held = w.object("box1")->pose;
    ASSERT_EQ(w.setFlangePose(other, at(0.8, 0.2, 0.3)), Good);
    EXPECT_TRUE(near(w.object("box1")->pose, held, 1e-12, 1e-12));
    EXPECT_EQ(w.release(other), BadInvalidState);  // it holds nothing
    ASSERT_EQ(w.release(kArm), Good);
    EXPECT_EQ(w.holderOf("box1"), std::nullopt);
}

TEST(DeviceWorld, ExtentAlongADirectionFollowsTheBoxOrientation) {
    World w;
    EXPECT_EQ(w.addRobot(kArm), ua::status::Good);
    ASSERT_EQ(w.addObject({"bar", {0.10, 0.02, 0.04}, at(0, 0, 0, 0, 0, M_PI / 2)}), Good);
    // Turned by 90 degrees about z: its 0.10 m edge lies along the base y axis.
    EXPECT_NEAR(*w.extentAlong("bar", KDL::Vector(0, 1, 0)), 0.10, 1e-9);
    EXPECT_NEAR(*w.extentAlong("bar", KDL::Vector(2, 0, 0)), 0.02, 1e-9);
    EXPECT_NEAR(*w.extentAlong("bar", KDL::Vector(0, 0, 1)), 0.04, 1e-9);
    EXPECT_FALSE(w.extentAlong("none", KDL::Vector(0, 0, 1)));
}

/// An empty world model on a real server.
struct WorldServer {
    WorldServer()
        : server(test::RunningServer::defaultConfig(), [this](ua::Server& s) {
              auto created = WorldNodes::create(s);
              ASSERT_TRUE(created.ok());
              nodes = std::move(*created);
          }) {}
    std::unique_ptr<WorldNodes> nodes;  // before the server: it goes after the server stops
    test::RunningServer server;
};

// The world file keeps all a world holds, exactly: what a restarted world goes on from.
TEST(DeviceWorldFile, SavesAndRestoresEverythingTheWorldHolds) {
    WorldContents c;
    c.revision = 812;
    c.objects["box1"] = {
        "box1", {0.04, 0.05, 0.06}, at(0.2, 0.1, 0.3, 0.1, 0.2, 0.3), ObjectKind::Box, 2};
    c.objects["block"] = {
        "block", {0.006, 0.04, 0.03}, at(0.5, 0, 0.1), ObjectKind::TerminalBlock, 1};
    c.objects["fuse"] = {"fuse", {0.019, 0.005, 0.018}, at(0.4, 0.2, 0.1), ObjectKind::Fuse, 0};
    c.tools["gripper"] = {"gripper", at(0, 0, 0.15)};
    c.docks["dock1"] = {"dock1", at(0.3, -0.4, 0.3, M_PI, 0, 0), ""};
    c.docks["dock2"] = {"dock2", at(0.6, -0.4, 0.3, M_PI, 0, 0), "other"};
    c.rails["rail"] = {"rail", at(0.5, 0, 0), 0.3, 0.035};
    c.railMounts["block2"] = {"rail", 0.12};
    Flange f;
    f.base = at(1, 0, 0, 0, 0, M_PI);
    f.pose = at(0.2, 0.1, 0.45, 0.1, 0.2, 0.3);
    f.tool = "gripper";
    f.held = "box1";
    f.toHeld = at(0, 0, 0.15, 0.01, 0.02, 0.03);
    f.hooked = RailMount{"rail", 0.07};
    f.tilted = true;
    f.railRefusal = "skewed";
    f.fuseContact = std::make_pair(std::string("slot1"), SlotContact{0.004, 0.0001, true, 7.5});
    c.robots["arm"] = f;
    c.robots["other"] = Flange{};
    FuseSlot slot;
    slot.id = "slot1";
    slot.pose = at(0.4, 0.2, 0.05);
    slot.misalignment = KDL::Vector(0.0002, -0.0001, 0);
    c.fuseSlots["slot1"] = slot;
    c.seatedFuses["fuse"] = "slot1";

    const test::TempDir dir("skillcell-world-file");
    const auto file = dir.path() / "world.json";
    ASSERT_TRUE(saveWorldFile(file, World(c)).ok());
    const auto back = loadWorldFile(file);
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_EQ(back->revision, 812u);
    ASSERT_EQ(back->objects.size(), 3u);
    const WorldObject& box = back->objects.at("box1");
    EXPECT_EQ(box.size, (BoxSize{0.04, 0.05, 0.06}));
    EXPECT_TRUE(near(box.pose, c.objects["box1"].pose, 0, 0));  // bit for bit
    EXPECT_EQ(box.grasps, 2u);
    EXPECT_EQ(back->objects.at("block").kind, ObjectKind::TerminalBlock);
    EXPECT_EQ(back->objects.at("fuse").kind, ObjectKind::Fuse);
    EXPECT_TRUE(near(back->tools.at("gripper").gripPoint, at(0, 0, 0.15), 0, 0));
    EXPECT_EQ(back->docks.at("dock1").tool, "");
    EXPECT_EQ(back->docks.at("dock2").tool, "other");
    EXPECT_DOUBLE_EQ(back->rails.at("rail").length, 0.3);
    EXPECT_EQ(back->railMounts.at("block2"), (RailMount{"rail", 0.12}));
    const Flange& arm = back->robots.at("arm");
    EXPECT_TRUE(near(arm.base, f.base, 0, 0));
    EXPECT_TRUE(near(arm.pose, f.pose, 0, 0));
    EXPECT_TRUE(near(arm.toHeld, f.toHeld, 0, 0));
    EXPECT_EQ(arm.tool, "gripper");
    EXPECT_EQ(arm.held, "box1");
    EXPECT_EQ(arm.hooked, f.hooked);
    EXPECT_TRUE(arm.tilted);
    EXPECT_FALSE(arm.snapped);
    EXPECT_EQ(arm.railRefusal, "skewed");
    ASSERT_TRUE(arm.fuseContact);
    EXPECT_EQ(arm.fuseContact->first, "slot1");
    EXPECT_DOUBLE_EQ(arm.fuseContact->second.force, 7.5);
    EXPECT_TRUE(arm.fuseContact->second.aligned);
    EXPECT_FALSE(back->robots.at("other").hooked);
    EXPECT_EQ(back->fuseSlots.at("slot1").misalignment, slot.misalignment);
    EXPECT_EQ(back->seatedFuses.at("fuse"), "slot1");
    // A World made from it holds the same; its robots act at their flanges only once each
    // has reported where its flange is now (it may have moved while the world was down).
    World restored(*back);
    EXPECT_EQ(restored.holderOf("box1"), std::optional<std::string>("arm"));
    EXPECT_FALSE(restored.settled("arm"));
    std::string why;
    EXPECT_EQ(restored.release("arm", &why), ua::status::BadWaitingForInitialData);
    EXPECT_NE(why.find("has not heard where robot arm"), std::string::npos) << why;
    EXPECT_EQ(restored.holderOf("box1"), std::optional<std::string>("arm"));
    ASSERT_EQ(restored.setFlangePose("arm", at(0.3, 0.2, 0.5)), Good);
    EXPECT_TRUE(restored.settled("arm"));
    EXPECT_TRUE(near(restored.object("box1")->pose, at(0.3, 0.2, 0.5) * f.toHeld, 1e-12, 1e-12));
    EXPECT_EQ(restored.release("arm"), Good);
    EXPECT_EQ(restored.release("other"), ua::status::BadWaitingForInitialData);

    // What is not a world file is refused with the file's name and what is wrong.
    std::ofstream(file) << "{\"format\": \"skillcell world 1\", \"revision\": 1}";
    auto bad = loadWorldFile(file);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().find(file.string()), std::string::npos) << bad.error();
    EXPECT_NE(bad.error().find("objects"), std::string::npos) << bad.error();
    std::ofstream(file) << "not json";
    bad = loadWorldFile(file);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().find("not JSON"), std::string::npos) << bad.error();
    EXPECT_FALSE(loadWorldFile(dir.path() / "none.json").ok());
}

TEST(DeviceWorldNodes, DevicesChangeTheWorldThroughMethodsAndReadItBack) {
    WorldServer fixture;
    test::RunningServer& server = fixture.server;
    const std::unique_ptr<WorldNodes>& nodes = fixture.nodes;
    auto link = WorldLink::connect(server.url(), {}, kArm);
    ASSERT_TRUE(link.ok()) << ua::statusName(link.status());
    WorldLink& w = **link;

    EXPECT_EQ(w.addObject("box1", {0.04, 0.04, 0.04}, at(0.5, 0.1, 0.02)), Good);
    EXPECT_EQ(w.addObject("box1", {0.04, 0.04, 0.04}, at(0.5, 0.1, 0.02)), BadNodeIdExists);
    EXPECT_EQ(w.addObject("bad", {0.04, -1, 0.04}, at(0.5, 0.1, 0.02)), BadInvalidArgument);
    EXPECT_EQ(w.addDock("dock1", at(0.3, -0.4, 0.3, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.addTool("gripper", "dock1", at(0, 0, 0.15)), Good);
    EXPECT_EQ(w.addDock("shelf", at(0.6, -0.4, 0.3, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.moveTool("gripper", "shelf"), Good);  // and back: a swap, by a person
    EXPECT_EQ(w.moveTool("gripper", "nowhere"), ua::status::BadNotFound);
    EXPECT_EQ(w.moveTool("gripper", "dock1"), Good);

    // The robot this link acts for: none yet, then placed.
    EXPECT_EQ(w.setFlangePose(at(0.3, -0.4, 0.3, M_PI, 0, 0)), BadNotFound);
    EXPECT_EQ(w.addRobot(kArm, at(0, 0, 0)), Good);
    EXPECT_EQ(w.addRobot(kArm, at(1, 0, 0)), BadNodeIdExists);
    EXPECT_EQ(w.mountTool("dock1"), BadInvalidState);
    EXPECT_EQ(w.setFlangePose(at(0.3, -0.4, 0.3, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.mountTool("dock1"), Good);
    EXPECT_EQ(*w.mountedTool(), "gripper");

    auto found = w.objectAtGripPoint();
    ASSERT_TRUE(found.ok());
    EXPECT_FALSE(found->has_value());
    EXPECT_EQ(w.setFlangePose(at(0.5, 0.1, 0.17, M_PI, 0, 0)), Good);
    found = w.objectAtGripPoint();
    ASSERT_TRUE(found.ok() && found->has_value());
    EXPECT_EQ((*found)->objectId, "box1");
    EXPECT_NEAR((*found)->extent[1], 0.04, 1e-9);

    EXPECT_EQ(w.grasp("box1"), Good);
    EXPECT_EQ(*w.graspedObject(), "box1");
    EXPECT_EQ(w.setFlangePose(at(0.2, 0.3, 0.4, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.release(), Good);
    EXPECT_EQ(w.release(), BadInvalidState);
    EXPECT_EQ(w.setFlangePose(at(0.3, -0.4, 0.3, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.unmountTool("dock1"), Good);

    // What a reader of the address space sees is what the World holds.
    const auto pose = w.objectPose("box1");
    ASSERT_TRUE(pose.ok());
    EXPECT_TRUE(near(*pose, at(0.2, 0.3, 0.25), 1e-9, 1e-9)) << describe(*pose);
    EXPECT_EQ(w.objectPose("nothing").status(), ua::status::BadNodeIdUnknown);
    EXPECT_EQ(*w.mountedTool(), "");
    const bool consistent = server.inServer([&](ua::Server&) {
        const World& world = nodes->world();
        return world.flange(kArm).held.empty() && world.flange(kArm).tool.empty() &&
               world.docks().at("dock1").tool == "gripper" &&
               near(world.object("box1")->pose, at(0.2, 0.3, 0.25), 1e-9, 1e-9);
    });
    EXPECT_TRUE(consistent);
}

// A device idle for longer than its session's timeout (a tool changer between two tool
// changes): the world closes the session while the channel stays up, and the next request
// goes through on a new session, without the device taking it for a lost world.
TEST(DeviceWorldNodes, ALinkWhoseSessionTheWorldClosedWhileIdleOpensAnotherAndGoesOn) {
    WorldServer fixture;
    test::RunningServer& server = fixture.server;
    ua::ClientConfig config;
    config.sessionTimeoutMs = 1000;  // the server's least
    auto link = WorldLink::connect(server.url(), config, kArm);
    ASSERT_TRUE(link.ok()) << ua::statusName(link.status());
    WorldLink& w = **link;
    EXPECT_EQ(w.addObject("box1", {0.04, 0.04, 0.04}, at(0.5, 0.1, 0.02)), Good);
    auto sessions = [&] { return server.inServer([](ua::Server& s) { return s.sessionCount(); }); };
    // The server looks for timed-out sessions every second: bounded by 5 s.
    const auto until = std::chrono::steady_clock::now() + 5s;
    while (sessions() != 0 && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(20ms);
    }
    ASSERT_EQ(sessions(), 0U);
    w.clearLoss();
    const auto pose = w.objectPose("box1");  // a read
    ASSERT_TRUE(pose.ok()) << ua::statusName(pose.status());
    EXPECT_TRUE(near(*pose, at(0.5, 0.1, 0.02), 1e-9, 1e-9));
    EXPECT_EQ(w.addObject("box2", {0.04, 0.04, 0.04}, at(0.3, 0.1, 0.02)), Good);  // a call
    auto ids = w.objectIds();                                                      // a browse
    ASSERT_TRUE(ids.ok());
    EXPECT_EQ(ids->size(), 2U);
    EXPECT_FALSE(w.lostConnection());
    EXPECT_EQ(sessions(), 1U);
}

// A fuse pushed into a slot through the world's methods: the force it meets and the slot it
// is seated in, as a reader of the address space sees them.
TEST(DeviceWorldNodes, AFuseInsertedThroughTheMethodsShowsItsForceAndItsSlot) {
    WorldServer fixture;
    test::RunningServer& server = fixture.server;
    auto link = WorldLink::connect(server.url(), {}, kArm);
    ASSERT_TRUE(link.ok()) << ua::statusName(link.status());
    WorldLink& w = **link;
    const std::array<double, 3> ato{0.0191, 0.0051, 0.0185};
    EXPECT_EQ(w.addFuseSlot("F1", at(0.5, 0.2, 0.05), 0.008), Good);
    EXPECT_EQ(w.addFuseSlot("F1", at(0.5, 0.2, 0.05), 0.008), BadNodeIdExists);
    EXPECT_EQ(w.addFuseSlot("F2", at(0.5, 0.3, 0.05), -1), BadInvalidArgument);
    EXPECT_EQ(w.addFuse("fuse1", ato, at(0.3, 0.1, ato[2] / 2)), Good);
    EXPECT_EQ(w.addDock("dock1", at(0.3, -0.4, 0.3, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.addTool("gripper", "dock1", at(0, 0, 0.15)), Good);
    EXPECT_EQ(w.addRobot(kArm, at(0, 0, 0)), Good);
    EXPECT_EQ(w.setFlangePose(at(0.3, -0.4, 0.3, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.mountTool("dock1"), Good);
    // Gripped from the top at its centre; the flange 0.15 m above the grip point.
    EXPECT_EQ(w.setFlangePose(at(0.3, 0.1, ato[2] / 2 + 0.15, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.grasp("fuse1"), Good);
    const double seatedZ = 0.05 + ato[2] / 2 - 0.008;
    EXPECT_EQ(w.setFlangePose(at(0.5, 0.2, seatedZ + 0.004 + 0.15, M_PI, 0, 0)), Good);
    auto force = w.contactForce();
    ASSERT_TRUE(force.ok());
    EXPECT_NEAR(*force, kTerminalFriction, 1e-6);  // half way in, the terminals rub
    EXPECT_EQ(w.setFlangePose(at(0.5, 0.2, seatedZ + 0.15, M_PI, 0, 0)), Good);
    EXPECT_EQ(w.release(), Good);
    EXPECT_NEAR(*w.contactForce(), 0, 1e-12);
    auto slot = w.fuseSlot("F1");
    ASSERT_TRUE(slot.ok());
    EXPECT_EQ(slot->fuse, "fuse1");
    EXPECT_NEAR(slot->depth, 0.008, 1e-12);
    EXPECT_EQ(*w.fuseSeat("fuse1"), "F1");
    EXPECT_EQ(w.fuseSlot("F9").status(), ua::status::BadNodeIdUnknown);
}

TEST(DeviceWorldNodes, MalformedCallsGetPreciseStatusCodesAndChangeNothing) {
    WorldServer fixture;
    test::RunningServer& server = fixture.server;
    const std::unique_ptr<WorldNodes>& nodes = fixture.nodes;
    ua::BlockingClient c;
    ASSERT_EQ(c.connect(server.url()), Good);
    const auto ns = server.inServer(
        [](ua::Server& s) { return *s.addressSpace().namespaceIndex(kWorldNamespaceUri); });
    const ua::NodeId world(ns, ua::String("World"));
    auto method = [&](const char* name) {
        return ua::NodeId(ns, ua::String(std::string("World.") + name));
    };
    auto status = [](const ua::Result<std::vector<ua::Variant>>& r) { return r.status(); };

    const ua::Variant arm{ua::String(kArm)};
    ASSERT_EQ(status(c.call(world, method("AddRobot"), {arm, frameToVariant(at(0, 0, 0))})), Good);
    // A number where a 3DFrame belongs: refused by the argument check.
    EXPECT_TRUE(status(c.call(world, method("SetFlangePose"), {arm, ua::Variant(1.0)})).isBad());
    // A robot the world lacks.
    EXPECT_EQ(status(c.call(world, method("SetFlangePose"),
                            {ua::Variant(ua::String("other")), frameToVariant(at(1, 0, 0))})),
              BadNotFound);
    // Another structure where a 3DFrame belongs: the argument check's, too.
    ua::ExtensionObject vector;  // a 3DVector (its Default Binary encoding: three Doubles)
    vector.typeId = ua::NodeId(18817);
    vector.encoding = ua::ExtensionObject::Encoding::Binary;
    vector.body = ua::ByteString(std::vector<std::uint8_t>(24, 0));
    EXPECT_EQ(status(c.call(world, method("SetFlangePose"), {arm, ua::Variant(vector)})),
              BadInvalidArgument);
    // An empty robot id is a bad argument, as AddRobot answers it, not a robot not found.
    for (const char* m : {"SetFlangePose", "MountTool", "UnmountTool", "Grasp"}) {
        const bool pose = std::string_view(m) == "SetFlangePose";
        EXPECT_EQ(
            status(c.call(world, method(m),
                          {ua::Variant(ua::String("")),
                           pose ? frameToVariant(at(1, 0, 0)) : ua::Variant(ua::String("x"))})),
            BadInvalidArgument)
            << m;
    }
    for (const char* m : {"Release", "DockAtFlange", "ObjectAtGripPoint"}) {
        EXPECT_EQ(status(c.call(world, method(m), {ua::Variant(ua::String(""))})),
                  BadInvalidArgument)
            << m;
    }
    EXPECT_EQ(status(c.call(world, method("AddRobot"), {arm, frameToVariant(at(1, 0, 0))})),
              BadNodeIdExists);
    // Two box edges, or a NaN edge: the world refuses them.
    EXPECT_EQ(status(c.call(
                  world, method("AddObject"),
                  {ua::Variant(ua::String("b")), ua::Variant::array(std::vector<double>{0.1, 0.1}),
                   frameToVariant(at(0, 0, 0))})),
              BadInvalidArgument);
    EXPECT_EQ(status(c.call(world, method("AddObject"),
                            {ua::Variant(ua::String("b")),
                             ua::Variant::array(std::vector<double>{0.1, std::nan(""), 0.1}),
                             frameToVariant(at(0, 0, 0))})),
              BadInvalidArgument);
    EXPECT_EQ(status(c.call(world, method("Grasp"), {arm, ua::Variant(ua::String(""))})),
              BadNotFound);
    EXPECT_EQ(status(c.call(world, method("MountTool"), {arm, ua::Variant(ua::String("x"))})),
              BadNotFound);
    EXPECT_EQ(status(c.call(world, method("Release"), {arm})), BadInvalidState);
    // Without the robot's id.
    EXPECT_TRUE(status(c.call(world, method("Release"), {})).isBad());
    // Too few arguments.
    EXPECT_TRUE(status(c.call(world, method("AddDock"), {ua::Variant(ua::String("d"))})).isBad());
    const bool untouched = server.inServer([&](ua::Server&) {
        const World& w = nodes->world();
        return w.objects().empty() && w.docks().empty() && w.tools().empty() &&
               near(w.flange(kArm).pose, KDL::Frame::Identity(), 0, 0);
    });
    EXPECT_TRUE(untouched);
}

}  // namespace
}  // namespace skillcell::devices::device_world_test
