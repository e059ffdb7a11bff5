#include "devices/world/world.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "devices/common/frame.hpp"

namespace skillcell::devices {

World::World(WorldContents contents, WorldTolerances tolerances)
    : tolerances_(tolerances),
      objects_(std::move(contents.objects)),
      tools_(std::move(contents.tools)),
      docks_(std::move(contents.docks)),
      rails_(std::move(contents.rails)),
      railMounts_(std::move(contents.railMounts)),
      robots_(std::move(contents.robots)),
      fuseSlots_(std::move(contents.fuseSlots)),
      seatedFuses_(std::move(contents.seatedFuses)),
      revision_(contents.revision) {
    // Robots may have moved while the world was down: each acts (takes a tool, grasps,
    // releases) only once it has reported its flange again.
    for (const auto& [id, f] : robots_) unsettled_.insert(id);
}

WorldContents World::contents() const {
    return {objects_, tools_,     docks_,       rails_,   railMounts_,
            robots_,  fuseSlots_, seatedFuses_, revision_};
}

namespace {

ua::StatusCode fail(ua::StatusCode status, std::string* why, std::string reason) {
    if (why != nullptr) *why = std::move(reason);
    return status;
}

bool positive(const BoxSize& s) {
    return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z) && s.x > 0 && s.y > 0 &&
           s.z > 0;
}

}  // namespace

bool World::idTaken(const std::string& id) const {
    return objects_.contains(id) || tools_.contains(id) || docks_.contains(id) ||
           rails_.contains(id) || fuseSlots_.contains(id) || robots_.contains(id);
}

bool World::flangeAt(const Flange& flange, const ToolDock& dock) const {
    return near(flange.pose, dock.pose, tolerances_.dockPosition, tolerances_.dockAngle);
}

Flange* World::findRobot(const std::string& robot, ua::StatusCode& status, std::string* why) {
    const auto it = robots_.find(robot);
    if (it != robots_.end()) return &it->second;
    status = fail(ua::status::BadNotFound, why, "no robot " + robot + " in the world");
    return nullptr;
}

Flange* World::actingRobot(const std::string& robot, ua::StatusCode& status, std::string* why) {
    Flange* f = findRobot(robot, status, why);
    if (f != nullptr && unsettled_.contains(robot)) {
        status = fail(ua::status::BadWaitingForInitialData, why,
                      "the world restarted and has not heard where robot " + robot +
                          "'s flange is since: it acts there once the robot reports it");
        return nullptr;
    }
    return f;
}

const Flange& World::flange(const std::string& robot) const {
    static const Flange none;
    const auto it = robots_.find(robot);
    return it == robots_.end() ? none : it->second;
}

std::optional<std::string> World::holderOf(const std::string& objectId) const {
    for (const auto& [id, f] : robots_) {
        if (!f.held.empty() && f.held == objectId) return id;
    }
    return std::nullopt;
}

ua::StatusCode World::addRobot(const std::string& id, const KDL::Frame& base, std::string* why) {
    if (id.empty()) return fail(ua::status::BadInvalidArgument, why, "empty robot id");
    if (idTaken(id)) return fail(ua::status::BadNodeIdExists, why, "id " + id + " is taken");
    Flange flange;
    flange.base = base;
    flange.pose = base;
    robots_.emplace(id, std::move(flange));
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::addObject(WorldObject object, std::string* why) {
    if (object.id.empty()) return fail(ua::status::BadInvalidArgument, why, "empty object id");
    if (!positive(object.size)) {
        return fail(ua::status::BadInvalidArgument, why,
                    "object " + object.id + ": every edge of the box must be positive");
    }
    if (idTaken(object.id)) {
        return fail(ua::status::BadNodeIdExists, why, "id " + object.id + " is taken");
    }
    const std::string id = object.id;
    objects_.emplace(id, std::move(object));
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::addDock(ToolDock dock, std::string* why) {
    if (dock.id.empty()) return fail(ua::status::BadInvalidArgument, why, "empty dock id");
    if (!dock.tool.empty()) {
        return fail(ua::status::BadInvalidArgument, why,
                    "dock " + dock.id + ": add the dock empty, then the tool into it");
    }
    if (idTaken(dock.id)) {
        return fail(ua::status::BadNodeIdExists, why, "id " + dock.id + " is taken");
    }
    const std::string id = dock.id;
    docks_.emplace(id, std::move(dock));
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::addTool(Tool tool, const std::string& dockId, std::string* why) {
    if (tool.id.empty()) return fail(ua::status::BadInvalidArgument, why, "empty tool id");
    if (idTaken(tool.id)) {
        return fail(ua::status::BadNodeIdExists, why, "id " + tool.id + " is taken");
    }
    const auto dock = docks_.find(dockId);
    if (dock == docks_.end()) {
        return fail(ua::status::BadNotFound, why, "no dock " + dockId);
    }
    if (!dock->second.tool.empty()) {
        return fail(ua::status::BadInvalidState, why,
                    "dock " + dockId + " holds tool " + dock->second.tool);
    }
    dock->second.tool = tool.id;
    const std::string id = tool.id;
    tools_.emplace(id, std::move(tool));
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::moveTool(const std::string& toolId, const std::string& dockId,
                               std::string* why) {
    if (!tools_.contains(toolId)) return fail(ua::status::BadNotFound, why, "no tool " + toolId);
    const auto to = docks_.find(dockId);
    if (to == docks_.end()) return fail(ua::status::BadNotFound, why, "no dock " + dockId);
    for (const auto& [robot, flange] : robots_) {
        if (flange.tool == toolId) {
            return fail(ua::status::BadInvalidState, why,
                        fmt::format("tool {} is mounted on robot {}", toolId, robot));
        }
    }
    if (to->second.tool == toolId) return ua::status::Good;  // there already
    if (!to->second.tool.empty()) {
        return fail(ua::status::BadInvalidState, why,
                    "dock " + dockId + " holds tool " + to->second.tool);
    }
    for (auto& [id, dock] : docks_) {
        if (dock.tool == toolId) dock.tool.clear();
    }
    to->second.tool = toolId;
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::addRail(DinRail rail, std::string* why) {
    if (rail.id.empty()) return fail(ua::status::BadInvalidArgument, why, "empty rail id");
    if (!std::isfinite(rail.length) || rail.length <= 0 || !std::isfinite(rail.width) ||
        rail.width <= 0) {
        return fail(ua::status::BadInvalidArgument, why,
                    "rail " + rail.id + ": its length and width must be positive");
    }
    if (idTaken(rail.id)) {
        return fail(ua::status::BadNodeIdExists, why, "id " + rail.id + " is taken");
    }
    const std::string id = rail.id;
    rails_.emplace(id, std::move(rail));
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::addFuseSlot(FuseSlot slot, std::string* why) {
    if (slot.id.empty()) return fail(ua::status::BadInvalidArgument, why, "empty fuse slot id");
    if (!std::isfinite(slot.depth) || slot.depth <= 0 || !std::isfinite(slot.clearance) ||
        slot.clearance <= 0) {
        return fail(ua::status::BadInvalidArgument, why,
                    "fuse slot " + slot.id + ": its depth and clearance must be positive");
    }
    if (idTaken(slot.id)) {
        return fail(ua::status::BadNodeIdExists, why, "id " + slot.id + " is taken");
    }
    const std::string id = slot.id;
    fuseSlots_.emplace(id, std::move(slot));
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::removeObject(const std::string& id, std::string* why) {
    if (!objects_.contains(id)) return fail(ua::status::BadNotFound, why, "no object " + id);
    if (const auto holder = holderOf(id)) {
        return fail(ua::status::BadInvalidState, why,
                    "object " + id + " is held by robot " + *holder);
    }
    objects_.erase(id);
    railMounts_.erase(id);
    seatedFuses_.erase(id);
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::setFlangePose(const std::string& robot, const KDL::Frame& pose,
                                    std::string* why) {
    ua::StatusCode status;
    Flange* f = findRobot(robot, status, why);
    if (f == nullptr) return status;
    unsettled_.erase(robot);
    // The same pose again (an arm that stands tells it again every 10 s) changes nothing: no new
    // revision, so the world's state file is not written again for it.
    if (std::equal(pose.p.data, pose.p.data + 3, f->pose.p.data) &&
        std::equal(pose.M.data, pose.M.data + 9, f->pose.M.data)) {
        return ua::status::Good;
    }
    f->pose = pose;
    if (!f->held.empty()) {
        objects_.at(f->held).pose = f->pose * f->toHeld;
        trackHeldBlock(*f);
        trackHeldFuse(*f);
    }
    ++revision_;
    return ua::status::Good;
}

std::optional<std::string> World::blockInTheWay(const std::string& rail, double position,
                                                double width) const {
    for (const auto& [id, mount] : railMounts_) {
        if (mount.rail != rail) continue;
        const double otherWidth = objects_.at(id).size.x;
        if (spansOverlap(position, width, mount.position, otherWidth, tolerances_.railOverlap)) {
            return id;
        }
    }
    return std::nullopt;
}

void World::trackHeldBlock(Flange& f) {
    const WorldObject& block = objects_.at(f.held);
    const std::optional<RailMount> before = f.hooked;
    const bool wasTilted = f.tilted;
    const bool wasSnapped = f.snapped;
    f.hooked.reset();
    f.tilted = false;
    f.snapped = false;
    f.railRefusal.clear();
    if (block.kind != ObjectKind::TerminalBlock) return;
    for (const auto& [id, rail] : rails_) {
        const auto contact = railContact(rail, block.pose, block.size, tolerances_.railContact);
        if (!contact) continue;
        f.hooked = RailMount{id, contact->position};
        if (contact->tilt > kSnapTilt) {
            f.tilted = true;  // hooked, not yet rotated down
            return;
        }
        // Lying flat on the rail. It snaps only when it was rotated down about the upper
        // edge from where it hooked (or had snapped there already): a block pressed straight
        // down meets the upper edge with its foot and stays on top, however often it is
        // reported there.
        const bool rotatedDown =
            before && before->rail == id && (wasTilted || wasSnapped) &&
            std::abs(before->position - contact->position) <= tolerances_.railContact;
        if (!rotatedDown) {
            f.railRefusal = "terminal block " + block.id + " came down flat on rail " + id +
                            " without hooking over its upper edge first";
            return;
        }
        // The spring foot snaps over the lower edge, unless another block stands where this
        // one would sit (it rests on that block instead).
        if (const auto other = blockInTheWay(id, contact->position, block.size.x)) {
            f.railRefusal = fmt::format(
                "terminal block {} at {:.1f} mm on rail {} would sit over terminal block {} "
                "at {:.1f} mm",
                block.id, contact->position * 1000, id, *other,
                railMounts_.at(*other).position * 1000);
            return;
        }
        f.snapped = true;
        return;
    }
}

void World::trackHeldFuse(Flange& f) {
    f.fuseContact.reset();
    const WorldObject& fuse = objects_.at(f.held);
    if (fuse.kind != ObjectKind::Fuse) return;
    for (const auto& [id, slot] : fuseSlots_) {
        if (const auto contact = slotContact(slot, fuse.pose, fuse.size)) {
            f.fuseContact.emplace(id, *contact);
            return;
        }
    }
}

ua::StatusCode World::mountTool(const std::string& robot, const std::string& dockId,
                                std::string* why) {
    ua::StatusCode status;
    Flange* f = actingRobot(robot, status, why);
    if (f == nullptr) return status;
    const auto dock = docks_.find(dockId);
    if (dock == docks_.end()) return fail(ua::status::BadNotFound, why, "no dock " + dockId);
    if (!f->tool.empty()) {
        return fail(ua::status::BadInvalidState, why, "tool " + f->tool + " is mounted already");
    }
    if (dock->second.tool.empty()) {
        return fail(ua::status::BadInvalidState, why, "dock " + dockId + " is empty");
    }
    if (!flangeAt(*f, dock->second)) {
        return fail(ua::status::BadInvalidState, why,
                    "the flange " + describe(f->pose) + " is not at dock " + dockId + " " +
                        describe(dock->second.pose));
    }
    f->tool = dock->second.tool;
    dock->second.tool.clear();
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::unmountTool(const std::string& robot, const std::string& dockId,
                                  std::string* why) {
    ua::StatusCode status;
    Flange* f = actingRobot(robot, status, why);
    if (f == nullptr) return status;
    const auto dock = docks_.find(dockId);
    if (dock == docks_.end()) return fail(ua::status::BadNotFound, why, "no dock " + dockId);
    if (f->tool.empty()) return fail(ua::status::BadInvalidState, why, "no tool is mounted");
    if (!f->held.empty()) {
        return fail(ua::status::BadInvalidState, why,
                    "tool " + f->tool + " still holds object " + f->held);
    }
    if (!dock->second.tool.empty()) {
        return fail(ua::status::BadInvalidState, why,
                    "dock " + dockId + " holds tool " + dock->second.tool);
    }
    if (!flangeAt(*f, dock->second)) {
        return fail(ua::status::BadInvalidState, why,
                    "the flange " + describe(f->pose) + " is not at dock " + dockId + " " +
                        describe(dock->second.pose));
    }
    dock->second.tool = f->tool;
    f->tool.clear();
    ++revision_;
    return ua::status::Good;
}

std::optional<std::string> World::dockAtFlange(const std::string& robot) const {
    const auto r = robots_.find(robot);
    if (r == robots_.end()) return std::nullopt;
    for (const auto& [id, dock] : docks_) {
        if (flangeAt(r->second, dock)) return id;
    }
    return std::nullopt;
}

KDL::Frame World::gripPoint(const std::string& robot) const {
    const Flange& f = flange(robot);
    if (f.tool.empty()) return f.pose;
    return f.pose * tools_.at(f.tool).gripPoint;
}

std::optional<std::string> World::objectAt(const KDL::Vector& point) const {
    // Blocks side by side on a rail are closer than the tolerance: the one whose centre is
    // nearest wins.
    std::optional<std::string> nearest;
    double nearestDistance = 0;
    for (const auto& [id, object] : objects_) {
        if (holderOf(id)) continue;
        const KDL::Vector local = object.pose.Inverse(point);
        const double t = tolerances_.grasp;
        if (std::abs(local.x()) <= object.size.x / 2 + t &&
            std::abs(local.y()) <= object.size.y / 2 + t &&
            std::abs(local.z()) <= object.size.z / 2 + t &&
            (!nearest || local.Norm() < nearestDistance)) {
            nearest = id;
            nearestDistance = local.Norm();
        }
    }
    return nearest;
}

std::optional<double> World::extentAlong(const std::string& objectId,
                                         const KDL::Vector& direction) const {
    const WorldObject* o = object(objectId);
    if (o == nullptr || direction.Norm() <= 0) return std::nullopt;
    KDL::Vector d = direction / direction.Norm();
    const KDL::Vector local = o->pose.M.Inverse(d);  // the direction in the box's frame
    return std::abs(local.x()) * o->size.x + std::abs(local.y()) * o->size.y +
           std::abs(local.z()) * o->size.z;
}

ua::StatusCode World::grasp(const std::string& robot, const std::string& objectId,
                            std::string* why) {
    ua::StatusCode status;
    Flange* f = actingRobot(robot, status, why);
    if (f == nullptr) return status;
    const auto object = objects_.find(objectId);
    if (object == objects_.end()) {
        return fail(ua::status::BadNotFound, why, "no object " + objectId);
    }
    if (f->tool.empty()) return fail(ua::status::BadInvalidState, why, "no tool is mounted");
    if (!f->held.empty()) {
        return fail(ua::status::BadInvalidState, why, "object " + f->held + " is held already");
    }
    if (const auto holder = holderOf(objectId)) {
        return fail(ua::status::BadInvalidState, why,
                    "object " + objectId + " is held by robot " + *holder);
    }
    const KDL::Frame grip = gripPoint(robot);
    if (objectAt(grip.p) != objectId) {
        return fail(ua::status::BadInvalidState, why,
                    "object " + objectId + " is not at the grip point " + describe(grip));
    }
    f->held = objectId;
    f->toHeld = f->pose.Inverse() * object->second.pose;
    ++object->second.grasps;
    // Taken off a rail, if it was on one (the gripper pulls it off as it moves away; until
    // then it is held where it snapped).
    if (const auto mount = railMounts_.find(objectId); mount != railMounts_.end()) {
        railMounts_.erase(mount);
    }
    seatedFuses_.erase(objectId);  // pulled out of its slot as it is taken
    trackHeldBlock(*f);
    trackHeldFuse(*f);
    ++revision_;
    return ua::status::Good;
}

ua::StatusCode World::release(const std::string& robot, std::string* why) {
    ua::StatusCode status;
    Flange* f = actingRobot(robot, status, why);
    if (f == nullptr) return status;
    if (f->held.empty()) return fail(ua::status::BadInvalidState, why, "no object is held");
    if (f->snapped && f->hooked) {
        // The latch holds the block square on the rail, at the position it snapped at.
        WorldObject& block = objects_.at(f->held);
        block.pose = mountedPose(rails_.at(f->hooked->rail), f->hooked->position, block.size);
        railMounts_[f->held] = *f->hooked;
    }
    if (f->fuseContact && f->fuseContact->second.seated(fuseSlots_.at(f->fuseContact->first))) {
        // The terminals hold a seated fuse square in its slot.
        WorldObject& fuse = objects_.at(f->held);
        fuse.pose = seatedPose(fuseSlots_.at(f->fuseContact->first), fuse.size);
        seatedFuses_[f->held] = f->fuseContact->first;
    }
    f->fuseContact.reset();
    f->held.clear();
    f->hooked.reset();
    f->tilted = false;
    f->snapped = false;
    f->railRefusal.clear();
    ++revision_;
    return ua::status::Good;
}

const WorldObject* World::object(const std::string& id) const {
    const auto it = objects_.find(id);
    return it == objects_.end() ? nullptr : &it->second;
}

}  // namespace skillcell::devices
