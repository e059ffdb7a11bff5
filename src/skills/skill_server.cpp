#include "skills/skill_server.hpp"

#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace skillcell::skills {

std::unique_ptr<SkillServer> SkillServer::create(ua::Server& server, asio::any_io_executor executor,
                                                 std::string* error) {
    std::vector<std::string_view> every;
    every.reserve(ua::kCompanionModels.size());
    for (const auto& model : ua::kCompanionModels) every.push_back(model.uri);
    return create(server, std::move(executor), every, error);
}

std::unique_ptr<SkillServer> SkillServer::create(ua::Server& server, asio::any_io_executor executor,
                                                 std::span<const std::string_view> models,
                                                 std::string* error) {
    ua::AddressSpace& as = server.addressSpace();
    const auto loaded = loadModels(as, models);
    if (!loaded.ok()) {
        if (error != nullptr) *error = "cannot load the skill models: " + loaded.error;
        return nullptr;
    }
    auto skills = std::make_unique<SkillServer>(Token{}, server, std::move(executor));
    // In the application's namespace, so that every component's skills have ids of the
    // same shape: ns=1;s=Skills/<name>.
    const ua::NodeId folder(1, ua::String("Skills"));
    if (as.find(folder) == nullptr) {
        auto added = as.addFolder(ua::NodeId(ua::ns0::ObjectsFolder), folder, "Skills");
        if (!added) {
            if (error != nullptr)
                *error =
                    "cannot add the Skills folder: " + std::string(ua::statusName(added.status()));
            return nullptr;
        }
    }
    skills->folder_ = folder;
    // One reservation per server: a second SkillServer on it (tests) goes without.
    if (as.find(reservationNode()) != nullptr) return skills;
    auto reservation = Reservation::create(server);
    if (!reservation) {
        if (error != nullptr)
            *error = "cannot add Objects/Reservation: " +
                     std::string(ua::statusName(reservation.status()));
        return nullptr;
    }
    skills->reservation_ = *reservation;
    return skills;
}

ua::NodeSetStatus SkillServer::loadModels(ua::AddressSpace& as,
                                          std::span<const std::string_view> models) {
    // Objects/Reservation is of a type of the Skills model, whatever the skills are.
    std::vector<std::string_view> uris{ua::companion::kSkillsUri};
    uris.insert(uris.end(), models.begin(), models.end());
    return ua::loadCompanionModels(as, uris);
}

ua::Result<std::shared_ptr<Skill>> SkillServer::add(const ua::NodeId& type, std::string name,
                                                    std::unique_ptr<SkillBehaviour> behaviour,
                                                    SkillState initialState) {
    SkillConfig config(type, folder_, std::move(name));
    config.initialState = initialState;
    config.reservation = reservation_;
    auto skill = Skill::create(server_, executor_, config, std::move(behaviour));
    if (!skill) return skill.status();
    skills_.push_back(*skill);
    return *skill;
}

std::optional<ua::NodeId> SkillServer::findSkillType(std::string_view typeName) const {
    const ua::AddressSpace& as = server_.addressSpace();
    const auto skillType = ua::skillsNodeId(as, ua::companion::kSkillType);
    if (!skillType) return std::nullopt;
    for (const auto& model : ua::kCompanionModels) {
        auto id = ua::findTypeByName(as, model.uri, typeName);
        if (id && as.isSubtypeOf(*id, *skillType)) return id;
    }
    // Then the models loaded besides them (a NodeSet2 file of a skill type of one's own).
    for (const auto& uri : as.namespaces()) {
        auto id = ua::findTypeByName(as, uri, typeName);
        if (id && as.isSubtypeOf(*id, *skillType)) return id;
    }
    return std::nullopt;
}

}  // namespace skillcell::skills
