#include "devices/dh/ag95_component.hpp"

namespace skillcell::devices::dh {

ua::Result<std::unique_ptr<GripperComponent>> startAg95Component(
    ua::Server& server, const Ag95ComponentOptions& options, std::string* error) {
    auto line = ModbusRtuMaster::open(options.device, kBaudRate, options.slaveId, error);
    if (!line) return line.status();
    return GripperComponent::create(server, Ag95Gripper::start(std::move(*line), options.gripper),
                                    options.gripPointOffset, error);
}

}  // namespace skillcell::devices::dh
