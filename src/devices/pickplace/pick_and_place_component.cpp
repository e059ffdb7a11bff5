#include "devices/pickplace/pick_and_place_component.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <cmath>
#include <tuple>

#include "devices/common/frame.hpp"
#include "skills/skill_behaviour.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices::pickplace {

namespace {
// Its skills are of the CompositeSkills model's types.
constexpr std::array<std::string_view, 1> kPickAndPlaceSkillModels{
    ua::companion::kCompositeSkillsUri};

/// What a skill of the component places where.
enum class Placement { Pose, Rail, FuseSlot };

/// PickAndPlace (a box to a pose), PlaceTerminalBlock (a block onto a DIN rail) and
/// InsertFuse (a fuse into its slot): one composite, three skills; the component runs one at
/// a time.
class PickAndPlaceBehaviour final : public skills::SkillBehaviour {
public:
    PickAndPlaceBehaviour(std::shared_ptr<PickAndPlace> composite, Placement placement)
        : composite_(std::move(composite)), placement_(placement) {}

    void start(const skills::SkillParameters& p, skills::SkillRun run) override {
        PickRequest request;
        request.objectId = p.get<ua::String>("ObjectId").value_or("");
        if (request.objectId.empty()) {
            run.failed("ObjectId is empty");
            return;
        }
        if (placement_ == Placement::Rail) {
            RailTarget target;
            target.railId = p.get<ua::String>("RailId").value_or("");
            target.position = p.get<double>("Position").value_or(-1);
            if (target.railId.empty()) {
                run.failed("RailId is empty");
                return;
            }
            if (!std::isfinite(target.position)) {
                run.failed("Position is not a number");
                return;
            }
            request.rail = target;
        } else if (placement_ == Placement::FuseSlot) {
            FuseTarget target;
            target.slotId = p.get<ua::String>("SlotId").value_or("");
            target.forceLimit = p.get<double>("ForceLimit").value_or(0);
            if (target.slotId.empty()) {
                run.failed("SlotId is empty");
                return;
            }
            if (!std::isfinite(target.forceLimit) || target.forceLimit <= 0) {
                run.failed("ForceLimit must be above 0 N");
                return;
            }
            request.fuse = target;
        } else {
            const auto place = frameFromVariant(p.value("PlacePosition"));
            if (!place) {
                run.failed("PlacePosition is not a valid 3DFrame (" +
                           std::string(ua::statusName(place.status())) + ")");
                return;
            }
            request.placePosition = *place;
        }
        request.toolEndpoint = p.get<ua::String>("ToolSkillControllerEndpoint").value_or("");
        request.moveEndpoint = p.get<ua::String>("MoveSkillControllerEndpoint").value_or("");
        asio::co_spawn(
            composite_->executor(),
            [composite = composite_, request, run]() -> asio::awaitable<void> {
                const std::string why = co_await composite->run(request);
                if (why.empty()) {
                    run.finished();
                } else {
                    run.failed(why);
                }
            },
            asio::detached);
    }
    void suspend() override { composite_->suspend(); }
    void resume() override { composite_->resume(); }
    void halt() override { composite_->halt(); }

private:
    std::shared_ptr<PickAndPlace> composite_;
    Placement placement_;
};

}  // namespace

std::span<const std::string_view> PickAndPlaceComponent::skillModels() {
    return kPickAndPlaceSkillModels;
}

PickAndPlaceComponent::~PickAndPlaceComponent() {
    // A run still going may hold the composite until the executor goes; the world link its
    // I/O uses goes with the component.
    if (composite_) composite_->shutdown();
}

ua::Result<std::unique_ptr<PickAndPlaceComponent>> PickAndPlaceComponent::create(
    ua::Server& server, WorldLink& world, std::shared_ptr<skills::SkillDetector> detector,
    PickAndPlaceOptions options, std::string* error) {
    auto component = std::make_unique<PickAndPlaceComponent>(Token{});
    ua::AddressSpace& as = server.addressSpace();
    const ua::NodeId object(1, ua::String("PickAndPlace"));
    const ua::NodeId current(1, ua::String("PickAndPlace/CurrentStep"));
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), object, "PickAndPlace"); !r) {
        return r.status();
    }
    if (auto r = as.addVariable(object, current, "CurrentStep", ua::NodeId(ua::ns0::String),
                                ua::Variant(ua::String()), ua::access_level::kCurrentRead,
                                ua::value_rank::kScalar);
        !r) {
        return r.status();
    }
    component->composite_ =
        PickAndPlace::create(server.executor(), world, std::move(detector), std::move(options));
    component->composite_->onStep = [&as, current](const std::string& step) {
        (void)as.setValue(current, ua::Variant(ua::String(step)));
    };
    component->skills_ =
        skills::SkillServer::create(server, server.executor(), kPickAndPlaceSkillModels, error);
    if (!component->skills_) return ua::status::BadConfigurationError;
    for (const auto& [typeName, name, placement] :
         {std::tuple{"PickAndPlaceSkillType", "PickAndPlace", Placement::Pose},
          std::tuple{"PlaceTerminalBlockSkillType", "PlaceTerminalBlock", Placement::Rail},
          std::tuple{"InsertFuseSkillType", "InsertFuse", Placement::FuseSlot}}) {
        const auto type = component->skills_->findSkillType(typeName);
        if (!type) {
            if (error != nullptr) *error = std::string("no skill type ") + typeName;
            return ua::status::BadTypeDefinitionInvalid;
        }
        auto skill = component->skills_->add(
            *type, name, std::make_unique<PickAndPlaceBehaviour>(component->composite_, placement));
        if (!skill) {
            if (error != nullptr) *error = std::string("cannot add ") + name;
            return skill.status();
        }
        // Empty endpoints mean "the detected ones": a client need not write them. A negative
        // position: the next free place on the rail.
        for (const auto& p : (*skill)->parameters()) {
            if (p.name == "ToolSkillControllerEndpoint" ||
                p.name == "MoveSkillControllerEndpoint") {
                (void)as.setValue(p.nodeId, ua::Variant(ua::String()));
            } else if (p.name == "Position") {
                (void)as.setValue(p.nodeId, ua::Variant(-1.0));
            }
        }
    }
    return component;
}

}  // namespace skillcell::devices::pickplace
