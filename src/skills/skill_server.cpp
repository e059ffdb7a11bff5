#include "skills/skill_server.hpp"

#include <algorithm>

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
    // One pass over the nodes (an arm's are some two thousand): the skill types of that
    // name. The companion models' come first, in their order; then those of the models
    // loaded besides them (a NodeSet2 file of a skill type of one's own), by namespace.
    const auto rank = [&as](const ua::Node& n) {
        const std::uint16_t ns = n.browseName.namespaceIndex;
        const auto& uri = as.namespaces()[ns];
        const auto* model =
            std::find_if(ua::kCompanionModels.begin(), ua::kCompanionModels.end(),
                         [&uri](const ua::CompanionModel& m) { return m.uri == uri; });
        return static_cast<std::size_t>(model - ua::kCompanionModels.begin()) +
               (model == ua::kCompanionModels.end() ? ns : 0);
    };
    std::optional<ua::NodeId> found;
    std::size_t foundRank = 0;
    as.forEachNode([&](const ua::Node& n) {
        if (n.nodeClass != ua::NodeClass::ObjectType || n.browseName.name != typeName ||
            n.browseName.namespaceIndex >= as.namespaces().size()) {
            return;
        }
        const std::size_t r = rank(n);
        if ((!found || r < foundRank) && as.isSubtypeOf(n.nodeId, *skillType)) {
            found = n.nodeId;
            foundRank = r;
        }
    });
    return found;
}

}  // namespace skillcell::skills
