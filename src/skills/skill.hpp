#pragma once
// Skill: one skill object in a component's address space, written once for every skill
// type (OPC 10000-10 program state machine; ARCHITECTURE.md, "The skill model").
//
// It instantiates its type (a concrete subtype of SkillType) so that the object has
// exactly the children the model declares, then owns them: CurrentState and
// LastTransition with their Id/Number/TransitionTime, the Start/Suspend/Resume/Halt/Reset
// methods and their interlocking (BadInvalidState for a method the state does not allow),
// a SkillTransitionEventType event on every change, and the ParameterSet: values are
// checked on write and again on Start, fixed for the run at Start, and the session that
// starts a run reserves the skill until the run ends (docs/skill-parameters.md).
//
// Threading: the address space and the behaviour are touched on the server's io_context
// thread only. state() may be read from any thread; fault() and SkillRun reports may be
// called from any thread (they are posted to the io_context).
#include <asio/any_io_executor.hpp>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "skills/skill_behaviour.hpp"
#include "skills/skill_parameters.hpp"
#include "skills/skill_state_machine.hpp"
#include "ua/server/server.hpp"

namespace skillcell::skills {

struct SkillConfig {
    // Not an aggregate (GCC 12's co_await aggregate bug, see ua::ClientConfig).
    SkillConfig() = default;
    SkillConfig(ua::NodeId skillType, ua::NodeId parentNode, std::string browseName)
        : type(std::move(skillType)), parent(std::move(parentNode)), name(std::move(browseName)) {}

    ua::NodeId type;    // a concrete subtype of SkillType
    ua::NodeId parent;  // the object or folder the skill is a component of
    std::string name;   // browse name, in the parent's namespace
    ua::NodeId nodeId;  // null: derived from the parent's id and the name
    SkillState initialState = SkillState::Ready;
    /// The component's reservation (reservation.hpp): while someone holds it, only its
    /// sessions may write parameters or call methods. Null: no reservation.
    std::shared_ptr<const class Reservation> reservation;
};

class Skill : public std::enable_shared_from_this<Skill> {
public:
    /// Builds the skill object in `server`'s address space (on the io_context thread, before
    /// or while the server runs). BadTypeDefinitionInvalid for a type that is not a concrete
    /// subtype of SkillType, BadNodeIdExists, BadInvalidArgument for a Halted/Ready initial
    /// state other than those two; the instantiation's status otherwise.
    [[nodiscard]] static ua::Result<std::shared_ptr<Skill>> create(
        ua::Server& server, asio::any_io_executor executor, const SkillConfig& config,
        std::unique_ptr<SkillBehaviour> behaviour);
    struct Token {  // lets create() use make_shared while the constructor stays private
    private:
        friend class Skill;
        Token() = default;
    };
    Skill(Token, ua::Server& server, asio::any_io_executor executor,
          std::unique_ptr<SkillBehaviour> behaviour);
    ~Skill();
    Skill(const Skill&) = delete;
    Skill& operator=(const Skill&) = delete;

    [[nodiscard]] const ua::NodeId& nodeId() const { return nodeId_; }
    [[nodiscard]] const ua::NodeId& type() const { return type_; }
    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] SkillState state() const { return state_.load(); }
    [[nodiscard]] const std::vector<ParameterDeclaration>& parameters() const {
        return parameters_;
    }
    [[nodiscard]] SkillBehaviour& behaviour() { return *behaviour_; }

    /// Runs a method as the Call service does for `caller` (io_context thread): Good, or
    /// BadInvalidState, BadUserAccessDenied, or the status of a parameter that fails its
    /// check at Start (the skill then stays Ready).
    ua::StatusCode invoke(SkillMethod method, const ua::Caller& caller = {});

    /// A fault the device reports outside a run, or that ends one: the skill goes to
    /// Halted with `reason` (from Ready, Running or Suspended; nothing happens in Halted).
    void fault(std::string reason);

private:
    friend class SkillRun;
    ua::StatusCode build(const SkillConfig& config);
    ua::StatusCode installMethods();
    void installParameterChecks();
    /// The run `runId` reported its end (io_context thread).
    void runEnded(std::uint64_t runId, bool success, std::string reason);
    /// True when `caller` may not act on the skill: another live session holds its run, or
    /// the component's reservation is not `caller`'s.
    [[nodiscard]] bool reservedAgainst(const ua::Caller& caller) const;
    [[nodiscard]] ua::StatusCode fixParameters(SkillParameters& out) const;
    void enter(SkillTransition transition, const std::string& reason = {});
    void publishState(SkillState state);

    ua::Server& server_;
    asio::any_io_executor executor_;
    std::unique_ptr<SkillBehaviour> behaviour_;
    ua::NodeId nodeId_;
    ua::NodeId type_;
    std::string name_;
    ua::NodeId eventType_;
    std::vector<ParameterDeclaration> parameters_;
    std::atomic<SkillState> state_{SkillState::Ready};
    ua::NodeId owner_;  // the session holding the current run; null when none
    std::shared_ptr<const Reservation> reservation_;
    std::uint64_t runId_ = 0;
    bool runActive_ = false;
};

}  // namespace skillcell::skills
