#include "devices/dh/ag95_component.hpp"

namespace skillcell::devices::dh {

Ag95Component::~Ag95Component() = default;

ua::Result<std::unique_ptr<Ag95Component>> Ag95Component::create(
    ua::Server& server, const Ag95ComponentOptions& options, std::string* error) {
    auto component = std::make_unique<Ag95Component>(Token{});
    auto line = ModbusRtuMaster::open(options.device, kBaudRate, options.slaveId, error);
    if (!line) return line.status();
    component->gripper_ = Ag95Gripper::start(std::move(*line), options.gripper);
    component->skills_ = skills::SkillServer::create(server, server.executor(), error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    const auto s = addGripperSkills(*component->skills_, *component->gripper_,
                                    options.gripPointOffset, GripPointType::Parallel, error);
    if (s.isBad()) return s;
    return component;
}

}  // namespace skillcell::devices::dh
