#pragma once
// The AG-95 component: what `skillcell device ag95` serves: the AG-95 adapter on a serial device
// and the same skills as any parallel gripper: Grasp, Release and MoveGripper (grip point
// PARALLEL at the given offset from the tool mounting plate). Nothing above the adapter
// knows which model it is: swapping the 2F-85 for it changes no process and no MES.
// Build and destroy it on the server's thread.
#include <memory>
#include <string>

#include "devices/dh/ag95_gripper.hpp"
#include "devices/gripper/gripper_component.hpp"

namespace skillcell::devices::dh {

struct Ag95ComponentOptions {
    Ag95ComponentOptions() = default;
    std::string device;  // the serial device the gripper is on
    int slaveId = kSlaveId;
    /// The AG-95's fingertip centre, 16 cm from the mounting plate along its z axis.
    KDL::Frame gripPointOffset = KDL::Frame(KDL::Vector(0, 0, 0.16));
    Ag95GripperOptions gripper;
};

/// The AG-95 adapter on `options.device` and its skills (a GripperComponent).
[[nodiscard]] ua::Result<std::unique_ptr<GripperComponent>> startAg95Component(
    ua::Server& server, const Ag95ComponentOptions& options, std::string* error = nullptr);

}  // namespace skillcell::devices::dh
