#include "devices/schmalz/ecbpi_component.hpp"

namespace skillcell::devices::schmalz {

ua::Result<std::unique_ptr<GripperComponent>> startEcbpiComponent(
    ua::Server& server, IoLinkMaster& master, const EcbpiComponentOptions& options,
    std::string* error) {
    return GripperComponent::create(server, EcbpiGripper::start(master, options.gripper),
                                    options.gripPointOffset, GripPointType::Vacuum, error);
}

}  // namespace skillcell::devices::schmalz
