#pragma once
// ArmComponent: everything `skillcell device ur5` (or `device iiwa`) serves: the simulated
// arm of its ArmModel, the four move skills in Objects/Skills (CartesianLinearMove,
// CartesianPtpMove, JointLinearMove, JointPtpMove) and Objects/<model name> (Objects/UR5,
// Objects/LBRiiwa7) with the arm's state as variables (JointPositions, FlangePose, TcpPose,
// ToolFrame: the ToolFrame of the last move, which defines the TCP; ContactForce, N, for an
// arm that senses force, which also offers CartesianForceLimitedLinearMove), and the arm in the
// Robotics model: DeviceSet/<name>System/MotionDevices/<name> with each axis's
// ActualPosition (motion_device_system.hpp).
// Build and destroy it on the server's io_context thread.
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include "devices/arm/arm_kinematics.hpp"
#include "devices/arm/motion_planner.hpp"
#include "devices/arm/simulated_arm.hpp"
#include "devices/common/motion_device_system.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::devices {

struct ArmComponentOptions {
    ArmComponentOptions() = default;
    ArmModel model = ArmModel::ur5();
    SimulatedArmOptions arm;  // an empty `initial`: the model's home
    /// Where the arm's base stands in the cell's frame, in which its poses are given.
    KDL::Frame base = KDL::Frame::Identity();
    /// Hears every new flange pose (e.g. to report it to the world model). Must not block.
    std::function<void(const KDL::Frame&)> onFlange;
    /// Where the arm starts, asked once its models are loaded, so that a device that learns
    /// it from elsewhere (the world model) learns it meanwhile; empty joints: `arm.initial`.
    /// A bad status fails create(), with `why`.
    std::function<ua::Result<Joints>(std::string* why)> startingJoints;
};

class ArmComponent {
public:
    /// The companion models its skills are of: what a server process loads beside namespace
    /// 0 before it creates the component (skills::SkillServer::loadModels).
    [[nodiscard]] static std::span<const std::string_view> skillModels();
    [[nodiscard]] static ua::Result<std::unique_ptr<ArmComponent>> create(
        ua::Server& server, ArmComponentOptions options, std::string* error = nullptr);
    ~ArmComponent();
    ArmComponent(const ArmComponent&) = delete;
    ArmComponent& operator=(const ArmComponent&) = delete;

    [[nodiscard]] SimulatedArm& arm() { return *arm_; }
    [[nodiscard]] const ArmKinematics& kinematics() const { return kinematics_; }
    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }
    [[nodiscard]] const ua::NodeId& robotNode() const { return robot_; }

    struct Token {
    private:
        friend class ArmComponent;
        Token() = default;
    };
    ArmComponent(Token, ua::Server& server, ArmComponentOptions options);

private:
    ua::StatusCode build(std::string* error);
    [[nodiscard]] bool sensesForce() const {
        return options_.model.sensesForce && static_cast<bool>(options_.arm.contactForce);
    }
    void publish(const Joints& q);

    ua::Server& server_;
    ArmComponentOptions options_;
    ArmKinematics kinematics_;
    MotionPlanner planner_;
    ua::NodeId robot_;
    KDL::Frame toolFrame_ = KDL::Frame::Identity();
    std::optional<MotionDeviceSystem> motionDevice_;  // DeviceSet/<name>System (Robotics)
    std::unique_ptr<SimulatedArm> arm_;
    // After the arm: the skills' behaviours refer to it, so they go first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices
