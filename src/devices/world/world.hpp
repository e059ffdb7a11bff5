#pragma once
// World: the simulated work cell as one plain value (no threads, no I/O): boxes with their
// poses, tool docks, tools, the robot's flange pose, the mounted tool and the grasped
// object. A grasped object keeps its pose relative to the flange, so it moves with the
// robot; a released one stays where it was put. Every change is checked against the
// state of the cell (a tool is taken from a dock only by a flange at that dock, an object
// is grasped only at the mounted tool's grip point, ...), so the world stays consistent
// whatever its clients report. Terminal blocks mount on DIN rails as they do on real ones
// (din_rail.hpp): hooked over the upper edge, rotated down until they snap, and never over
// another block. Blade fuses meet a force as they enter a fuse box's slot (fuse_slot.hpp),
// small when they are aligned with its terminals, steep when they are not, and stay seated
// when released at its depth. The OPC UA face is world_nodes.hpp.
#include <kdl/frames.hpp>
#include <map>
#include <optional>
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

/// How close the flange must be to a dock to take or leave a tool, and how far outside
/// a box the grip point may be for a grasp (sensor and placement tolerances).
struct WorldTolerances {
    double dockPosition = 0.005;  // m
    double dockAngle = 0.02;      // rad
    double grasp = 0.005;         // m
    double railContact = 0.002;   // m: a block's foot on a rail's edge
    double railOverlap = 0.0001;  // m: blocks side by side may touch by this much
};

class World {
public:
    explicit World(WorldTolerances tolerances = {}) : tolerances_(tolerances) {}

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
    /// Removes an object that is not grasped (BadNotFound, BadInvalidState).
    ua::StatusCode removeObject(const std::string& id, std::string* why = nullptr);

    // What the devices report.
    /// The robot's flange moved; a grasped object moves with it.
    void setFlangePose(const KDL::Frame& flange);
    /// The tool changer locked the tool in `dockId` to the flange: the flange must be at
    /// the dock, the dock must hold a tool and no tool may be mounted (BadNotFound,
    /// BadInvalidState otherwise).
    ua::StatusCode mountTool(const std::string& dockId, std::string* why = nullptr);
    /// The tool changer left the mounted tool in the free dock `dockId` (the flange must be
    /// there); refused while the tool holds an object.
    ua::StatusCode unmountTool(const std::string& dockId, std::string* why = nullptr);
    /// The mounted gripper holds `objectId`: the object must contain the grip point
    /// (within the grasp tolerance) and nothing may be held already.
    ua::StatusCode grasp(const std::string& objectId, std::string* why = nullptr);
    /// The gripper let go: the object stays where it is, or, a terminal block that has
    /// snapped onto a rail, mounted there. BadInvalidState if none is held.
    ua::StatusCode release(std::string* why = nullptr);

    // Queries.
    [[nodiscard]] const std::map<std::string, WorldObject>& objects() const { return objects_; }
    [[nodiscard]] const std::map<std::string, Tool>& tools() const { return tools_; }
    [[nodiscard]] const std::map<std::string, ToolDock>& docks() const { return docks_; }
    [[nodiscard]] const std::map<std::string, DinRail>& rails() const { return rails_; }
    /// The terminal blocks mounted on rails, by object id.
    [[nodiscard]] const std::map<std::string, RailMount>& railMounts() const { return railMounts_; }
    /// The held block's contact with a rail: hooked over its upper edge (not yet snapped),
    /// or snapped and still held; nullopt when it touches no rail.
    [[nodiscard]] const std::optional<RailMount>& heldBlockOnRail() const { return hooked_; }
    [[nodiscard]] bool heldBlockSnapped() const { return snapped_; }
    /// Why the held block, rotated down on a rail, did not snap (it would sit over another
    /// block); empty when nothing stopped it.
    [[nodiscard]] const std::string& railRefusal() const { return railRefusal_; }
    [[nodiscard]] const std::map<std::string, FuseSlot>& fuseSlots() const { return fuseSlots_; }
    /// The fuses seated in slots: fuse id to slot id.
    [[nodiscard]] const std::map<std::string, std::string>& seatedFuses() const {
        return seatedFuses_;
    }
    /// The held fuse's contact with a slot (the slot's id and the contact); nullopt when it
    /// touches none.
    [[nodiscard]] const std::optional<std::pair<std::string, SlotContact>>& heldFuseContact()
        const {
        return fuseContact_;
    }
    /// The force the held object meets (N, pushing it back along its way in): a fuse in a
    /// slot; 0 otherwise.
    [[nodiscard]] double contactForce() const {
        return fuseContact_ ? fuseContact_->second.force : 0;
    }
    [[nodiscard]] const WorldObject* object(const std::string& id) const;
    [[nodiscard]] const KDL::Frame& flangePose() const { return flange_; }
    /// The mounted tool's id, empty when none.
    [[nodiscard]] const std::string& mountedTool() const { return mounted_; }
    /// The grasped object's id, empty when none.
    [[nodiscard]] const std::string& graspedObject() const { return grasped_; }
    /// The grip point in the base frame (the flange itself when no tool is mounted).
    [[nodiscard]] KDL::Frame gripPoint() const;
    /// The dock the flange is at (within the dock tolerances), if any: what a tool changer's
    /// coupling meets when it locks or unlocks.
    [[nodiscard]] std::optional<std::string> dockAtFlange() const;
    /// The free object whose box contains `point` (within the grasp tolerance) and whose
    /// centre is nearest to it, if any.
    [[nodiscard]] std::optional<std::string> objectAt(const KDL::Vector& point) const;
    /// The object's extent along `direction` (base frame; normalised here): what a
    /// parallel gripper closing along that direction meets.
    [[nodiscard]] std::optional<double> extentAlong(const std::string& objectId,
                                                    const KDL::Vector& direction) const;
    /// Bumps on every change, so observers can tell whether anything happened.
    [[nodiscard]] std::uint64_t revision() const { return revision_; }

private:
    [[nodiscard]] bool idTaken(const std::string& id) const;
    [[nodiscard]] bool flangeAt(const ToolDock& dock) const;
    /// Follows a held terminal block onto and off the rails after the flange moved.
    void trackHeldBlock();
    /// Follows a held fuse into and out of the slots after the flange moved.
    void trackHeldFuse();
    /// The mounted block whose span on `rail` overlaps [position +- width / 2], if any.
    [[nodiscard]] std::optional<std::string> blockInTheWay(const std::string& rail, double position,
                                                           double width) const;

    WorldTolerances tolerances_;
    std::map<std::string, WorldObject> objects_;
    std::map<std::string, Tool> tools_;
    std::map<std::string, ToolDock> docks_;
    std::map<std::string, DinRail> rails_;
    std::map<std::string, RailMount> railMounts_;
    KDL::Frame flange_ = KDL::Frame::Identity();
    std::string mounted_;
    std::string grasped_;
    KDL::Frame flangeToGrasped_ = KDL::Frame::Identity();
    std::optional<RailMount> hooked_;  // the held block's contact with a rail
    bool tilted_ = false;              // ... tilted back over the upper edge
    bool snapped_ = false;             // ... or it has snapped there
    std::string railRefusal_;
    std::map<std::string, FuseSlot> fuseSlots_;
    std::map<std::string, std::string> seatedFuses_;                  // fuse -> slot
    std::optional<std::pair<std::string, SlotContact>> fuseContact_;  // the held fuse's
    std::uint64_t revision_ = 0;
};

}  // namespace skillcell::devices
