#include "mes/mes_component.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>

#include "skills/skill_behaviour.hpp"
#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::mes {
namespace {

class ExecuteProcessBehaviour final : public skills::SkillBehaviour {
public:
    explicit ExecuteProcessBehaviour(std::shared_ptr<ProcessExecutor> executor)
        : executor_(std::move(executor)) {}

    void start(const skills::SkillParameters& p, skills::SkillRun run) override {
        std::string iri = p.get<ua::String>("ProcessIri").value_or("");
        if (iri.empty()) {
            run.failed("ProcessIri is empty: which process?");
            return;
        }
        asio::co_spawn(
            executor_->executor(),
            [executor = executor_, iri = std::move(iri), run]() -> asio::awaitable<void> {
                const ProcessOutcome outcome = co_await executor->execute(iri);
                if (outcome.completed) {
                    run.finished();
                } else {
                    run.failed(outcome.reason);
                }
            },
            asio::detached);
    }
    void suspend() override { executor_->suspend(); }
    void resume() override { executor_->resume(); }
    void halt() override { executor_->halt(); }

private:
    std::shared_ptr<ProcessExecutor> executor_;
};

constexpr const char* kTextVariables[] = {"ProcessIri", "SkillType", "Component", "Skill",
                                          "State",      "Message",   "Progress"};
constexpr const char* kNumberVariables[] = {"Run", "Step", "Steps"};

}  // namespace

ua::NodeId progressVariable(const char* name) {
    return ua::NodeId(1, ua::String(std::string("ProcessExecution/") + name));
}

MesComponent::~MesComponent() {
    if (executor_) {
        executor_->onProgress = nullptr;
        executor_->halt();
    }
}

ua::Result<std::unique_ptr<MesComponent>> MesComponent::create(
    ua::Server& server, std::shared_ptr<ProcessExecutor> executor, std::string* error) {
    auto component = std::make_unique<MesComponent>(Token{});
    ua::AddressSpace& as = server.addressSpace();
    const ua::NodeId object(1, ua::String("ProcessExecution"));
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), object, "ProcessExecution"); !r) {
        return r.status();
    }
    for (const char* name : kTextVariables) {
        if (auto r = as.addVariable(object, progressVariable(name), name,
                                    ua::NodeId(ua::ns0::String), ua::Variant(ua::String()),
                                    ua::access_level::kCurrentRead, ua::value_rank::kScalar);
            !r) {
            return r.status();
        }
    }
    for (const char* name : kNumberVariables) {
        if (auto r = as.addVariable(object, progressVariable(name), name,
                                    ua::NodeId(ua::ns0::Int32), ua::Variant(std::int32_t{0}),
                                    ua::access_level::kCurrentRead, ua::value_rank::kScalar);
            !r) {
            return r.status();
        }
    }
    executor->onProgress = [&as](const Progress& p) {
        const std::pair<const char*, const std::string*> texts[] = {
            {"ProcessIri", &p.processIri}, {"SkillType", &p.skillType}, {"Component", &p.component},
            {"Skill", &p.skill},           {"State", &p.state},         {"Message", &p.message}};
        for (const auto& [name, value] : texts) {
            (void)as.setValue(progressVariable(name), ua::Variant(ua::String(*value)));
        }
        (void)as.setValue(progressVariable("Progress"), ua::Variant(ua::String(p.line())));
        (void)as.setValue(progressVariable("Run"), ua::Variant(static_cast<std::int32_t>(p.run)));
        (void)as.setValue(progressVariable("Step"), ua::Variant(std::int32_t{p.step}));
        (void)as.setValue(progressVariable("Steps"), ua::Variant(std::int32_t{p.steps}));
    };
    component->executor_ = executor;
    component->skills_ = skills::SkillServer::create(server, server.executor(), error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    const auto type = component->skills_->findSkillType("ExecuteProcessSkillType");
    if (!type) {
        if (error != nullptr) *error = "no skill type ExecuteProcessSkillType";
        return ua::status::BadTypeDefinitionInvalid;
    }
    auto skill = component->skills_->add(*type, "ExecuteProcess",
                                         std::make_unique<ExecuteProcessBehaviour>(executor));
    if (!skill) {
        if (error != nullptr) *error = "cannot add ExecuteProcess";
        return skill.status();
    }
    return component;
}

}  // namespace skillcell::mes
