#include "mes/mes_component.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>

#include "skills/skill_behaviour.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::mes {

namespace {
// Its skill is of the MesSkills model's type.
constexpr std::array<std::string_view, 1> kMesSkillModels{ua::companion::kMesSkillsUri};

// ExecuteProcess: an order of ProcessIri, followed to its end; Halt stops that order
// (resumably), Suspend and Resume go to its skills.
class ExecuteProcessBehaviour final : public skills::SkillBehaviour {
public:
    explicit ExecuteProcessBehaviour(std::shared_ptr<ProcessExecutor> executor)
        : executor_(std::move(executor)) {}

    void start(const skills::SkillParameters& p, skills::SkillRun run) override {
        const std::string iri = p.get<ua::String>("ProcessIri").value_or("");
        if (iri.empty()) {
            run.failed("ProcessIri is empty: which process?");
            return;
        }
        auto submitted = executor_->submit(iri);
        if (!submitted) {
            run.failed(submitted.error());
            return;
        }
        order_ = submitted->order;
        asio::co_spawn(
            executor_->executor(),
            [executor = executor_, order = order_, run]() -> asio::awaitable<void> {
                const ProcessOutcome outcome = co_await executor->outcome(order);
                if (outcome.completed) {
                    run.finished();
                } else {
                    run.failed(outcome.reason);
                }
            },
            asio::detached);
    }
    void suspend() override { executor_->suspend(order_); }
    void resume() override { executor_->resume(order_); }
    void halt() override { (void)executor_->stop(order_, /*cancel=*/false); }

private:
    std::shared_ptr<ProcessExecutor> executor_;
    std::int64_t order_ = 0;
};

constexpr const char* kTextVariables[] = {"ProcessIri", "SkillType", "Component", "Skill",
                                          "State",      "Message",   "Progress"};
constexpr const char* kNumberVariables[] = {"Run", "Step", "Steps"};

}  // namespace

ua::NodeId progressVariable(const char* name) {
    return ua::NodeId(1, ua::String(std::string("ProcessExecution/") + name));
}

std::span<const std::string_view> MesComponent::skillModels() {
    return kMesSkillModels;
}

MesComponent::~MesComponent() {
    if (executor_) {
        executor_->onProgress = nullptr;
        executor_->haltAll();
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
    auto orders = OrderNodes::create(as, executor, executor->journal());
    if (!orders) {
        if (error != nullptr) *error = "cannot add Objects/Orders";
        return orders.status();
    }
    component->orders_ = std::move(*orders);
    executor->onProgress = [&as, orders = component->orders_.get()](const Progress& p) {
        orders->show(p);
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
    component->skills_ =
        skills::SkillServer::create(server, server.executor(), kMesSkillModels, error);
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
    // The journal's open orders are shown at once, for clients to follow, and run unless
    // this MES stands by for another.
    if (auto open = executor->journal().openOrders()) {
        for (const auto& r : *open) {
            Progress p;
            p.run = r.id;
            p.processIri = r.processIri;
            p.state = toString(r.state);
            p.message = executor->standingBy() ? "another MES runs it; this one stands by"
                                               : "resuming it after a restart of the MES";
            component->orders_->show(p);
        }
    }
    if (!executor->standingBy()) {
        if (auto resumed = executor->resumeOpenOrders(); !resumed) {
            if (error != nullptr) *error = resumed.error();
            return ua::status::BadConfigurationError;
        }
    }
    return component;
}

}  // namespace skillcell::mes
