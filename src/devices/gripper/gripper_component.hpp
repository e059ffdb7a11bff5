#pragma once
// GripperComponent: what a gripper's `skillcell device` command serves, whatever the model:
// its adapter (a Gripper) and the skills Grasp and Release, and MoveGripper for a
// ParallelGripper, with the grip point (offset from the tool mounting plate, and type) in
// their parameters. The model-specific part is only how its adapter is built
// (robotiq/robotiq_component, dh/ag95_component, schmalz/ecbpi_component), so nothing above
// the adapter knows which model it is. Build and destroy it on the server's thread.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "devices/gripper/gripper_skills.hpp"

namespace skillcell::devices {

class GripperComponent {
public:
    /// The companion models its skills are of: what a server process loads beside namespace
    /// 0 before it creates the component (skills::SkillServer::loadModels).
    [[nodiscard]] static std::span<const std::string_view> skillModels();
    /// A parallel gripper: Grasp, Release, MoveGripper; grip point PARALLEL.
    [[nodiscard]] static ua::Result<std::unique_ptr<GripperComponent>> create(
        ua::Server& server, std::unique_ptr<ParallelGripper> gripper, const KDL::Frame& offset,
        std::string* error = nullptr);
    /// Any gripper: Grasp and Release; grip point `type`.
    [[nodiscard]] static ua::Result<std::unique_ptr<GripperComponent>> create(
        ua::Server& server, std::unique_ptr<Gripper> gripper, const KDL::Frame& offset,
        GripPointType type, std::string* error = nullptr);
    ~GripperComponent();
    GripperComponent(const GripperComponent&) = delete;
    GripperComponent& operator=(const GripperComponent&) = delete;

    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }
    /// The robot that carries the gripper, as whoever mounted it says (its tool changer):
    /// every skill's RobotUri.
    void setRobotUri(const std::string& uri);

    struct Token {
    private:
        friend class GripperComponent;
        Token() = default;
    };
    explicit GripperComponent(Token) {}

private:
    std::unique_ptr<Gripper> gripper_;
    // After the gripper: the skills' behaviours refer to it, so they go first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices
