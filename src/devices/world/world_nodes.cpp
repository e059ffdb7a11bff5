#include "devices/world/world_nodes.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

#include "devices/common/frame.hpp"
#include "devices/world/world_file.hpp"

namespace skillcell::devices {
namespace {

using ua::Argument;
using ua::NodeId;
using ua::StatusCode;
using ua::Variant;

Argument arg(const char* name, std::uint32_t type, const char* text,
             std::int32_t rank = ua::value_rank::kScalar) {
    return Argument{name, NodeId(type), rank, {}, {"", text}};
}

Variant sizeValue(const BoxSize& s) {
    return Variant::array(std::vector<double>{s.x, s.y, s.z});
}

/// Box edges from a Double[3] argument.
std::optional<BoxSize> sizeFrom(const Variant& v) {
    if (!v.isArray() || v.elements().size() != 3) return std::nullopt;
    double e[3];
    for (std::size_t i = 0; i < 3; ++i) {
        const double* d = std::get_if<double>(&v.elements()[i]);
        if (d == nullptr) return std::nullopt;
        e[i] = *d;
    }
    return BoxSize{e[0], e[1], e[2]};
}

std::string stringArg(const Variant& v) {
    const auto* s = v.get<ua::String>();
    return s == nullptr ? std::string() : std::string(*s);
}

/// A 3DFrame argument called `name` as a frame; when it is none, the reason in `why`. The
/// Call service has refused another structure already (BadInvalidArgument, BadTypeMismatch
/// on the argument): what is left is a 3DFrame that does not hold six Doubles, or one with
/// a NaN or infinite number (BadOutOfRange).
ua::Result<KDL::Frame> frameArg(const Variant& v, const char* name, std::string& why) {
    auto frame = frameFromVariant(v);
    if (!frame) {
        why = std::string(name) + (frame.status() == ua::status::BadOutOfRange
                                       ? " holds a NaN or infinite number"
                                       : " is not a 3DFrame in its Default Binary encoding "
                                         "(six Doubles)");
    }
    return frame;
}

/// A Double argument called `name`, or nullptr with the reason in `why`.
const double* doubleArg(const Variant& v, const char* name, std::string& why) {
    const double* d = v.get<double>();
    if (d == nullptr) why = std::string(name) + " is not a Double";
    return d;
}

/// The robot id a per-robot method names (its first argument) in `robot`; an empty one is
/// BadInvalidArgument, as AddRobot answers it (not BadNotFound for a robot called "").
StatusCode robotArg(const Variant& v, std::string& robot, std::string& why) {
    robot = stringArg(v);
    if (!robot.empty()) return ua::status::Good;
    why = "empty robot id";
    return ua::status::BadInvalidArgument;
}

/// BadNotFound, with the reason, for a robot `world` lacks: the questions about a robot's
/// flange (the changes get the same from the World itself).
StatusCode knownRobot(const World& world, const std::string& robot, std::string& why) {
    if (world.robots().contains(robot)) return ua::status::Good;
    why = "no robot " + robot + " in the world";
    return ua::status::BadNotFound;
}

/// A robot whose flange the world knows: one restored from a state file answers questions
/// about what is at its flange only once it has reported the flange again.
StatusCode heardRobot(const World& world, const std::string& robot, std::string& why) {
    if (const StatusCode s = knownRobot(world, robot, why); s.isBad()) return s;
    if (world.settled(robot)) return ua::status::Good;
    why = "the world restarted and has not heard where robot " + robot +
          "'s flange is since: it answers for its flange once the robot reports it";
    return ua::status::BadWaitingForInitialData;
}

/// A refused change: its reason goes to the log, its status to the caller. Every refusal
/// in this file and in World says why; the fallback only keeps a new one that does not from
/// logging an empty reason.
StatusCode refused(const char* method, StatusCode status, const std::string& why) {
    spdlog::warn("world: {} refused ({}): {}", method, ua::statusName(status),
                 why.empty() ? std::string("no reason given") : why);
    return status;
}

}  // namespace

WorldNodes::WorldNodes(Token, ua::Server& server, World world, std::uint16_t ns)
    : server_(server), world_(std::move(world)), ns_(ns) {}

NodeId WorldNodes::id(const std::string& path) const {
    return NodeId(ns_, ua::String(path));
}

ua::Result<std::unique_ptr<WorldNodes>> WorldNodes::create(ua::Server& server, World world,
                                                           std::filesystem::path stateFile) {
    const std::uint16_t ns = server.addressSpace().registerNamespace(kWorldNamespaceUri);
    auto nodes = std::make_unique<WorldNodes>(Token{}, server, std::move(world), ns);
    nodes->stateFile_ = std::move(stateFile);
    if (const StatusCode s = nodes->build(); s.isBad()) return s;  // build() saves
    return nodes;
}

void WorldNodes::save() {
    if (stateFile_.empty() || savedRevision_ == world_.revision()) return;
    if (auto s = saveWorldFile(stateFile_, world_); !s) {
        if (!saveFailed_) spdlog::error("world: {}: a restart will not find this state", s.error());
        saveFailed_ = true;
        return;
    }
    saveFailed_ = false;
    savedRevision_ = world_.revision();
}

StatusCode WorldNodes::build() {
    ua::AddressSpace& as = server_.addressSpace();
    const NodeId world = id("World");
    if (auto r = as.addObject(NodeId(ua::ns0::ObjectsFolder), world, "World"); !r) {
        return r.status();
    }
    for (const char* folder : {"Objects", "Tools", "Docks", "Rails", "FuseSlots", "Robots"}) {
        if (auto r = as.addFolder(world, id(std::string("World/") + folder), folder); !r) {
            return r.status();
        }
    }

    // The methods. The Call service has checked the argument count and types against the
    // declarations before a callback runs (a 3DFrame argument holds a 3DFrame, not another
    // structure); the callbacks check values.
    struct MethodSpec {
        const char* name;
        ua::Role requiredRole;  // changing the scene is configuration: Engineer
        std::vector<Argument> inputs;
        std::vector<Argument> outputs;
        std::function<StatusCode(std::span<const Variant>, std::vector<Variant>&, std::string&)>
            body;
    };
    const std::uint32_t kFrame = ua::ns0::ThreeDFrame;
    const std::uint32_t kString = ua::ns0::String;
    const std::uint32_t kDouble = ua::ns0::Double;
    std::vector<MethodSpec> methods;
    // AddObject, AddTerminalBlock, AddFuse: one method per kind of object, alike but for
    // what their size and pose mean.
    struct ObjectMethod {
        const char* name;
        ObjectKind kind;
        const char* size;
        const char* pose;
    };
    const ObjectMethod objectMethods[] = {
        {"AddObject", ObjectKind::Box, "box edges x, y, z (m)", "the box centre in the base frame"},
        {"AddTerminalBlock", ObjectKind::TerminalBlock,
         "width along a rail, depth across it, height off it (m)",
         "the block's centre in the base frame"},
        {"AddFuse", ObjectKind::Fuse, "width (through both blades), thickness, height (m)",
         "the fuse's centre in the base frame, blades down its -z"},
    };
    for (const ObjectMethod& m : objectMethods) {
        methods.push_back(
            {m.name,
             ua::Role::Engineer,
             {arg("Id", kString, "object id"),
              arg("Size", kDouble, m.size, ua::value_rank::kOneDimension),
              arg("Pose", kFrame, m.pose)},
             {},
             [this, kind = m.kind](std::span<const Variant> in, std::vector<Variant>&,
                                   std::string& why) {
                 const auto size = sizeFrom(in[1]);
                 if (!size) {
                     why = "Size must hold three Doubles";
                     return StatusCode(ua::status::BadInvalidArgument);
                 }
                 const auto pose = frameArg(in[2], "Pose", why);
                 if (!pose) return pose.status();
                 return world_.addObject(WorldObject{stringArg(in[0]), *size, *pose, kind}, &why);
             }});
    }
    methods.push_back(
        {"AddFuseSlot",
         ua::Role::Engineer,
         {arg("Id", kString, "slot id"),
          arg("Pose", kFrame, "the opening's centre on the fuse box's face, z out of the box"),
          arg("Depth", kDouble, "m the blades go in when seated")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             const auto pose = frameArg(in[1], "Pose", why);
             if (!pose) return pose.status();
             const double* depth = doubleArg(in[2], "Depth", why);
             if (depth == nullptr) return StatusCode(ua::status::BadTypeMismatch);
             FuseSlot slot;
             slot.id = stringArg(in[0]);
             slot.pose = *pose;
             slot.depth = *depth;
             return world_.addFuseSlot(std::move(slot), &why);
         }});
    methods.push_back(
        {"AddRail",
         ua::Role::Engineer,
         {arg("Id", kString, "rail id"),
          arg("Pose", kFrame,
              "the rail's start on its face's centre line: x along the rail, y towards its "
              "upper edge, z out of its face"),
          arg("Length", kDouble, "m"), arg("Width", kDouble, "m (TS35: 0.035)")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             const auto pose = frameArg(in[1], "Pose", why);
             if (!pose) return pose.status();
             const double* length = doubleArg(in[2], "Length", why);
             if (length == nullptr) return StatusCode(ua::status::BadTypeMismatch);
             const double* width = doubleArg(in[3], "Width", why);
             if (width == nullptr) return StatusCode(ua::status::BadTypeMismatch);
             return world_.addRail(DinRail{stringArg(in[0]), *pose, *length, *width}, &why);
         }});
    methods.push_back(
        {"AddDock",
         ua::Role::Engineer,
         {arg("Id", kString, "dock id"),
          arg("Pose", kFrame, "the flange pose at which the dock's tool locks")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             const auto pose = frameArg(in[1], "Pose", why);
             if (!pose) return pose.status();
             return world_.addDock(ToolDock{stringArg(in[0]), *pose, {}}, &why);
         }});
    methods.push_back(
        {"AddTool",
         ua::Role::Engineer,
         {arg("Id", kString, "tool id"), arg("DockId", kString, "the dock the tool is stored in"),
          arg("GripPoint", kFrame, "grip point relative to the tool mounting plate")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             const auto grip = frameArg(in[2], "GripPoint", why);
             if (!grip) return grip.status();
             return world_.addTool(Tool{stringArg(in[0]), *grip}, stringArg(in[1]), &why);
         }});
    methods.push_back(
        {"MoveTool",
         ua::Role::Engineer,  // the cell's setup changes: a person swaps a tool in its dock
         {arg("Id", kString, "a stored (not mounted) tool"),
          arg("DockId", kString, "the free dock it is put in")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             return world_.moveTool(stringArg(in[0]), stringArg(in[1]), &why);
         }});
    methods.push_back(
        {"AddRobot",
         ua::Role::Engineer,
         {arg("Id", kString, "robot id"),
          arg("Base", kFrame, "the robot's base frame in the cell's base frame")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             const auto base = frameArg(in[1], "Base", why);
             if (!base) return base.status();
             return world_.addRobot(stringArg(in[0]), *base, &why);
         }});
    // What the devices report: each names the robot whose flange it moves or acts at (an
    // empty id is BadInvalidArgument, an unknown one BadNotFound).
    const Argument robot = arg("Robot", kString, "the robot's id (World/Robots)");
    // The answer is the physics' to the robot's motion: the force the held object meets
    // there, which an arm with force sensing measures.
    methods.push_back(
        {"SetFlangePose",
         ua::Role::Operator,
         {robot, arg("Pose", kFrame, "the robot flange in the base frame")},
         {arg("ContactForce", kDouble,
              "N the held object meets at this pose, pushing it back (a fuse in a slot)")},
         [this](std::span<const Variant> in, std::vector<Variant>& out, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             const auto pose = frameArg(in[1], "Pose", why);
             if (!pose) return pose.status();
             if (const auto s = world_.setFlangePose(r, *pose, &why); s.isBad()) return s;
             out.emplace_back(world_.contactForce(r));
             return StatusCode(ua::status::Good);
         }});
    methods.push_back(
        {"MountTool",
         ua::Role::Operator,
         {robot, arg("DockId", kString, "the dock whose tool the flange takes")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             return world_.mountTool(r, stringArg(in[1]), &why);
         }});
    methods.push_back(
        {"DockAtFlange",
         ua::Role::Observer,  // a question, not a change
         {robot},
         {arg("DockId", kString, "the dock the flange is at; empty when none")},
         [this](std::span<const Variant> in, std::vector<Variant>& out, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             if (const StatusCode s = heardRobot(world_, r, why); s.isBad()) return s;
             out.emplace_back(ua::String(world_.dockAtFlange(r).value_or("")));
             return StatusCode(ua::status::Good);
         }});
    methods.push_back(
        {"UnmountTool",
         ua::Role::Operator,
         {robot, arg("DockId", kString, "the free dock the mounted tool is left in")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             return world_.unmountTool(r, stringArg(in[1]), &why);
         }});
    methods.push_back(
        {"Grasp",
         ua::Role::Operator,
         {robot, arg("ObjectId", kString, "the object at the grip point")},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             return world_.grasp(r, stringArg(in[1]), &why);
         }});
    methods.push_back(
        {"Release",
         ua::Role::Operator,
         {robot},
         {},
         [this](std::span<const Variant> in, std::vector<Variant>&, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             return world_.release(r, &why);
         }});
    methods.push_back(
        {"ObjectAtGripPoint",
         ua::Role::Observer,  // a question, not a change
         {robot},
         {arg("ObjectId", kString, "the free object at the grip point; empty when none"),
          arg("Extent", kDouble, "its extent along the grip point's x, y and z axes (m)",
              ua::value_rank::kOneDimension)},
         [this](std::span<const Variant> in, std::vector<Variant>& out, std::string& why) {
             std::string r;
             if (const StatusCode s = robotArg(in[0], r, why); s.isBad()) return s;
             if (const StatusCode s = heardRobot(world_, r, why); s.isBad()) return s;
             const KDL::Frame grip = world_.gripPoint(r);
             const auto found = world_.objectAt(grip.p);
             std::vector<double> extent{0, 0, 0};
             if (found) {
                 const KDL::Vector axes[3] = {grip.M.UnitX(), grip.M.UnitY(), grip.M.UnitZ()};
                 for (std::size_t i = 0; i < 3; ++i) {
                     extent[i] = world_.extentAlong(*found, axes[i]).value_or(0);
                 }
             }
             out.emplace_back(ua::String(found.value_or("")));
             out.emplace_back(Variant::array(std::move(extent)));
             return StatusCode(ua::status::Good);
         }});

    for (auto& m : methods) {
        auto body = std::move(m.body);
        const char* name = m.name;
        auto r = as.addMethod(world, id(std::string("World.") + name), name, std::move(m.inputs),
                              std::move(m.outputs),
                              [this, body = std::move(body), name](
                                  const ua::Caller&, const NodeId&, std::span<const Variant> in,
                                  std::vector<Variant>& out) -> StatusCode {
                                  std::string why;
                                  const StatusCode s = body(in, out, why);
                                  if (s.isBad()) return refused(name, s, why);
                                  sync();
                                  return s;
                              });
        if (!r) return r.status();
        as.find(id(std::string("World.") + name))->requiredRole = m.requiredRole;
    }
    sync();
    return ua::status::Good;
}

void WorldNodes::sync() {
    ua::AddressSpace& as = server_.addressSpace();
    const NodeId frame(ua::ns0::ThreeDFrame);
    // Values of nodes that exist; nodes for what the world gained since the last sync.
    auto put = [&](const std::string& path, const std::string& parent, const char* name,
                   const NodeId& dataType, Variant value, std::int32_t rank) {
        const NodeId node = id(path);
        if (as.find(node) == nullptr) {
            auto r = as.addVariable(id(parent), node, name, dataType, std::move(value),
                                    ua::access_level::kCurrentRead, rank);
            if (!r) spdlog::error("world: cannot add {}: {}", path, ua::statusName(r.status()));
            return;
        }
        (void)as.setValue(node, std::move(value));
    };
    auto ensureObject = [&](const std::string& path, const std::string& parent,
                            const std::string& name) {
        if (as.find(id(path)) != nullptr) return;
        auto r = as.addObject(id(parent), id(path), name);
        if (!r) spdlog::error("world: cannot add {}: {}", path, ua::statusName(r.status()));
    };
    for (const auto& [oid, object] : world_.objects()) {
        const std::string path = "World/Objects/" + oid;
        ensureObject(path, "World/Objects", oid);
        put(path + "/Pose", path, "Pose", frame, frameToVariant(object.pose),
            ua::value_rank::kScalar);
        put(path + "/Size", path, "Size", NodeId(ua::ns0::Double), sizeValue(object.size),
            ua::value_rank::kOneDimension);
        // How often a gripper took hold of it: one pick, one grasp, however its run went.
        put(path + "/Grasps", path, "Grasps", NodeId(ua::ns0::UInt32), Variant(object.grasps),
            ua::value_rank::kScalar);
        if (object.kind == ObjectKind::TerminalBlock) {
            // Where it is mounted: the rail and the block's centre along it; an empty rail
            // and NaN when it is on none.
            const auto mount = world_.railMounts().find(oid);
            const bool on = mount != world_.railMounts().end();
            put(path + "/Rail", path, "Rail", NodeId(ua::ns0::String),
                Variant(ua::String(on ? mount->second.rail : std::string())),
                ua::value_rank::kScalar);
            put(path + "/RailPosition", path, "RailPosition", NodeId(ua::ns0::Double),
                Variant(on ? mount->second.position : std::nan("")), ua::value_rank::kScalar);
            // Why it lies loose on a rail, held, instead of having snapped (empty when it has,
            // or when it is not held there): what a placing skill reports.
            const auto holder = world_.holderOf(oid);
            put(path + "/RailRefusal", path, "RailRefusal", NodeId(ua::ns0::String),
                Variant(ua::String(holder ? world_.flange(*holder).railRefusal : std::string())),
                ua::value_rank::kScalar);
        }
        if (object.kind == ObjectKind::Fuse) {
            // The slot it is seated in; empty when none.
            const auto seat = world_.seatedFuses().find(oid);
            put(path + "/Slot", path, "Slot", NodeId(ua::ns0::String),
                Variant(
                    ua::String(seat != world_.seatedFuses().end() ? seat->second : std::string())),
                ua::value_rank::kScalar);
        }
    }
    for (const auto& [sid, slot] : world_.fuseSlots()) {
        const std::string path = "World/FuseSlots/" + sid;
        ensureObject(path, "World/FuseSlots", sid);
        put(path + "/Pose", path, "Pose", frame, frameToVariant(slot.pose),
            ua::value_rank::kScalar);
        put(path + "/Depth", path, "Depth", NodeId(ua::ns0::Double), Variant(slot.depth),
            ua::value_rank::kScalar);
        std::string seated;
        for (const auto& [fuse, at] : world_.seatedFuses()) {
            if (at == sid) seated = fuse;
        }
        put(path + "/Fuse", path, "Fuse", NodeId(ua::ns0::String), Variant(ua::String(seated)),
            ua::value_rank::kScalar);
    }
    for (const auto& [rid, rail] : world_.rails()) {
        const std::string path = "World/Rails/" + rid;
        ensureObject(path, "World/Rails", rid);
        put(path + "/Pose", path, "Pose", frame, frameToVariant(rail.pose),
            ua::value_rank::kScalar);
        put(path + "/Length", path, "Length", NodeId(ua::ns0::Double), Variant(rail.length),
            ua::value_rank::kScalar);
        put(path + "/Width", path, "Width", NodeId(ua::ns0::Double), Variant(rail.width),
            ua::value_rank::kScalar);
    }
    for (const auto& [tid, tool] : world_.tools()) {
        const std::string path = "World/Tools/" + tid;
        ensureObject(path, "World/Tools", tid);
        put(path + "/GripPoint", path, "GripPoint", frame, frameToVariant(tool.gripPoint),
            ua::value_rank::kScalar);
    }
    for (const auto& [did, dock] : world_.docks()) {
        const std::string path = "World/Docks/" + did;
        ensureObject(path, "World/Docks", did);
        put(path + "/Pose", path, "Pose", frame, frameToVariant(dock.pose),
            ua::value_rank::kScalar);
        put(path + "/Tool", path, "Tool", NodeId(ua::ns0::String), Variant(ua::String(dock.tool)),
            ua::value_rank::kScalar);
    }
    for (const auto& [rid, f] : world_.robots()) {
        const std::string path = "World/Robots/" + rid;
        ensureObject(path, "World/Robots", rid);
        put(path + "/Base", path, "Base", frame, frameToVariant(f.base), ua::value_rank::kScalar);
        put(path + "/FlangePose", path, "FlangePose", frame, frameToVariant(f.pose),
            ua::value_rank::kScalar);
        put(path + "/GripPoint", path, "GripPoint", frame, frameToVariant(world_.gripPoint(rid)),
            ua::value_rank::kScalar);
        put(path + "/MountedTool", path, "MountedTool", NodeId(ua::ns0::String),
            Variant(ua::String(f.tool)), ua::value_rank::kScalar);
        put(path + "/GraspedObject", path, "GraspedObject", NodeId(ua::ns0::String),
            Variant(ua::String(f.held)), ua::value_rank::kScalar);
        // What the held object meets (N, pushing it back along its way in; a fuse entering a
        // slot): what a force-sensing arm measures at its flange.
        put(path + "/ContactForce", path, "ContactForce", NodeId(ua::ns0::Double),
            Variant(world_.contactForce(rid)), ua::value_rank::kScalar);
    }
    save();
}

}  // namespace skillcell::devices
