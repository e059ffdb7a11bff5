#pragma once
// MesComponent: what `skillcell mes` serves over a ProcessExecutor: Objects/Orders (orders:
// submit, cancel, list, follow; order_nodes.hpp), the ExecuteProcess skill (ProcessIri: an
// order followed to its end, for clients that know skills only), and Objects/ProcessExecution,
// whose variables show the latest progress of any order (Run, Step, Steps, SkillType,
// Component, Skill, State, Message, and all of it as one line in Progress). On creation it
// resumes the orders the journal shows Queued or Running. Build and destroy it on the
// server's thread.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "mes/order_nodes.hpp"
#include "mes/process_executor.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::mes {

class MesComponent {
public:
    /// The companion models its skills are of: what a server process loads beside namespace
    /// 0 before it creates the component (skills::SkillServer::loadModels).
    [[nodiscard]] static std::span<const std::string_view> skillModels();
    [[nodiscard]] static ua::Result<std::unique_ptr<MesComponent>> create(
        ua::Server& server, std::shared_ptr<ProcessExecutor> executor,
        std::string* error = nullptr);
    ~MesComponent();
    MesComponent(const MesComponent&) = delete;
    MesComponent& operator=(const MesComponent&) = delete;

    struct Token {
    private:
        friend class MesComponent;
        Token() = default;
    };
    explicit MesComponent(Token) {}

private:
    std::shared_ptr<ProcessExecutor> executor_;
    std::unique_ptr<OrderNodes> orders_;
    std::unique_ptr<skills::SkillServer> skills_;  // after the executor: its behaviour uses it
};

/// The NodeIds of Objects/ProcessExecution's variables (ns=1, string ids).
[[nodiscard]] ua::NodeId progressVariable(const char* name);

}  // namespace skillcell::mes
