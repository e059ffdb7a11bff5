#include "devices/robotiq/robotiq_component.hpp"

namespace skillcell::devices::robotiq {

RobotiqComponent::~RobotiqComponent() = default;

ua::Result<std::unique_ptr<RobotiqComponent>> RobotiqComponent::create(
    ua::Server& server, const RobotiqComponentOptions& options, std::string* error) {
    auto component = std::make_unique<RobotiqComponent>(Token{});
    auto client = RobotiqClient::open(options.device, options.slaveId, error);
    if (!client) return client.status();
    component->gripper_ = RobotiqGripper::start(std::move(*client), options.gripper);
    component->skills_ = skills::SkillServer::create(server, server.executor(), error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    const auto s = addGripperSkills(*component->skills_, *component->gripper_,
                                    options.gripPointOffset, GripPointType::Parallel, error);
    if (s.isBad()) return s;
    return component;
}

}  // namespace skillcell::devices::robotiq
