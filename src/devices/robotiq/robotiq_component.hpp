#pragma once
// The Robotiq component: what `skillcell device robotiq` serves: the 2F-85 adapter on a serial
// device and its skills Grasp, Release and MoveGripper (grip point PARALLEL at the given
// offset from the tool mounting plate). Build and destroy it on the server's thread.
#include <memory>
#include <string>

#include "devices/gripper/gripper_component.hpp"
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

/// The 2F-85 adapter on `options.device` and its skills (a GripperComponent).
[[nodiscard]] ua::Result<std::unique_ptr<GripperComponent>> startRobotiqComponent(
    ua::Server& server, const RobotiqComponentOptions& options, std::string* error = nullptr);

}  // namespace skillcell::devices::robotiq
