#include "devices/gripper/gripper_component.hpp"

#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices {

namespace {
// A gripper adapter's skills are of the GripperSkills model's types.
constexpr std::array<std::string_view, 1> kGripperSkillModels{ua::companion::kGripperSkillsUri};
}  // namespace

std::span<const std::string_view> GripperComponent::skillModels() {
    return kGripperSkillModels;
}

GripperComponent::~GripperComponent() = default;

ua::Result<std::unique_ptr<GripperComponent>> GripperComponent::create(
    ua::Server& server, std::unique_ptr<ParallelGripper> gripper, const KDL::Frame& offset,
    std::string* error) {
    auto component = std::make_unique<GripperComponent>(Token{});
    ParallelGripper& parallel = *gripper;
    component->gripper_ = std::move(gripper);
    component->skills_ =
        skills::SkillServer::create(server, server.executor(), kGripperSkillModels, error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    const auto s =
        addGripperSkills(*component->skills_, parallel, offset, GripPointType::Parallel, error);
    if (s.isBad()) return s;
    return component;
}

ua::Result<std::unique_ptr<GripperComponent>> GripperComponent::create(
    ua::Server& server, std::unique_ptr<Gripper> gripper, const KDL::Frame& offset,
    GripPointType type, std::string* error) {
    auto component = std::make_unique<GripperComponent>(Token{});
    component->gripper_ = std::move(gripper);
    component->skills_ =
        skills::SkillServer::create(server, server.executor(), kGripperSkillModels, error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    const auto s = addGripperSkills(*component->skills_, *component->gripper_, offset, type, error);
    if (s.isBad()) return s;
    return component;
}

void GripperComponent::setRobotUri(const std::string& uri) {
    ua::AddressSpace& as = skills_->server().addressSpace();
    for (const auto& skill : skills_->skills()) {
        for (const auto& p : skill->parameters()) {
            if (p.name == "RobotUri") (void)as.setValue(p.nodeId, ua::Variant(ua::String(uri)));
        }
    }
}

}  // namespace skillcell::devices
