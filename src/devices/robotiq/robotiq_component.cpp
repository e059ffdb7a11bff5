#include "devices/robotiq/robotiq_component.hpp"

namespace skillcell::devices::robotiq {

ua::Result<std::unique_ptr<GripperComponent>> startRobotiqComponent(
    ua::Server& server, const RobotiqComponentOptions& options, std::string* error) {
    auto client = RobotiqClient::open(options.device, options.slaveId, error);
    if (!client) return client.status();
    return GripperComponent::create(server,
                                    RobotiqGripper::start(std::move(*client), options.gripper),
                                    options.gripPointOffset, error);
}

}  // namespace skillcell::devices::robotiq
