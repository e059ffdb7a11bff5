#pragma once
// RobotiqComponent: what `skillcell device robotiq` serves: the 2F-85 adapter on a serial
// device and its skills Grasp, Release and MoveGripper (grip point PARALLEL at the given
// offset from the tool mounting plate). Build and destroy it on the server's thread.
#include <memory>
#include <string>

#include "devices/gripper/gripper_skills.hpp"
#include "devices/robotiq/robotiq_gripper.hpp"

namespace skillcell::devices::robotiq {

struct RobotiqComponentOptions {
    RobotiqComponentOptions() = default;
    std::string device;  // the serial device the gripper is on
    int slaveId = kSlaveId;
    /// The 2F-85's fingertip centre, 15 cm from the mounting plate along its z axis.
    KDL::Frame gripPointOffset = KDL::Frame(KDL::Vector(0, 0, 0.15));
    RobotiqGripperOptions gripper;
};

class RobotiqComponent {
public:
    [[nodiscard]] static ua::Result<std::unique_ptr<RobotiqComponent>> create(
        ua::Server& server, const RobotiqComponentOptions& options, std::string* error = nullptr);
    ~RobotiqComponent();
    RobotiqComponent(const RobotiqComponent&) = delete;
    RobotiqComponent& operator=(const RobotiqComponent&) = delete;

    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }

    struct Token {
    private:
        friend class RobotiqComponent;
        Token() = default;
    };
    explicit RobotiqComponent(Token) {}

private:
    std::unique_ptr<RobotiqGripper> gripper_;
    // After the gripper: the skills' behaviours refer to it, so they go first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices::robotiq
