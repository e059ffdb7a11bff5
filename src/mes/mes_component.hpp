#pragma once
// MesComponent: what `skillcell mes` serves: the ExecuteProcess skill (ProcessIri) over a
// ProcessExecutor, and Objects/ProcessExecution, whose variables show what the MES is doing
// (Run, Step, Steps, SkillType, Component, Skill, State, Message, and all of it as one line in
// Progress, which `skillcell run` subscribes to). Build and destroy it on the server's thread.
#include <memory>
#include <string>

#include "mes/process_executor.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::mes {

class MesComponent {
public:
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
    std::unique_ptr<skills::SkillServer> skills_;  // after the executor: its behaviour uses it
};

/// The NodeIds of Objects/ProcessExecution's variables (ns=1, string ids).
[[nodiscard]] ua::NodeId progressVariable(const char* name);

}  // namespace skillcell::mes
