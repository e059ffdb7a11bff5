#pragma once
// SkillServer: the skills of one component, served by its ua::Server. It loads the
// companion models its skill types come from (all of them unless told which), keeps a "Skills"
// folder under Objects, and creates each skill there from a type and a behaviour, all under one
// Objects/Reservation. A device adapter is a SkillServer plus one SkillBehaviour per skill.
#include <asio/any_io_executor.hpp>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "skills/reservation.hpp"
#include "skills/skill.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::skills {

class SkillServer {
public:
    /// Loads every companion model (if the address space lacks them) and adds the folder
    /// Objects/Skills. On failure `error` (if given) says why.
    [[nodiscard]] static std::unique_ptr<SkillServer> create(ua::Server& server,
                                                             asio::any_io_executor executor,
                                                             std::string* error = nullptr);
    /// The same with only the companion models `models` (namespace URIs, see
    /// ua::companion), the Skills model and what they require: the types a component's skills
    /// are of, without the parse of models it does not use at each start.
    [[nodiscard]] static std::unique_ptr<SkillServer> create(
        ua::Server& server, asio::any_io_executor executor,
        std::span<const std::string_view> models, std::string* error = nullptr);
    /// Loads what create() with `models` loads (the Skills model, `models` and what they
    /// require) into `as`, where that is missing: a server process does it beside namespace
    /// 0, on a thread of its own, before the server exists (runServerProcess).
    [[nodiscard]] static ua::NodeSetStatus loadModels(ua::AddressSpace& as,
                                                      std::span<const std::string_view> models);

    /// Adds a skill of `type` named `name` to the Skills folder.
    [[nodiscard]] ua::Result<std::shared_ptr<Skill>> add(
        const ua::NodeId& type, std::string name, std::unique_ptr<SkillBehaviour> behaviour,
        SkillState initialState = SkillState::Ready);
    /// The skill type called `typeName` (e.g. "CartesianLinearMoveSkillType") in one of the
    /// companion models, else in another model loaded into the server; for command lines.
    /// nullopt if there is none.
    [[nodiscard]] std::optional<ua::NodeId> findSkillType(std::string_view typeName) const;

    [[nodiscard]] const ua::NodeId& folder() const { return folder_; }
    /// Objects/Reservation: who may drive these skills (reservation.hpp).
    [[nodiscard]] const std::shared_ptr<Reservation>& reservation() const { return reservation_; }
    [[nodiscard]] const std::vector<std::shared_ptr<Skill>>& skills() const { return skills_; }
    [[nodiscard]] ua::Server& server() { return server_; }

    struct Token {  // create() only
    private:
        friend class SkillServer;
        Token() = default;
    };
    SkillServer(Token, ua::Server& server, asio::any_io_executor executor)
        : server_(server), executor_(std::move(executor)) {}

private:
    ua::Server& server_;
    asio::any_io_executor executor_;
    ua::NodeId folder_;
    std::shared_ptr<Reservation> reservation_;
    std::vector<std::shared_ptr<Skill>> skills_;
};

}  // namespace skillcell::skills
