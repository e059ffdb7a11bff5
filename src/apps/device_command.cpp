// `skillcell device <kind>`: one component of the simulated work cell per process
// (docs/devices.md). Each is a server process like `skillcell server` (--port, discovery,
// READY line, SIGTERM) whose content is the device:
//   world    the world model (Objects/World), optionally seeded with a scene
//   ur5      the simulated UR5 with its four move skills, reporting to a world model
//   iiwa     the simulated KUKA LBR iiwa 7 R800 (7 axes), the same skills and reports
//   robotiq  the Robotiq 2F-85 adapter on a serial device; without --serial, on a
//            simulated 2F-85 behind a pseudo-terminal that asks the world model what lies
//            between its fingers and reports grasps and releases there
//   ag95     the same for another parallel-gripper model, the DH-Robotics AG-95
//   schmalz  the Schmalz ECBPi adapter on an IO-Link master port, here a simulated master
//            with a simulated ECBPi that asks the world model what is under its cup
//   toolchanger  the Kelvin tool changer: AttachTool, DetachTool, ChangeTool on the robot's
//            move skill; a simulated coupling on the world model; it powers the tools'
//            adapter processes
//   pickplace  the pick-and-place composite: PickAndPlace and PlaceTerminalBlock over the
//            robot's move skill and the mounted tool's Grasp and Release, the object from the
//            world model
#include <spdlog/spdlog.h>
#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <map>

#include "cell/component_uris.hpp"
#include "cell/device_arguments.hpp"
#include "commands.hpp"
#include "devices/arm/arm_component.hpp"
#include "devices/arm/arm_kinematics.hpp"
#include "devices/common/frame.hpp"
#include "devices/common/robot_motion.hpp"
#include "devices/dh/ag95_component.hpp"
#include "devices/dh/simulated_ag95.hpp"
#include "devices/pickplace/pick_and_place_component.hpp"
#include "devices/robotiq/robotiq_component.hpp"
#include "devices/robotiq/simulated_gripper_port.hpp"
#include "devices/schmalz/ecbpi_component.hpp"
#include "devices/toolchanger/simulated_kelvin_changer.hpp"
#include "devices/toolchanger/tool_changer_component.hpp"
#include "devices/world/flange_reporter.hpp"
#include "devices/world/world_file.hpp"
#include "devices/world/world_nodes.hpp"
#include "server_process.hpp"
#include "world_connection.hpp"

namespace skillcell::apps {
namespace {

using devices::parsePose6;
using devices::toFrame;

/// A pose on the command line: X,Y,Z[,A,B,C] (devices::parsePose6), refused at parse time.
CLI::Validator poseText() {
    return {[](std::string& text) {
                return parsePose6(text) ? std::string() : "expected X,Y,Z[,A,B,C] (m, rad)";
            },
            "POSE"};
}

/// --boot-profile: the gripper adapters can start like the paper's Wi-Fi boards.
void addBootProfileOption(CLI::App* cmd, std::string& profile) {
    cmd->add_option("--boot-profile", profile,
                    "tinyua: start like the paper's Wi-Fi microcontroller board (boot loader, "
                    "Wi-Fi join, NTP, application start: about 8-10 s until announced); none: "
                    "at once")
        ->check(CLI::IsMember({"none", "tinyua"}))
        ->capture_default_str();
}

/// The robot a device moves or is mounted on when it is not told (--robot), and the one a
/// world model given no --robot has: a cell file names each (`cell up` passes them).
constexpr const char* kDefaultRobot = "robot";

/// --robot: which of the world's robots a device moves, or acts at the flange of.
void addRobotOption(CLI::App* cmd, std::string& robot, const char* what) {
    cmd->add_option("--robot", robot, std::string("the world model's id of the robot ") + what)
        ->capture_default_str();
}

/// --robot-uri of a gripper adapter: what its skills publish as RobotUri, for an MES to take
/// the gripper on the robot it moves.
void addRobotUriOption(CLI::App* cmd, std::string& uri) {
    cmd->add_option("--robot-uri", uri,
                    "the application URI of the robot that carries the gripper (its tool "
                    "changer passes it), published as its skills' RobotUri");
}

/// Starts `world` connecting as soon as the component can (StartEarly); nothing without one.
StartEarly connectEarly(const std::shared_ptr<WorldConnection>& world) {
    if (!world) return {};
    return [world](const ua::ClientSecurity& security, const std::string& applicationUri) {
        world->start(security, applicationUri);
    };
}

struct WorldOptions {
    ServerProcessOptions process;
    std::vector<std::string> objects;          // ID:SX,SY,SZ@POSE
    std::vector<std::string> docks;            // ID@POSE
    std::vector<std::string> tools;            // ID:DOCK@GRIPPOINT
    std::vector<std::string> rails;            // ID:LENGTH@POSE
    std::vector<std::string> terminalBlocks;   // ID:SX,SY,SZ@POSE
    std::vector<std::string> fuses;            // ID:SX,SY,SZ@POSE
    std::vector<std::string> fuseSlots;        // ID@POSE
    std::vector<std::string> misalignedSlots;  // ID:DX,DY,DZ
    std::vector<std::string> robots;           // ID[@BASE]
    std::string stateFile;                     // kept across restarts; empty: none
};

/// Splits "HEAD@POSE" into HEAD and the pose.
std::optional<std::pair<std::string, KDL::Frame>> headAndPose(const std::string& spec) {
    const auto at = spec.find('@');
    if (at == std::string::npos) return std::nullopt;
    const auto pose = parsePose6(std::string_view(spec).substr(at + 1));
    if (!pose) return std::nullopt;
    return std::make_pair(spec.substr(0, at), toFrame(*pose));
}

/// Three numbers X,Y,Z (a pose's text without angles): a size or an offset.
std::optional<KDL::Vector> threeNumbers(std::string_view text) {
    const auto p = parsePose6(text);
    if (!p || p->a != 0 || p->b != 0 || p->c != 0) return std::nullopt;
    return KDL::Vector(p->x, p->y, p->z);
}

/// Adds a box of `kind` from "ID:SX,SY,SZ@POSE" (`option` names the option in errors).
ua::StatusCode seedObject(const std::string& option, const std::string& spec,
                          devices::ObjectKind kind, devices::World& world) {
    const auto hp = headAndPose(spec);
    const auto colon = hp ? hp->first.find(':') : std::string::npos;
    const auto size = colon == std::string::npos
                          ? std::nullopt
                          : threeNumbers(std::string_view(hp->first).substr(colon + 1));
    if (!size) {
        spdlog::critical("{} {}: expected ID:SX,SY,SZ@X,Y,Z[,A,B,C]", option, spec);
        return ua::status::BadInvalidArgument;
    }
    std::string why;
    const auto s = world.addObject(
        {hp->first.substr(0, colon), {size->x(), size->y(), size->z()}, hp->second, kind}, &why);
    if (s.isBad()) spdlog::critical("{} {}: {}", option, spec, why);
    return s;
}

ua::StatusCode seedWorld(const WorldOptions& options, devices::World& world) {
    std::string why;
    for (const auto& spec :
         options.robots.empty() ? std::vector<std::string>{kDefaultRobot} : options.robots) {
        const bool placed = spec.find('@') != std::string::npos;
        const auto hp = placed ? headAndPose(spec)
                               : std::make_optional(std::pair(spec, KDL::Frame::Identity()));
        if (!hp) {
            spdlog::critical("--robot {}: expected ID[@X,Y,Z[,A,B,C]]", spec);
            return ua::status::BadInvalidArgument;
        }
        if (const auto s = world.addRobot(hp->first, hp->second, &why); s.isBad()) {
            spdlog::critical("--robot {}: {}", spec, why);
            return s;
        }
    }
    // Rails first: a terminal block may be given already mounted on one.
    for (const auto& spec : options.rails) {
        const auto hp = headAndPose(spec);
        const auto colon = hp ? hp->first.find(':') : std::string::npos;
        double length = 0;
        const std::string lengthText =
            colon == std::string::npos ? std::string() : hp->first.substr(colon + 1);
        const auto [end, ec] =
            std::from_chars(lengthText.data(), lengthText.data() + lengthText.size(), length);
        if (colon == std::string::npos || ec != std::errc() ||
            end != lengthText.data() + lengthText.size()) {
            spdlog::critical("--rail {}: expected ID:LENGTH@X,Y,Z[,A,B,C]", spec);
            return ua::status::BadInvalidArgument;
        }
        const auto s = world.addRail({hp->first.substr(0, colon), hp->second, length}, &why);
        if (s.isBad()) {
            spdlog::critical("--rail {}: {}", spec, why);
            return s;
        }
    }
    for (const auto& spec : options.objects) {
        if (const auto s = seedObject("--object", spec, devices::ObjectKind::Box, world);
            s.isBad()) {
            return s;
        }
    }
    for (const auto& spec : options.terminalBlocks) {
        if (const auto s =
                seedObject("--terminal-block", spec, devices::ObjectKind::TerminalBlock, world);
            s.isBad()) {
            return s;
        }
    }
    for (const auto& spec : options.fuses) {
        if (const auto s = seedObject("--fuse", spec, devices::ObjectKind::Fuse, world);
            s.isBad()) {
            return s;
        }
    }
    // A slot's hidden manufacturing error, by slot id.
    std::map<std::string, KDL::Vector> misalignments;
    for (const auto& m : options.misalignedSlots) {
        const auto colon = m.find(':');
        const auto offset = colon == std::string::npos
                                ? std::nullopt
                                : threeNumbers(std::string_view(m).substr(colon + 1));
        if (!offset) {
            spdlog::critical("--misaligned-slot {}: expected ID:DX,DY,DZ", m);
            return ua::status::BadInvalidArgument;
        }
        misalignments[m.substr(0, colon)] = *offset;
    }
    for (const auto& spec : options.fuseSlots) {
        const auto hp = headAndPose(spec);
        if (!hp) {
            spdlog::critical("--fuse-slot {}: expected ID@X,Y,Z[,A,B,C]", spec);
            return ua::status::BadInvalidArgument;
        }
        devices::FuseSlot slot;
        slot.id = hp->first;
        slot.pose = hp->second;
        if (const auto m = misalignments.find(slot.id); m != misalignments.end()) {
            slot.misalignment = m->second;
        }
        if (const auto s = world.addFuseSlot(std::move(slot), &why); s.isBad()) {
            spdlog::critical("--fuse-slot {}: {}", spec, why);
            return s;
        }
    }
    for (const auto& [id, offset] : misalignments) {
        if (!world.fuseSlots().contains(id)) {
            spdlog::critical("--misaligned-slot {}: no --fuse-slot {}", id, id);
            return ua::status::BadInvalidArgument;
        }
    }
    for (const auto& spec : options.docks) {
        const auto hp = headAndPose(spec);
        if (!hp) {
            spdlog::critical("--dock {}: expected ID@X,Y,Z[,A,B,C]", spec);
            return ua::status::BadInvalidArgument;
        }
        if (const auto s = world.addDock({hp->first, hp->second, {}}, &why); s.isBad()) {
            spdlog::critical("--dock {}: {}", spec, why);
            return s;
        }
    }
    for (const auto& spec : options.tools) {
        const auto hp = headAndPose(spec);
        const auto colon = hp ? hp->first.find(':') : std::string::npos;
        if (colon == std::string::npos) {
            spdlog::critical("--tool {}: expected ID:DOCK@X,Y,Z[,A,B,C]", spec);
            return ua::status::BadInvalidArgument;
        }
        const auto s = world.addTool({hp->first.substr(0, colon), hp->second},
                                     hp->first.substr(colon + 1), &why);
        if (s.isBad()) {
            spdlog::critical("--tool {}: {}", spec, why);
            return s;
        }
    }
    return ua::status::Good;
}

/// The world as --state-file kept it, else as the scene options build it.
ua::Result<devices::World> startingWorld(const WorldOptions& options) {
    std::error_code ec;
    if (!options.stateFile.empty() && std::filesystem::exists(options.stateFile, ec)) {
        auto kept = devices::loadWorldFile(options.stateFile);
        if (!kept) {
            spdlog::critical("--state-file: {}", kept.error());
            return ua::status::BadConfigurationError;
        }
        spdlog::info("world: going on from {} (revision {}, {} objects, {} robots)",
                     options.stateFile, kept->revision, kept->objects.size(), kept->robots.size());
        return devices::World(std::move(*kept));
    }
    devices::World world;
    if (const auto s = seedWorld(options, world); s.isBad()) return s;
    return world;
}

CLI::App* addWorld(CLI::App* device, std::vector<Command>& commands) {
    auto options = std::make_shared<WorldOptions>();
    options->process.applicationUri = std::string(cell::kWorldUri);
    options->process.applicationName = "skillcell world model";
    CLI::App* cmd = device->add_subcommand(
        "world",
        "Serve the world model (Objects/World: boxes, tool docks, tools, and each robot's "
        "flange, mounted tool and grasped object) that the simulated devices report to "
        "(docs/devices.md).");
    addServerProcessOptions(cmd, options->process);
    addDiscoveryOptions(cmd, options->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--object", options->objects,
                    "a box: ID:SX,SY,SZ@X,Y,Z[,A,B,C] (edges and centre pose, m and rad)");
    cmd->add_option("--dock", options->docks,
                    "a tool dock: ID@X,Y,Z[,A,B,C] (the flange pose at which its tool locks)");
    cmd->add_option("--tool", options->tools,
                    "a tool stored in a dock: ID:DOCK@X,Y,Z[,A,B,C] (its grip point relative "
                    "to the mounting plate)");
    cmd->add_option("--rail", options->rails,
                    "a TS35 DIN rail: ID:LENGTH@X,Y,Z[,A,B,C] (m; the pose of its start, x "
                    "along the rail, y towards its upper edge, z out of its face)");
    cmd->add_option("--terminal-block", options->terminalBlocks,
                    "a terminal block: ID:WIDTH,DEPTH,HEIGHT@X,Y,Z[,A,B,C] (m and rad; it "
                    "snaps onto a rail when hooked over the upper edge and rotated down)");
    cmd->add_option("--fuse", options->fuses,
                    "a blade fuse: ID:WIDTH,THICKNESS,HEIGHT@X,Y,Z[,A,B,C] (m and rad, blades "
                    "down its -z; it meets a force as it enters a fuse slot)");
    cmd->add_option("--fuse-slot", options->fuseSlots,
                    "a fuse box's slot for an ATO fuse: ID@X,Y,Z[,A,B,C] (the opening's centre, "
                    "z out of the box, x through the terminals; 8 mm deep)");
    cmd->add_option("--robot", options->robots,
                    std::string("a robot whose flange the devices report: ID[@X,Y,Z[,A,B,C]] "
                                "(its base in the cell's frame; none: the origin); none given: "
                                "one, ") +
                        kDefaultRobot);
    cmd->add_option("--state-file", options->stateFile,
                    "keep the world in FILE after every change, and start from it when it "
                    "exists (a restarted world goes on from the cell as it was; the scene "
                    "options then only start a new FILE)");
    cmd->add_option("--misaligned-slot", options->misalignedSlots,
                    "a fuse slot made out of tolerance: ID:DX,DY,DZ, its terminals that far (m, "
                    "in its frame) from where --fuse-slot draws it; only the physics knows it");
    commands.push_back(
        {cmd, [options] {
             return runServerProcess(
                 options->process,
                 [options](const ComponentContext& c) -> ua::Result<ComponentContent> {
                     auto world = startingWorld(*options);
                     if (!world) return world.status();
                     auto nodes = devices::WorldNodes::create(c.server, *world, options->stateFile);
                     if (!nodes) return nodes.status();
                     return ComponentContent(std::move(*nodes));
                 });
         }});
    return cmd;
}

struct ArmOptions {
    ServerProcessOptions process;
    double speed = 1;
    int tickMs = 10;
    WorldAddress world;
    std::string robot = kDefaultRobot;
    std::string base = "0,0,0";
};

/// What `device ur5` or `device iiwa` keeps alive: the reporter outlives the component that
/// feeds it.
struct ArmContent {
    std::unique_ptr<devices::FlangeReporter> reporter;
    std::unique_ptr<devices::ArmComponent> component;
};

/// Where a simulated arm starts: where the world has its flange, as a real arm's absolute
/// encoders tell a restarted controller (a killed arm comes back where it stopped, holding
/// what it held); the model's home when the world has not seen the arm yet (its flange still
/// at the base) or the pose is out of its reach. The joints are those the solver reaches
/// from home; only when it reaches none from there does the full search run (33 solver
/// runs, 7 ms of a UR5's start on the 2-core machine, against one).
devices::Joints startingJoints(devices::WorldLink& world, const devices::ArmModel& model,
                               const KDL::Frame& base, const std::string& name) {
    const auto flange = world.flangePose();
    if (!flange || devices::near(*flange, base, 1e-9, 1e-9)) return {};
    const devices::ArmKinematics kinematics(model, base);
    std::string why;
    auto q = kinematics.inverseNear(*flange, model.home, model.bounds);
    if (!q) q = kinematics.inverse(*flange, model.home, model.bounds, &why);
    if (!q) {
        spdlog::warn(
            "{}: the world has the flange at {}, which the arm cannot take ({}): "
            "starting at home",
            name, devices::describe(*flange), why);
        return {};
    }
    spdlog::info("{}: starting where the world has the flange, {}", name,
                 devices::describe(*flange));
    return *q;
}

/// A simulated robot arm of `model` as the command `name`.
CLI::App* addArm(CLI::App* device, std::vector<Command>& commands, const char* name,
                 std::string_view applicationUri, const devices::ArmModel& model) {
    auto options = std::make_shared<ArmOptions>();
    options->process.applicationUri = std::string(applicationUri);
    options->process.applicationName = "skillcell " + model.model + " (simulated)";
    const auto models = devices::ArmComponent::skillModels();
    options->process.skillModels.assign(models.begin(), models.end());
    CLI::App* cmd = device->add_subcommand(
        name, "Run a simulated " + model.manufacturer + " " + model.model + " (" +
                  std::to_string(model.joints()) +
                  " axes) with the skills CartesianLinearMove, CartesianPtpMove, "
                  "JointLinearMove and JointPtpMove, Objects/" +
                  model.name +
                  " with its joint positions, flange and TCP poses, and the arm in the OPC "
                  "Foundation's Robotics model (DeviceSet/" +
                  model.name + "System).");
    addServerProcessOptions(cmd, options->process);
    addDiscoveryOptions(cmd, options->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--speed", options->speed, "simulated seconds per real second")
        ->check(CLI::Range(0.01, 1000.0))
        ->capture_default_str();
    cmd->add_option("--tick-ms", options->tickMs, "simulation step (real time)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    cmd->add_option("--world", options->world.url,
                    "the world model's endpoint (opc.tcp://...): the flange pose is reported "
                    "there");
    addWorldCertificateOption(cmd, options->world);
    addRobotOption(cmd, options->robot, "this arm is");
    cmd->add_option("--base", options->base,
                    "where the arm's base stands in the cell's frame, X,Y,Z[,A,B,C] (m, rad): "
                    "the frame its skills' poses and its reports are in")
        ->check(poseText())
        ->capture_default_str();
    commands.push_back(
        {cmd, [options, model, name = std::string(name)] {
             const KDL::Frame base = toFrame(*parsePose6(options->base));  // by poseText()
             // Where the world has the flange, and the joints that take it there: learnt on
             // the world link's thread (the inverse kinematics included) while the arm loads
             // its models.
             auto joints = std::make_shared<devices::Joints>();
             std::shared_ptr<WorldConnection> world;
             if (!options->world.empty()) {
                 world = std::make_shared<WorldConnection>(
                     options->world, options->robot,
                     [joints, model, base, name](devices::WorldLink& link) {
                         *joints = startingJoints(link, model, base, name);
                     });
             }
             return runServerProcess(
                 options->process,
                 [options, model, name, base, world,
                  joints](const ComponentContext& c) -> ua::Result<ComponentContent> {
                     auto content = std::make_shared<ArmContent>();
                     devices::ArmComponentOptions o;
                     o.model = model;
                     o.arm.speed = options->speed;
                     o.arm.tick = std::chrono::milliseconds(options->tickMs);
                     o.base = base;
                     if (world) {
                         ArmContent* arm = content.get();  // owns the component: outlives it
                         o.startingJoints =
                             [arm, world, joints](std::string* why) -> ua::Result<devices::Joints> {
                             auto link = world->take();
                             if (!link) {
                                 *why = "the world model is out of reach (" +
                                        std::string(ua::statusName(link.status())) + ")";
                                 return link.status();
                             }
                             arm->reporter = devices::FlangeReporter::start(std::move(*link));
                             return *joints;
                         };
                         // Called once the arm exists, after startingJoints: the reporter is.
                         o.onFlange = [arm](const KDL::Frame& f) { arm->reporter->report(f); };
                         // A move ends once the world has its final pose: whoever runs
                         // the next skill finds the world up to date.
                         o.arm.beforeDone = [arm](std::function<void()> report) {
                             arm->reporter->whenSent(std::move(report));
                         };
                         // What the arm's torque sensing measures: the world's answer.
                         if (model.sensesForce) {
                             o.arm.contactForce = [arm] { return arm->reporter->contactForce(); };
                             o.arm.unmeasuredSamples = [arm] {
                                 return arm->reporter->unanswered();
                             };
                         }
                     }
                     std::string error;
                     auto component = devices::ArmComponent::create(c.server, o, &error);
                     if (!component) {
                         spdlog::critical("{}: {}", name, error);
                         return component.status();
                     }
                     content->component = std::move(*component);
                     return ComponentContent(content);
                 },
                 connectEarly(world));
         }});
    return cmd;
}

/// The command-line options every parallel-gripper model shares.
struct ParallelGripperOptions {
    ServerProcessOptions process;
    std::string serial;
    int slaveId = 1;
    double speed = 1;
    WorldAddress world;
    std::string robot = kDefaultRobot;
    std::string robotUri;
    std::string gripOffset;
    double fingerSpeed = 0.1;
    double graspForce = 100;
    std::string bootProfile = "none";
};

/// The world as a simulated parallel gripper's fingers meet it.
struct FingerWiring {
    std::function<devices::Probed()> probe;
    std::function<void(const devices::FingerEvent&)> onEvent;
    /// Whether the world has not heard a grasp or release yet (it restarts).
    std::function<bool()> worldBehind;
    /// What the fingers hold as the simulated gripper starts: the world model's answer, for
    /// an adapter restarted while its gripper holds a part.
    std::optional<devices::ObjectBetweenFingers> holding;
};

/// What differs between parallel-gripper models; everything else of `skillcell device
/// <model>` is the same, as the skills above them are.
struct ParallelGripperModel {
    std::string command;  // "robotiq"
    std::string applicationUri;
    std::string applicationName;
    std::string description;
    std::string simulatedName;  // for logs: "2F-85"
    int slaveId = 1;
    std::string gripOffset;  // default X,Y,Z
    double maxForce = 100;   // N
    double maxFingerSpeed = 0.15;
    /// Starts a simulated gripper on a pty: its device path and what keeps it running.
    std::function<ua::Result<std::pair<std::string, std::shared_ptr<void>>>(
        double speed, FingerWiring wiring, std::string* why)>
        simulate;
    /// The adapter and its skills on the serial device `options.serial`.
    std::function<ua::Result<std::shared_ptr<devices::GripperComponent>>(
        ua::Server& server, const ParallelGripperOptions& options, std::string* error)>
        adapter;
};

/// What `device <parallel gripper>` keeps alive, destroyed in reverse: the adapter first (it
/// closes the serial line), then the simulated gripper, then the world link it reports
/// through.
struct ParallelGripperContent {
    std::unique_ptr<devices::WorldLink> world;
    std::shared_ptr<void> simulated;
    std::shared_ptr<devices::GripperComponent> adapter;
};

/// How long a simulated gripper's sensor waits for a world that is restarting: behind a
/// Modbus reply (its timeout is 1 s), and behind an in-process call.
constexpr std::chrono::milliseconds kSensorPatience{400};
constexpr std::chrono::milliseconds kInProcessSensorPatience{5000};

/// The fingers close along the grip point's y axis: what they meet is the object's extent
/// along it; grasps and releases go to the world model.
FingerWiring wireFingers(devices::WorldLink* world) {
    FingerWiring wiring;
    if (world == nullptr) return wiring;
    wiring.probe = [world]() -> devices::Probed {
        // Briefly: the controller's reply waits for it (its Modbus timeout is 1 s). A world
        // still out of reach then is asked again on the next status read; the fingers wait.
        const auto found =
            world->untilHeard([world] { return world->objectAtGripPoint(); }, kSensorPatience);
        if (!found && ua::isTransient(found.status())) return devices::Probed::unknown();
        if (!found || !found->has_value()) return devices::Probed();
        return devices::Probed(
            devices::ObjectBetweenFingers{(*found)->objectId, (*found)->extent[1]});
    };
    wiring.onEvent = [world](const devices::FingerEvent& e) {
        const bool grasped = e.kind == devices::FingerEvent::Kind::Grasped;
        world->tell([world, grasped,
                     id = e.objectId] { return grasped ? world->grasp(id) : world->release(); },
                    std::string(grasped ? "grasp" : "release") + " of " + e.objectId);
    };
    wiring.worldBehind = [world] { return world->behind(); };
    // Held already: the fingers stand at the object's extent along the grip point's y axis.
    const auto held = world->graspedObject();
    if (held && !held->empty()) {
        const auto size = world->objectSize(*held);
        const auto pose = world->objectPose(*held);
        const auto grip = world->gripPoint();
        if (size && pose && grip) {
            const KDL::Vector across = grip->M.UnitY();
            double width = 0;
            for (int i = 0; i < 3; ++i) {
                const KDL::Vector axis = pose->M * KDL::Vector(i == 0, i == 1, i == 2);
                width += std::abs(KDL::dot(axis, across)) * (*size)[static_cast<std::size_t>(i)];
            }
            wiring.holding = devices::ObjectBetweenFingers{*held, width};
            spdlog::info("the fingers hold {} ({} m across) as the gripper starts", *held, width);
        }
    }
    return wiring;
}

ua::Result<ComponentContent> populateParallelGripper(
    const ParallelGripperModel& model, ParallelGripperOptions options, const ComponentContext& c,
    const std::shared_ptr<WorldConnection>& world) {
    auto content = std::make_shared<ParallelGripperContent>();
    if (options.serial.empty()) {
        if (world) {
            auto link = world->take();
            if (!link) return link.status();
            content->world = std::move(*link);
        }
        std::string why;
        auto simulated = model.simulate(options.speed, wireFingers(content->world.get()), &why);
        if (!simulated) {
            spdlog::critical("simulated {}: {}", model.simulatedName, why);
            return ua::status::BadResourceUnavailable;
        }
        options.serial = simulated->first;
        content->simulated = std::move(simulated->second);
        spdlog::info("simulated {} on {}", model.simulatedName, options.serial);
    }
    std::string error;
    auto adapter = model.adapter(c.server, options, &error);
    if (!adapter) {
        spdlog::critical("{}: {}", model.command, error);
        return adapter.status();
    }
    content->adapter = std::move(*adapter);
    content->adapter->setRobotUri(options.robotUri);
    return ComponentContent(content);
}

CLI::App* addParallelGripper(CLI::App* device, std::vector<Command>& commands,
                             const ParallelGripperModel& model) {
    auto options = std::make_shared<ParallelGripperOptions>();
    options->process.applicationUri = model.applicationUri;
    options->process.applicationName = model.applicationName;
    const auto models = devices::GripperComponent::skillModels();
    options->process.skillModels.assign(models.begin(), models.end());
    options->slaveId = model.slaveId;
    options->gripOffset = model.gripOffset;
    CLI::App* cmd = device->add_subcommand(model.command, model.description);
    addServerProcessOptions(cmd, options->process);
    addDiscoveryOptions(cmd, options->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--serial", options->serial,
                    "the gripper's serial device (e.g. /dev/ttyUSB0); empty: simulate one");
    cmd->add_option("--slave-id", options->slaveId, "the gripper's Modbus slave id")
        ->check(CLI::Range(1, 247))
        ->capture_default_str();
    cmd->add_option("--speed", options->speed, "simulated seconds per real second")
        ->check(CLI::Range(0.01, 1000.0))
        ->capture_default_str();
    cmd->add_option("--world", options->world.url,
                    "the world model's endpoint: the simulated gripper asks it what lies "
                    "between its fingers and reports grasps and releases");
    addWorldCertificateOption(cmd, options->world);
    addRobotOption(cmd, options->robot, "whose flange the gripper is mounted on");
    addRobotUriOption(cmd, options->robotUri);
    cmd->add_option("--grip-offset", options->gripOffset,
                    "the grip point from the tool mounting plate: X,Y,Z[,A,B,C] (m, rad)")
        ->check(poseText())
        ->capture_default_str();
    cmd->add_option("--finger-speed", options->fingerSpeed, "finger speed of every motion (m/s)")
        ->check(CLI::Range(0.02, model.maxFingerSpeed))
        ->capture_default_str();
    cmd->add_option("--grasp-force", options->graspForce, "grip force of Grasp (N)")
        ->check(CLI::Range(20.0, model.maxForce))
        ->capture_default_str();
    addBootProfileOption(cmd, options->bootProfile);
    commands.push_back(
        {cmd, [options, model] {
             options->process.boot = *devices::bootProfileNamed(options->bootProfile, false);
             // A simulated gripper's fingers ask the world what lies between them.
             std::shared_ptr<WorldConnection> world;
             if (options->serial.empty() && !options->world.empty()) {
                 world = std::make_shared<WorldConnection>(options->world, options->robot);
             }
             return runServerProcess(
                 options->process,
                 [options, model, world](const ComponentContext& c) {
                     return populateParallelGripper(model, *options, c, world);
                 },
                 connectEarly(world));
         }});
    return cmd;
}

/// A parallel gripper's command and URI, as cell files name them
/// (src/cell/device_arguments.cpp).
ParallelGripperModel fromAdapterModel(std::string_view name) {
    const cell::AdapterModel& model = *cell::findAdapterModel(name);
    ParallelGripperModel m;
    m.command = std::string(model.command);
    m.applicationUri = std::string(model.applicationUri);
    return m;
}

ParallelGripperModel robotiq2f85() {
    namespace rq = devices::robotiq;
    ParallelGripperModel m = fromAdapterModel("robotiq-2f85");
    m.applicationName = "skillcell Robotiq 2F-85";
    m.description =
        "Run the Robotiq 2F-85 adapter (Modbus RTU) with the skills Grasp, Release and "
        "MoveGripper (grip point PARALLEL). Without --serial it runs a simulated 2F-85 on a "
        "pseudo-terminal.";
    m.simulatedName = "2F-85";
    m.slaveId = rq::kSlaveId;
    m.gripOffset = "0,0,0.15";
    m.maxForce = 235;
    m.simulate = [](double speed, FingerWiring wiring,
                    std::string* why) -> ua::Result<std::pair<std::string, std::shared_ptr<void>>> {
        rq::SimulatedGripperOptions sim;
        sim.speed = speed;
        sim.probe = std::move(wiring.probe);
        sim.onEvent = std::move(wiring.onEvent);
        sim.worldBehind = std::move(wiring.worldBehind);
        sim.holding = std::move(wiring.holding);
        std::shared_ptr<rq::SimulatedGripperPort> port = rq::SimulatedGripperPort::open(sim, why);
        if (!port) return ua::status::BadResourceUnavailable;
        return std::pair{port->devicePath(), std::shared_ptr<void>(port)};
    };
    m.adapter = [](ua::Server& server, const ParallelGripperOptions& options,
                   std::string* error) -> ua::Result<std::shared_ptr<devices::GripperComponent>> {
        rq::RobotiqComponentOptions o;
        o.device = options.serial;
        o.slaveId = options.slaveId;
        o.gripPointOffset = toFrame(*parsePose6(options.gripOffset));  // checked by poseText()
        o.gripper.speed = options.fingerSpeed;
        o.gripper.graspForce = options.graspForce;
        auto component = rq::startRobotiqComponent(server, o, error);
        if (!component) return component.status();
        return std::shared_ptr<devices::GripperComponent>(std::move(*component));
    };
    return m;
}

ParallelGripperModel dhAg95() {
    namespace dh = devices::dh;
    ParallelGripperModel m = fromAdapterModel("dh-ag95");
    m.applicationName = "skillcell DH-Robotics AG-95";
    m.description =
        "Run the DH-Robotics AG-95 adapter (Modbus RTU) with the same skills as every "
        "parallel gripper: Grasp, Release and MoveGripper (grip point PARALLEL). Without "
        "--serial it runs a simulated AG-95 on a pseudo-terminal.";
    m.simulatedName = "AG-95";
    m.slaveId = dh::kSlaveId;
    m.gripOffset = "0,0,0.16";
    m.maxForce = dh::kMaximumForce;
    m.maxFingerSpeed = dh::kMaximumSpeed;
    m.simulate = [](double speed, FingerWiring wiring,
                    std::string* why) -> ua::Result<std::pair<std::string, std::shared_ptr<void>>> {
        dh::SimulatedAg95Options sim;
        sim.speed = speed;
        sim.probe = std::move(wiring.probe);
        sim.onEvent = std::move(wiring.onEvent);
        sim.worldBehind = std::move(wiring.worldBehind);
        sim.holding = std::move(wiring.holding);
        std::shared_ptr<dh::SimulatedAg95> gripper = dh::SimulatedAg95::open(sim, why);
        if (!gripper) return ua::status::BadResourceUnavailable;
        return std::pair{gripper->devicePath(), std::shared_ptr<void>(gripper)};
    };
    m.adapter = [](ua::Server& server, const ParallelGripperOptions& options,
                   std::string* error) -> ua::Result<std::shared_ptr<devices::GripperComponent>> {
        dh::Ag95ComponentOptions o;
        o.device = options.serial;
        o.slaveId = options.slaveId;
        o.gripPointOffset = toFrame(*parsePose6(options.gripOffset));  // checked by poseText()
        o.gripper.speed = options.fingerSpeed;
        o.gripper.graspForce = options.graspForce;
        auto component = dh::startAg95Component(server, o, error);
        if (!component) return component.status();
        return std::shared_ptr<devices::GripperComponent>(std::move(*component));
    };
    return m;
}

struct SchmalzOptions {
    ServerProcessOptions process;
    double speed = 1;
    WorldAddress world;
    std::string robot = kDefaultRobot;
    std::string robotUri;
    std::string gripOffset = "0,0,0.12";
    int port = 1;
    std::string bootProfile = "none";
};

/// What `device schmalz` keeps alive, destroyed in reverse: the adapter, the simulated
/// IO-Link master, the world link.
struct SchmalzContent {
    std::unique_ptr<devices::WorldLink> world;
    std::unique_ptr<devices::schmalz::SimulatedIoLinkMaster> master;
    std::unique_ptr<devices::GripperComponent> component;
};

ua::Result<ComponentContent> populateSchmalz(const SchmalzOptions& options,
                                             const ComponentContext& c,
                                             const std::shared_ptr<WorldConnection>& connection) {
    namespace sz = devices::schmalz;
    auto content = std::make_shared<SchmalzContent>();
    sz::EcbpiComponentOptions o;
    o.gripPointOffset = toFrame(*parsePose6(options.gripOffset));  // checked by poseText()
    o.gripper.port = options.port;
    if (connection) {
        auto link = connection->take();
        if (!link) return link.status();
        content->world = std::move(*link);
    }
    sz::SimulatedIoLinkOptions sim;
    sim.port = options.port;
    sim.speed = options.speed;
    if (devices::WorldLink* world = content->world.get()) {
        sim.probe = [world]() -> std::optional<std::string> {
            // The simulated IO-Link master is called in-process, with no reply timeout: the
            // switch may wait for a world that restarts as long as it usually takes.
            const auto found = world->untilHeard([world] { return world->objectAtGripPoint(); },
                                                 kInProcessSensorPatience);
            if (!found || !found->has_value()) return std::nullopt;
            return (*found)->objectId;
        };
        sim.onEvent = [world](const sz::CupEvent& e) {
            const bool grasped = e.kind == sz::CupEvent::Kind::Grasped;
            world->tell([world, grasped,
                         id = e.partId] { return grasped ? world->grasp(id) : world->release(); },
                        std::string(grasped ? "grasp" : "release") + " of " + e.partId);
        };
        sim.worldBehind = [world] { return world->behind(); };
        sim.awaitWorld = [world] { return world->waitUntilHeard(kInProcessSensorPatience); };
        // Held already (an adapter restarted while the cup holds a part): still sucking.
        if (const auto held = world->graspedObject(); held && !held->empty()) {
            sim.holding = *held;
            spdlog::info("the cup holds {} as the generator starts", *held);
        }
    }
    content->master = std::make_unique<sz::SimulatedIoLinkMaster>(sim);
    std::string error;
    auto component = sz::startEcbpiComponent(c.server, *content->master, o, &error);
    if (!component) {
        spdlog::critical("schmalz: {}", error);
        return component.status();
    }
    content->component = std::move(*component);
    content->component->setRobotUri(options.robotUri);
    return ComponentContent(content);
}

CLI::App* addSchmalz(CLI::App* device, std::vector<Command>& commands) {
    auto options = std::make_shared<SchmalzOptions>();
    // Its command and URI, as cell files name them (src/cell/device_arguments.cpp).
    const cell::AdapterModel& model = *cell::findAdapterModel("schmalz-ecbpi");
    options->process.applicationUri = std::string(model.applicationUri);
    options->process.applicationName = "skillcell Schmalz ECBPi";
    const auto models = devices::GripperComponent::skillModels();
    options->process.skillModels.assign(models.begin(), models.end());
    CLI::App* cmd = device->add_subcommand(
        std::string(model.command),
        "Run the Schmalz ECBPi vacuum gripper adapter (IO-Link process data) with the skills "
        "Grasp and Release (grip point VACUUM), on a simulated IO-Link master and ECBPi.");
    addServerProcessOptions(cmd, options->process);
    addDiscoveryOptions(cmd, options->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--speed", options->speed, "simulated seconds per real second")
        ->check(CLI::Range(0.01, 1000.0))
        ->capture_default_str();
    cmd->add_option("--world", options->world.url,
                    "the world model's endpoint: the simulated ECBPi asks it what is under the "
                    "cup and reports grasps and releases");
    addWorldCertificateOption(cmd, options->world);
    addRobotOption(cmd, options->robot, "whose flange the gripper is mounted on");
    addRobotUriOption(cmd, options->robotUri);
    cmd->add_option("--grip-offset", options->gripOffset,
                    "the grip point (the cup's face) from the tool mounting plate: "
                    "X,Y,Z[,A,B,C] (m, rad)")
        ->check(poseText())
        ->capture_default_str();
    cmd->add_option("--io-link-port", options->port, "the IO-Link master port of the ECBPi")
        ->check(CLI::Range(1, 8))
        ->capture_default_str();
    addBootProfileOption(cmd, options->bootProfile);
    commands.push_back(
        {cmd, [options] {
             // The Schmalz board also initialises its IO-Link master.
             options->process.boot = *devices::bootProfileNamed(options->bootProfile, true);
             std::shared_ptr<WorldConnection> world;
             if (!options->world.empty()) {
                 world = std::make_shared<WorldConnection>(options->world, options->robot);
             }
             return runServerProcess(
                 options->process,
                 [options, world](const ComponentContext& c) {
                     return populateSchmalz(*options, c, world);
                 },
                 connectEarly(world));
         }});
    return cmd;
}

/// What every composite (tool changer, pick and place) shares: a server that uses the cell's
/// skills (found by discovery), the world model, and how long to wait for a skill to appear.
struct CompositeOptions {
    ServerProcessOptions process;
    WorldAddress world;
    int detectionTimeoutMs = 30'000;
};

void addCompositeOptions(CLI::App* cmd, CompositeOptions& options, const char* worldHelp) {
    options.process.usesDetector = true;
    options.process.detectsItself = false;
    addServerProcessOptions(cmd, options.process);
    addDiscoveryOptions(cmd, options.process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--world", options.world.url, worldHelp)->required();
    addWorldCertificateOption(cmd, options.world);
    cmd->add_option("--detection-timeout-ms", options.detectionTimeoutMs,
                    "how long to wait for a skill it needs (the robot's moves, a tool's skills) "
                    "to be detected")
        ->check(CLI::Range(100, 600'000))
        ->capture_default_str();
}

/// How a composite connects to the robot and the tools: as the component itself, with sessions
/// that are its short lease on them (devices::kCompositeSessionTimeout).
ua::ClientConfig compositeClient(const ComponentContext& c, const char* sessionName) {
    ua::ClientConfig config;
    config.applicationUri = c.applicationUri;
    config.sessionName = sessionName;
    config.security = c.clientSecurity;
    config.sessionTimeoutMs = static_cast<double>(devices::kCompositeSessionTimeout.count());
    return config;
}

struct ToolChangerOptions {
    CompositeOptions composite;
    std::vector<std::string> tools;  // ID:MIN-MAX:APPLICATION-URI
    std::vector<std::string> power;  // ID=PROGRAM ARG...
    int moveTimeoutMs = 60'000;
    std::string dockMap;  // empty: in memory only
    std::string robot = kDefaultRobot;
    std::string robotUri;  // empty: the robot discovery finds first
};

/// What `device toolchanger` keeps alive, destroyed in reverse: the component (it powers the
/// tools off), the simulated coupling, the tools' resistors it reads, the world link.
struct ToolChangerContent {
    std::unique_ptr<devices::WorldLink> world;
    devices::toolchanger::ToolTable resistors;
    std::unique_ptr<devices::toolchanger::SimulatedKelvinChanger> coupling;
    std::unique_ptr<devices::toolchanger::ToolChangerComponent> component;
};

ua::Result<ComponentContent> populateToolChanger(const ToolChangerOptions& options,
                                                 const std::shared_ptr<WorldConnection>& world,
                                                 const ComponentContext& c) {
    namespace tc = devices::toolchanger;
    tc::ToolTable tools;
    std::string why;
    for (const auto& spec : options.tools) {
        if (const auto s = tools.add(spec, &why); s.isBad()) {
            spdlog::critical("--tool {}: {}", spec, why);
            return s;
        }
    }
    for (const auto& spec : options.power) {
        if (const auto s = tools.setPowerCommand(spec, &why); s.isBad()) {
            spdlog::critical("--power {}: {}", spec, why);
            return s;
        }
    }
    auto content = std::make_shared<ToolChangerContent>();
    auto link = world->take();
    if (!link) return link.status();
    content->world = std::move(*link);
    // The simulated coupling keeps its own copy of the table: the tools' resistors.
    content->resistors = tools;
    content->coupling =
        std::make_unique<tc::SimulatedKelvinChanger>(*content->world, content->resistors);
    tc::ToolChangerOptions o;
    o.detectionTimeout = std::chrono::milliseconds(options.composite.detectionTimeoutMs);
    o.robotUri = options.robotUri;
    o.moveTimeout = std::chrono::milliseconds(options.moveTimeoutMs);
    o.client = compositeClient(c, "tool changer");
    o.dockMapFile = options.dockMap;
    std::string error;
    auto component = tc::ToolChangerComponent::create(c.server, *content->coupling,
                                                      std::move(tools), c.detector, o, &error);
    if (!component) {
        spdlog::critical("toolchanger: {}", error);
        return component.status();
    }
    content->component = std::move(*component);
    return ComponentContent(content);
}

CLI::App* addToolChanger(CLI::App* device, std::vector<Command>& commands) {
    auto options = std::make_shared<ToolChangerOptions>();
    options->composite.process.applicationUri = std::string(cell::kToolChangerUri);
    options->composite.process.applicationName = "skillcell Kelvin tool changer";
    const auto models = devices::toolchanger::ToolChangerComponent::skillModels();
    options->composite.process.skillModels.assign(models.begin(), models.end());
    CLI::App* cmd = device->add_subcommand(
        "toolchanger",
        "Run the Kelvin tool changer with the skills AttachTool, DetachTool and ChangeTool. "
        "It moves the robot with its CartesianLinearMove skill (the one discovery finds, or "
        "MoveSkillControllerEndpoint), knows a tool by the voltage of its identification "
        "pin, and powers an attached tool by starting its adapter process (--power); an "
        "attach ends when the tool's adapter is detected.");
    addCompositeOptions(cmd, options->composite,
                        "the world model's endpoint: the simulated coupling locks and opens "
                        "there");
    addRobotOption(cmd, options->robot, "whose flange the changer is on");
    cmd->add_option("--robot-uri", options->robotUri,
                    "the application URI of that robot, whose move skill the changer uses when "
                    "a request names none; empty: the first one discovery finds (a cell with "
                    "one robot)");
    cmd->add_option("--tool", options->tools,
                    "a tool: ID:MIN-MAX:APPLICATION-URI (its world model id, its voltage band "
                    "on the identification pin, the application URI of its adapter)")
        ->required()
        ->check(CLI::Validator(
            [](std::string& spec) {
                devices::toolchanger::ToolTable one;
                std::string why;
                return one.add(spec, &why).isBad() ? why : std::string();
            },
            "TOOL"));
    cmd->add_option("--power", options->power,
                    "the adapter process of a tool, started when it is attached: "
                    "ID=PROGRAM ARG... (split at blanks)");
    cmd->add_option("--dock-map", options->dockMap,
                    "a file where the changer keeps the dock of each tool it took, so that it "
                    "can put the mounted tool back after a restart (JSON, written atomically; "
                    "default: in memory only)");
    cmd->add_option("--move-timeout-ms", options->moveTimeoutMs, "the longest move")
        ->check(CLI::Range(100, 600'000))
        ->capture_default_str();
    commands.push_back({cmd, [options] {
                            auto world = std::make_shared<WorldConnection>(options->composite.world,
                                                                           options->robot);
                            return runServerProcess(
                                options->composite.process,
                                [options, world](const ComponentContext& c) {
                                    return populateToolChanger(*options, world, c);
                                },
                                connectEarly(world));
                        }});
    return cmd;
}

struct PickPlaceOptions {
    CompositeOptions composite;
    int skillTimeoutMs = 60'000;
    double approachDistance = devices::pickplace::kDefaultApproachDistance;
};

/// What `device pickplace` keeps alive, destroyed in reverse: the component, the world link.
struct PickPlaceContent {
    std::unique_ptr<devices::WorldLink> world;
    std::unique_ptr<devices::pickplace::PickAndPlaceComponent> component;
};

CLI::App* addPickPlace(CLI::App* device, std::vector<Command>& commands) {
    auto options = std::make_shared<PickPlaceOptions>();
    options->composite.process.applicationUri = std::string(cell::kPickAndPlaceUri);
    options->composite.process.applicationName = "skillcell pick and place";
    const auto models = devices::pickplace::PickAndPlaceComponent::skillModels();
    options->composite.process.skillModels.assign(models.begin(), models.end());
    CLI::App* cmd = device->add_subcommand(
        "pickplace",
        "Run the pick-and-place composite with the skills PickAndPlace and "
        "PlaceTerminalBlock: it reads the object from the world model and the grip point from "
        "the tool's Grasp skill, plans the approach (vacuum from the top, parallel from the "
        "side, 5 cm off; a terminal block from the top, hooked over a DIN rail's upper edge and "
        "rotated down until it snaps), and runs the robot's CartesianLinearMove and the tool's "
        "Grasp and Release (the ones discovery finds, or the endpoints given). "
        "Objects/PickAndPlace/CurrentStep shows its step.");
    addCompositeOptions(cmd, options->composite,
                        "the world model's endpoint: where the objects' boxes and poses are "
                        "read");
    cmd->add_option("--approach-distance", options->approachDistance,
                    "how far off the grasp and place poses the approaches are (m)")
        ->check(CLI::Range(0.0, 0.3))
        ->capture_default_str();
    cmd->add_option("--skill-timeout-ms", options->skillTimeoutMs, "the longest sub-skill")
        ->check(CLI::Range(100, 600'000))
        ->capture_default_str();
    commands.push_back(
        {cmd, [options] {
             auto world = std::make_shared<WorldConnection>(options->composite.world, "");
             return runServerProcess(
                 options->composite.process,
                 [options, world](const ComponentContext& c) -> ua::Result<ComponentContent> {
                     namespace pp = devices::pickplace;
                     auto content = std::make_shared<PickPlaceContent>();
                     auto link = world->take();
                     if (!link) return link.status();
                     content->world = std::move(*link);
                     pp::PickAndPlaceOptions o;
                     o.approachDistance = options->approachDistance;
                     o.detectionTimeout =
                         std::chrono::milliseconds(options->composite.detectionTimeoutMs);
                     o.skillTimeout = std::chrono::milliseconds(options->skillTimeoutMs);
                     o.client = compositeClient(c, "pick and place");
                     std::string error;
                     auto component = pp::PickAndPlaceComponent::create(c.server, *content->world,
                                                                        c.detector, o, &error);
                     if (!component) {
                         spdlog::critical("pickplace: {}", error);
                         return component.status();
                     }
                     content->component = std::move(*component);
                     return ComponentContent(content);
                 },
                 connectEarly(world));
         }});
    return cmd;
}

/// A device kind by its subcommand's name, and what adds that subcommand.
struct DeviceKind {
    std::string_view name;
    void (*add)(CLI::App* device, std::vector<Command>& commands);
};

constexpr std::array kDeviceKinds{
    DeviceKind{"world", [](CLI::App* d, std::vector<Command>& c) { addWorld(d, c); }},
    DeviceKind{"ur5",
               [](CLI::App* d, std::vector<Command>& c) {
                   addArm(d, c, "ur5", cell::kUr5Uri, devices::ArmModel::ur5());
               }},
    DeviceKind{"iiwa",
               [](CLI::App* d, std::vector<Command>& c) {
                   addArm(d, c, "iiwa", cell::kIiwaUri, devices::ArmModel::lbrIiwa7());
               }},
    DeviceKind{"robotiq", [](CLI::App* d,
                             std::vector<Command>& c) { addParallelGripper(d, c, robotiq2f85()); }},
    DeviceKind{"ag95",
               [](CLI::App* d, std::vector<Command>& c) { addParallelGripper(d, c, dhAg95()); }},
    DeviceKind{"schmalz", [](CLI::App* d, std::vector<Command>& c) { addSchmalz(d, c); }},
    DeviceKind{"toolchanger", [](CLI::App* d, std::vector<Command>& c) { addToolChanger(d, c); }},
    DeviceKind{"pickplace", [](CLI::App* d, std::vector<Command>& c) { addPickPlace(d, c); }},
};

}  // namespace

std::vector<Command> addDeviceCommands(CLI::App& app, std::string_view kind) {
    CLI::App* device = app.add_subcommand(
        "device", "Run one simulated device of the work cell as its own component");
    device->require_subcommand(1);
    std::vector<Command> commands;
    // Only the kind the command line names: every kind's options (and both arms' models)
    // were 0.6 ms of each device's start.
    const auto* named = std::find_if(kDeviceKinds.begin(), kDeviceKinds.end(),
                                     [&](const DeviceKind& k) { return k.name == kind; });
    if (named != kDeviceKinds.end()) {
        named->add(device, commands);
    } else {
        for (const auto& k : kDeviceKinds) k.add(device, commands);
    }
    return commands;
}

}  // namespace skillcell::apps
