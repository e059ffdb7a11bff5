#pragma once
// World: the simulated work cell as one plain value (no threads, no I/O): boxes with their
// poses, tool docks, tools, and each robot's flange: its pose, the tool mounted on it and the
// object that tool holds. A grasped object keeps its pose relative to its flange, so it moves
// with that robot; a released one stays where it was put. A cell may have several robots;
// each device that moves a flange or acts at it names its robot. Every change is checked against
// the state of the cell (a tool is taken from a dock only by a flange at that dock, an object is
// grasped only at the mounted tool's grip point, ...), so the world stays consistent whatever its
// clients report. Terminal blocks mount on DIN rails as they do on real ones (din_rail.hpp): hooked
// over the upper edge, rotated down until they snap, and never over another block. Blade fuses meet
// a force as they enter a fuse box's slot (fuse_slot.hpp), small when they are aligned with its
// terminals, steep when they are not, and stay seated when released at its depth. The OPC UA face
// is world_nodes.hpp.
#include <kdl/frames.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "devices/world/box_size.hpp"
#include "devices/world/din_rail.hpp"
#include "devices/world/fuse_slot.hpp"
#include "ua/types/status_code.hpp"

namespace skillcell::devices {

/// What an object is, where that changes how it behaves.
enum class ObjectKind {
    Box,            // rests where it is put
    TerminalBlock,  // also mounts on a DIN rail
    Fuse,           // a blade fuse: goes into a fuse slot
};

struct WorldObject {
    std::string id;
    BoxSize size;
    KDL::Frame pose;  // the box's centre and orientation, in the cell's base frame
    ObjectKind kind = ObjectKind::Box;
    std::uint32_t grasps = 0;  // how often a gripper took hold of it: what tests count
};

/// Where a terminal block is mounted.
struct RailMount {
    std::string rail;
    double position = 0;  // the block's centre along the rail, m
    friend bool operator==(const RailMount&, const RailMount&) = default;
};

struct Tool {
    std::string id;
    /// The grip point (tool centre point) relative to the tool mounting plate (the flange).
    KDL::Frame gripPoint;
};

struct ToolDock {
    std::string id;
    KDL::Frame pose;   // where the flange is when the tool in the dock is mounted
    std::string tool;  // the tool in the dock; empty when the dock is free
};

/// One robot as the world sees it: where its base stands, where its flange is, the tool locked
/// to the flange and the object that tool holds, and what a held block or fuse touches.
struct Flange {
    KDL::Frame base = KDL::Frame::Identity();    // the robot's base frame, in the cell's
    KDL::Frame pose = KDL::Frame::Identity();    // the flange, in the cell's base frame
    std::string tool;                            // mounted; empty when none
    std::string held;                            // the grasped object; empty when none
    KDL::Frame toHeld = KDL::Frame::Identity();  // the held object's pose from the flange
    std::optional<RailMount> hooked;             // the held block's contact with a rail
    bool tilted = false;                         // ... tilted back over the upper edge
    bool snapped = false;                        // ... or it has snapped there
    std::string railRefusal;  // why the held block, rotated down on a rail, did not snap
    std::optional<std::pair<std::string, SlotContact>> fuseContact;  // the held fuse's
};

/// How close the flange must be to a dock to take or leave a tool, and how far outside
/// a box the grip point may be for a grasp (sensor and placement tolerances).
struct WorldTolerances {
    double dockPosition = 0.005;  // m
    double dockAngle = 0.02;      // rad
    double grasp = 0.005;         // m
    double railContact = 0.002;   // m: a block's foot on a rail's edge
    double railOverlap = 0.0001;  // m: blocks side by side may touch by this much
};

/// Everything a World holds beyond its tolerances: what a world file saves and restores
/// (world_file.hpp).
struct WorldContents {
    std::map<std::string, WorldObject> objects;
    std::map<std::string, Tool> tools;
    std::map<std::string, ToolDock> docks;
    std::map<std::string, DinRail> rails;
    std::map<std::string, RailMount> railMounts;
    std::map<std::string, Flange> robots;
    std::map<std::string, FuseSlot> fuseSlots;
    std::map<std::string, std::string> seatedFuses;  // fuse -> slot
    std::uint64_t revision = 0;
};

class World {
public:
    explicit World(WorldTolerances tolerances = {}) : tolerances_(tolerances) {}
    /// A world as it was (a saved one), trusted to be consistent: it was built by a World.
    /// Its robots act at their flanges again only once each has reported it (they may have
    /// moved while the world was down): until then such a change is BadWaitingForInitialData.
    explicit World(WorldContents contents, WorldTolerances tolerances = {});
    [[nodiscard]] WorldContents contents() const;

    // Building the scene. BadInvalidArgument for an empty id, a box with an edge that is
    // not positive; BadNodeIdExists for an id already used by an object, tool or dock.
    ua::StatusCode addObject(WorldObject object, std::string* why = nullptr);
    ua::StatusCode addDock(ToolDock dock, std::string* why = nullptr);
    /// A tool, stored in `dockId` (BadNotFound for an unknown dock, BadInvalidState for an
    /// occupied one).
    ua::StatusCode addTool(Tool tool, const std::string& dockId, std::string* why = nullptr);
    /// A person moves a stored tool to another, free dock (a tool swapped for another model
    /// in the dock the process uses). BadNotFound for an unknown tool or dock;
    /// BadInvalidState for a mounted tool or an occupied dock.
    ua::StatusCode moveTool(const std::string& toolId, const std::string& dockId,
                            std::string* why = nullptr);
    /// A DIN rail (BadInvalidArgument for an empty id or a length that is not positive,
    /// BadNodeIdExists for an id taken).
    ua::StatusCode addRail(DinRail rail, std::string* why = nullptr);
    /// A fuse box's slot (BadInvalidArgument for an empty id or a depth or clearance that is
    /// not positive, BadNodeIdExists for an id taken).
    ua::StatusCode addFuseSlot(FuseSlot slot, std::string* why = nullptr);
    /// A robot whose base stands at `base` (BadInvalidArgument for an empty id,
    /// BadNodeIdExists for one taken); its flange starts at the base.
    ua::StatusCode addRobot(const std::string& id, const KDL::Frame& base = KDL::Frame::Identity(),
                            std::string* why = nullptr);
    /// Removes an object that is not grasped (BadNotFound, BadInvalidState).
    ua::StatusCode removeObject(const std::string& id, std::string* why = nullptr);

    // What the devices report, each for one robot (BadNotFound for a robot the world lacks).
    /// The robot's flange moved; an object it holds moves with it.
    ua::StatusCode setFlangePose(const std::string& robot, const KDL::Frame& flange,
                                 std::string* why = nullptr);
    /// The robot's tool changer locked the tool in `dockId` to the flange: the flange must be
    /// at the dock, the dock must hold a tool and no tool may be mounted (BadNotFound,
    /// BadInvalidState otherwise).
    ua::StatusCode mountTool(const std::string& robot, const std::string& dockId,
                             std::string* why = nullptr);
    /// The tool changer left the mounted tool in the free dock `dockId` (the flange must be
    /// there); refused while the tool holds an object.
    ua::StatusCode unmountTool(const std::string& robot, const std::string& dockId,
                               std::string* why = nullptr);
    /// The gripper mounted on the robot holds `objectId`: the object must contain the grip
    /// point (within the grasp tolerance), be held by no robot, and this one may hold nothing.
    ua::StatusCode grasp(const std::string& robot, const std::string& objectId,
                         std::string* why = nullptr);
    /// The gripper let go: the object stays where it is, or, a terminal block that has
    /// snapped onto a rail, mounted there. BadInvalidState if none is held.
    ua::StatusCode release(const std::string& robot, std::string* why = nullptr);

    // Queries.
    [[nodiscard]] const std::map<std::string, WorldObject>& objects() const { return objects_; }
    [[nodiscard]] const std::map<std::string, Tool>& tools() const { return tools_; }
    [[nodiscard]] const std::map<std::string, ToolDock>& docks() const { return docks_; }
    [[nodiscard]] const std::map<std::string, DinRail>& rails() const { return rails_; }
    /// The terminal blocks mounted on rails, by object id.
    [[nodiscard]] const std::map<std::string, RailMount>& railMounts() const { return railMounts_; }
    /// The robots, by id.
    [[nodiscard]] const std::map<std::string, Flange>& robots() const { return robots_; }
    /// A robot's flange; an empty one (at the origin, holding nothing) for an unknown robot.
    [[nodiscard]] const Flange& flange(const std::string& robot) const;
    /// The robot holding `objectId`, if any.
    [[nodiscard]] std::optional<std::string> holderOf(const std::string& objectId) const;
    [[nodiscard]] const std::map<std::string, FuseSlot>& fuseSlots() const { return fuseSlots_; }
    /// The fuses seated in slots: fuse id to slot id.
    [[nodiscard]] const std::map<std::string, std::string>& seatedFuses() const {
        return seatedFuses_;
    }
    /// The force the object held by `robot` meets (N, pushing it back along its way in): a
    /// fuse in a slot; 0 otherwise.
    [[nodiscard]] double contactForce(const std::string& robot) const {
        const auto& f = flange(robot);
        return f.fuseContact ? f.fuseContact->second.force : 0;
    }
    [[nodiscard]] const WorldObject* object(const std::string& id) const;
    /// The robot's grip point in the base frame (its flange itself when no tool is mounted).
    [[nodiscard]] KDL::Frame gripPoint(const std::string& robot) const;
    /// The dock the robot's flange is at (within the dock tolerances), if any: what a tool
    /// changer's coupling meets when it locks or unlocks.
    [[nodiscard]] std::optional<std::string> dockAtFlange(const std::string& robot) const;
    /// The free (held by no robot) object whose box contains `point` (within the grasp tolerance)
    /// and whose centre is nearest to it, if any.
    [[nodiscard]] std::optional<std::string> objectAt(const KDL::Vector& point) const;
    /// The object's extent along `direction` (base frame; normalised here): what a
    /// parallel gripper closing along that direction meets.
    [[nodiscard]] std::optional<double> extentAlong(const std::string& objectId,
                                                    const KDL::Vector& direction) const;
    /// Whether the world knows where the robot's flange is: not a robot restored from a
    /// state file that has not reported its flange since. What is at its flange (a dock, an
    /// object at its grip point) is known only then.
    [[nodiscard]] bool settled(const std::string& robot) const {
        return !unsettled_.contains(robot);
    }
    /// Bumps on every change, so observers can tell whether anything happened.
    [[nodiscard]] std::uint64_t revision() const { return revision_; }

private:
    [[nodiscard]] bool idTaken(const std::string& id) const;
    [[nodiscard]] bool flangeAt(const Flange& flange, const ToolDock& dock) const;
    /// The robot's flange, or a BadNotFound with the reason.
    Flange* findRobot(const std::string& robot, ua::StatusCode& status, std::string* why);
    /// The same, for a change that acts at the flange: BadWaitingForInitialData while the
    /// robot has not reported its flange since the world was restored.
    Flange* actingRobot(const std::string& robot, ua::StatusCode& status, std::string* why);
    /// Follows a held terminal block onto and off the rails after the flange moved.
    void trackHeldBlock(Flange& flange);
    /// Follows a held fuse into and out of the slots after the flange moved.
    void trackHeldFuse(Flange& flange);
    /// The mounted block whose span on `rail` overlaps [position +- width / 2], if any.
    [[nodiscard]] std::optional<std::string> blockInTheWay(const std::string& rail, double position,
                                                           double width) const;

    WorldTolerances tolerances_;
    std::map<std::string, WorldObject> objects_;
    std::map<std::string, Tool> tools_;
    std::map<std::string, ToolDock> docks_;
    std::map<std::string, DinRail> rails_;
    std::map<std::string, RailMount> railMounts_;
    std::map<std::string, Flange> robots_;
    std::map<std::string, FuseSlot> fuseSlots_;
    std::map<std::string, std::string> seatedFuses_;  // fuse -> slot
    std::uint64_t revision_ = 0;
    std::set<std::string> unsettled_;  // restored robots not heard from since
};

}  // namespace skillcell::devices
