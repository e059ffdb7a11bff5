#pragma once
// Ur5Component: everything `skillcell device ur5` serves: the simulated arm, the four
// move skills in Objects/Skills (CartesianLinearMove, CartesianPtpMove, JointLinearMove,
// JointPtpMove) and Objects/UR5 with the arm's state as variables (JointPositions,
// FlangePose, TcpPose, ToolFrame: the ToolFrame of the last move, which defines the TCP),
// and the arm in the Robotics model: DeviceSet/UR5System/MotionDevices/UR5 with its six axes'
// ActualPosition (motion_device_system.hpp).
// Build and destroy it on the server's io_context thread.
#include <functional>
#include <memory>
#include <optional>

#include "devices/common/motion_device_system.hpp"
#include "devices/ur5/motion_planner.hpp"
#include "devices/ur5/simulated_ur5.hpp"
#include "devices/ur5/ur5_kinematics.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::devices {

struct Ur5ComponentOptions {
    Ur5ComponentOptions() = default;
    SimulatedUr5Options arm;
    MoveDefaults defaults;
    /// Hears every new flange pose (e.g. to report it to the world model). Must not block.
    std::function<void(const KDL::Frame&)> onFlange;
};

class Ur5Component {
public:
    [[nodiscard]] static ua::Result<std::unique_ptr<Ur5Component>> create(
        ua::Server& server, Ur5ComponentOptions options, std::string* error = nullptr);
    ~Ur5Component();
    Ur5Component(const Ur5Component&) = delete;
    Ur5Component& operator=(const Ur5Component&) = delete;

    [[nodiscard]] SimulatedUr5& arm() { return *arm_; }
    [[nodiscard]] const Ur5Kinematics& kinematics() const { return kinematics_; }
    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }
    [[nodiscard]] const ua::NodeId& robotNode() const { return robot_; }

    struct Token {
    private:
        friend class Ur5Component;
        Token() = default;
    };
    Ur5Component(Token, ua::Server& server, Ur5ComponentOptions options);

private:
    ua::StatusCode build(std::string* error);
    void publish(const Joints& q);

    ua::Server& server_;
    Ur5ComponentOptions options_;
    Ur5Kinematics kinematics_;
    MotionPlanner planner_;
    ua::NodeId robot_;
    KDL::Frame toolFrame_ = KDL::Frame::Identity();
    std::optional<MotionDeviceSystem> motionDevice_;  // DeviceSet/UR5System (Robotics model)
    std::unique_ptr<SimulatedUr5> arm_;
    // After the arm: the skills' behaviours refer to it, so they go first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices
