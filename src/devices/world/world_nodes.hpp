#pragma once
// WorldNodes: the OPC UA face of a World (docs/devices.md, "The world model"). It owns the
// World and serves it under Objects/World in the namespace kWorldNamespaceUri:
//
//   World/Robots/<id>/Base, FlangePose, GripPoint (3DFrame), MountedTool, GraspedObject
//       (String), ContactForce (Double, N)
//   World/Objects/<id>/Pose (3DFrame), Size (Double[3])
//   World/Tools/<id>/GripPoint (3DFrame)
//   World/Objects/<id>/Rail (String), RailPosition (Double, m): a terminal block's mount,
//       RailRefusal (String): why it lies loose on a rail, held
//   World/Docks/<id>/Pose (3DFrame), Tool (String)
//   World/Rails/<id>/Pose (3DFrame), Length, Width (Double, m)
//   methods on World: AddObject, AddTerminalBlock, AddRail, AddDock, AddTool, AddRobot,
//   MoveTool; and, each with the robot's id first, SetFlangePose, MountTool, UnmountTool,
//   DockAtFlange, Grasp, Release, ObjectAtGripPoint
//
// Every change goes through a method, so the World's consistency checks decide it; a
// refused change answers the World's status code (BadNotFound, BadInvalidState, ...) and
// logs the reason. Variables are updated after every change (subscriptions see it).
// Threading: the server's io_context thread only.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "devices/world/world.hpp"
#include "ua/server/server.hpp"

namespace skillcell::devices {

inline constexpr const char* kWorldNamespaceUri = "http://skillcell.dev/UA/World/";

class WorldNodes {
public:
    /// Adds the World object and its methods to `server`'s address space. With a
    /// `stateFile`, the world is saved there after every change (world_file.hpp).
    [[nodiscard]] static ua::Result<std::unique_ptr<WorldNodes>> create(
        ua::Server& server, World world = World(), std::filesystem::path stateFile = {});
    WorldNodes(const WorldNodes&) = delete;
    WorldNodes& operator=(const WorldNodes&) = delete;
    ~WorldNodes() = default;

    [[nodiscard]] const World& world() const { return world_; }
    /// Changes the world from the component itself (a scene file, a test) and republishes.
    template <class F>
    auto change(F f) {
        auto result = f(world_);
        sync();
        return result;
    }

    struct Token {
    private:
        friend class WorldNodes;
        Token() = default;
    };
    WorldNodes(Token, ua::Server& server, World world, std::uint16_t ns);

private:
    ua::StatusCode build();
    /// Adds nodes for what is new in the world and writes every value.
    void sync();
    [[nodiscard]] ua::NodeId id(const std::string& path) const;

    /// Saves the world to the state file when it changed since the last save.
    void save();

    ua::Server& server_;
    World world_;
    std::uint16_t ns_;
    std::filesystem::path stateFile_;
    std::optional<std::uint64_t> savedRevision_;
    bool saveFailed_ = false;  // said once, not on every change
};

}  // namespace skillcell::devices
