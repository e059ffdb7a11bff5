#include "devices/toolchanger/tool_changer_component.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>

#include "devices/common/frame.hpp"
#include "skills/skill_behaviour.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices::toolchanger {

namespace {
// Its skills are of the ToolChangerSkills model's types.
constexpr std::array<std::string_view, 1> kToolChangerSkillModels{
    ua::companion::kToolChangerSkillsUri};

/// One of the three skills: reads its parameters and runs the operation on the changer.
class ToolChangerBehaviour final : public skills::SkillBehaviour {
public:
    ToolChangerBehaviour(std::shared_ptr<ToolChanger> changer, ToolOperation operation)
        : changer_(std::move(changer)), operation_(operation) {}

    void start(const skills::SkillParameters& p, skills::SkillRun run) override {
        ToolRequest request;
        request.operation = operation_;
        const auto position = frameFromVariant(p.value("ToolPosition"));
        if (!position) {
            run.failed("ToolPosition is not a valid 3DFrame (" +
                       std::string(ua::statusName(position.status())) + ")");
            return;
        }
        request.toolPosition = *position;
        request.moveEndpoint = p.get<ua::String>("MoveSkillControllerEndpoint").value_or("");
        if (operation_ != ToolOperation::Detach) {
            request.toolAppUri = p.get<ua::String>("ToolAppUri").value_or("");
            if (!request.toolAppUri.empty() &&
                changer_->tools().byApplicationUri(request.toolAppUri) == nullptr) {
                run.failed("no tool of this changer has the application URI " + request.toolAppUri);
                return;
            }
        }
        asio::co_spawn(
            changer_->executor(),
            [changer = changer_, request, run]() -> asio::awaitable<void> {
                const std::string why = co_await changer->run(request);
                if (why.empty()) {
                    run.finished();
                } else {
                    run.failed(why);
                }
            },
            asio::detached);
    }
    void suspend() override { changer_->suspend(); }
    void resume() override { changer_->resume(); }
    void halt() override { changer_->halt(); }

private:
    std::shared_ptr<ToolChanger> changer_;
    ToolOperation operation_;
};

}  // namespace

std::span<const std::string_view> ToolChangerComponent::skillModels() {
    return kToolChangerSkillModels;
}

ToolChangerComponent::~ToolChangerComponent() {
    // An operation still running may hold the changer until the executor goes; its I/O
    // (which `io` serves) must end now, and the tools lose power with the changer.
    if (changer_) changer_->shutdown();
}

ua::Result<std::unique_ptr<ToolChangerComponent>> ToolChangerComponent::create(
    ua::Server& server, ToolChangerIo& io, ToolTable tools,
    std::shared_ptr<skills::SkillDetector> detector, ToolChangerOptions options,
    std::string* error) {
    auto component = std::make_unique<ToolChangerComponent>(Token{});
    ua::AddressSpace& as = server.addressSpace();
    const ua::NodeId object(1, ua::String("ToolChanger"));
    const ua::NodeId mounted(1, ua::String("ToolChanger/MountedTool"));
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), object, "ToolChanger"); !r) {
        return r.status();
    }
    if (auto r = as.addVariable(object, mounted, "MountedTool", ua::NodeId(ua::ns0::String),
                                ua::Variant(ua::String()), ua::access_level::kCurrentRead,
                                ua::value_rank::kScalar);
        !r) {
        return r.status();
    }
    const std::string robotUri = options.robotUri;
    component->changer_ = ToolChanger::create(server.executor(), io, std::move(tools),
                                              std::move(detector), std::move(options));
    component->changer_->onMountedTool = [&as, mounted](const std::string& id) {
        (void)as.setValue(mounted, ua::Variant(ua::String(id)));
    };
    // The hardware, not a memory, says which tool is mounted: after a restart too.
    asio::co_spawn(
        server.executor(),
        [changer = std::weak_ptr<ToolChanger>(component->changer_)]() -> asio::awaitable<void> {
            if (auto c = changer.lock()) (void)co_await c->recover();
        },
        asio::detached);
    component->skills_ =
        skills::SkillServer::create(server, server.executor(), kToolChangerSkillModels, error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    struct Spec {
        const char* type;
        const char* name;
        ToolOperation operation;
    };
    const Spec specs[] = {
        {"AttachToolSkillType", "AttachTool", ToolOperation::Attach},
        {"DetachToolSkillType", "DetachTool", ToolOperation::Detach},
        {"ChangeToolSkillType", "ChangeTool", ToolOperation::Change},
    };
    for (const Spec& spec : specs) {
        const auto type = component->skills_->findSkillType(spec.type);
        if (!type) {
            if (error != nullptr) *error = std::string("no skill type ") + spec.type;
            return ua::status::BadTypeDefinitionInvalid;
        }
        auto skill = component->skills_->add(
            *type, spec.name,
            std::make_unique<ToolChangerBehaviour>(component->changer_, spec.operation));
        if (!skill) {
            if (error != nullptr) *error = std::string("cannot add ") + spec.name;
            return skill.status();
        }
        // An empty endpoint means "the detected robot": a client need not write it.
        for (const auto& p : (*skill)->parameters()) {
            if (p.name == "MoveSkillControllerEndpoint" || p.name == "ToolAppUri") {
                (void)as.setValue(p.nodeId, ua::Variant(ua::String()));
            }
            // Which robot it is on: an MES takes the changer of the robot that reaches.
            if (p.name == "RobotUri") {
                (void)as.setValue(p.nodeId, ua::Variant(ua::String(robotUri)));
            }
        }
    }
    return component;
}

}  // namespace skillcell::devices::toolchanger
