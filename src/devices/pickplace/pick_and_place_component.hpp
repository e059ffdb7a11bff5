#pragma once
// PickAndPlaceComponent: what `skillcell device pickplace` serves: the PickAndPlace skill
// over a PickAndPlace composite, and Objects/PickAndPlace/CurrentStep. Build and destroy it
// on the server's thread.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "devices/pickplace/pick_and_place.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::devices::pickplace {

class PickAndPlaceComponent {
public:
    /// The companion models its skills are of: what a server process loads beside namespace
    /// 0 before it creates the component (skills::SkillServer::loadModels).
    [[nodiscard]] static std::span<const std::string_view> skillModels();
    /// `world` must outlive the component.
    [[nodiscard]] static ua::Result<std::unique_ptr<PickAndPlaceComponent>> create(
        ua::Server& server, WorldLink& world, std::shared_ptr<skills::SkillDetector> detector,
        PickAndPlaceOptions options, std::string* error = nullptr);
    ~PickAndPlaceComponent();
    PickAndPlaceComponent(const PickAndPlaceComponent&) = delete;
    PickAndPlaceComponent& operator=(const PickAndPlaceComponent&) = delete;

    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }

    struct Token {
    private:
        friend class PickAndPlaceComponent;
        Token() = default;
    };
    explicit PickAndPlaceComponent(Token) {}

private:
    std::shared_ptr<PickAndPlace> composite_;
    // After the composite: the skill's behaviour refers to it, so it goes first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices::pickplace
