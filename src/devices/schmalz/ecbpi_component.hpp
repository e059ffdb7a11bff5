#pragma once
// The Schmalz component: what `skillcell device schmalz` serves: the ECBPi adapter on an IO-Link
// master port and its skills Grasp and Release (grip point VACUUM at the given offset from
// the tool mounting plate). Build and destroy it on the server's thread.
#include <memory>
#include <string>

#include "devices/gripper/gripper_component.hpp"
#include "devices/schmalz/ecbpi_gripper.hpp"

namespace skillcell::devices::schmalz {

struct EcbpiComponentOptions {
    EcbpiComponentOptions() = default;
    /// The suction cup's face, 12 cm from the mounting plate along its z axis.
    KDL::Frame gripPointOffset = KDL::Frame(KDL::Vector(0, 0, 0.12));
    EcbpiGripperOptions gripper;
};

/// The ECBPi adapter on a port of `master` (which must outlive it) and its skills Grasp
/// and Release (a GripperComponent).
[[nodiscard]] ua::Result<std::unique_ptr<GripperComponent>> startEcbpiComponent(
    ua::Server& server, IoLinkMaster& master, const EcbpiComponentOptions& options,
    std::string* error = nullptr);

}  // namespace skillcell::devices::schmalz
