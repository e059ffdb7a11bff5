#include "devices/schmalz/ecbpi_component.hpp"

namespace skillcell::devices::schmalz {

EcbpiComponent::~EcbpiComponent() = default;

ua::Result<std::unique_ptr<EcbpiComponent>> EcbpiComponent::create(
    ua::Server& server, IoLinkMaster& master, const EcbpiComponentOptions& options,
    std::string* error) {
    auto component = std::make_unique<EcbpiComponent>(Token{});
    component->gripper_ = EcbpiGripper::start(master, options.gripper);
    component->skills_ = skills::SkillServer::create(server, server.executor(), error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    const auto s = addGripperSkills(*component->skills_, *component->gripper_,
                                    options.gripPointOffset, GripPointType::Vacuum, error);
    if (s.isBad()) return s;
    return component;
}

}  // namespace skillcell::devices::schmalz
