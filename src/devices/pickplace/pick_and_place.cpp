#include "devices/pickplace/pick_and_place.hpp"

#include <spdlog/spdlog.h>

#include "devices/common/blocking_call.hpp"
#include "devices/common/frame.hpp"

namespace skillcell::devices::pickplace {
namespace {

constexpr const char* kMoveType = "CartesianLinearMoveSkillType";
constexpr const char* kGraspType = "GraspGripperSkillType";
constexpr const char* kReleaseType = "ReleaseGripperSkillType";

/// The object as the world model has it.
struct ObjectFacts {
    ua::StatusCode status;
    BoxSize size;
    KDL::Frame pose;
};

}  // namespace

std::shared_ptr<PickAndPlace> PickAndPlace::create(asio::any_io_executor executor, WorldLink& world,
                                                   std::shared_ptr<skills::SkillDetector> detector,
                                                   PickAndPlaceOptions options) {
    return std::make_shared<PickAndPlace>(Token{}, std::move(executor), world, std::move(detector),
                                          std::move(options));
}

PickAndPlace::PickAndPlace(Token, asio::any_io_executor executor, WorldLink& world,
                           std::shared_ptr<skills::SkillDetector> detector,
                           PickAndPlaceOptions options)
    : executor_(std::move(executor)),
      world_(world),
      detector_(std::move(detector)),
      options_(std::move(options)),
      subSkill_(executor_) {}

PickAndPlace::~PickAndPlace() {
    ioThread_.join();
}

void PickAndPlace::halt() {
    subSkill_.halt();
}

void PickAndPlace::suspend() {
    subSkill_.suspend();
}

void PickAndPlace::resume() {
    subSkill_.resume();
}

void PickAndPlace::shutdown() {
    halt();
    ioThread_.stop();
    ioThread_.join();
}

void PickAndPlace::publish(const std::string& name) {
    if (!name.empty()) spdlog::info("pick and place: {}", name);
    if (onStep) onStep(name);
}

asio::awaitable<PickAndPlace::Connection> PickAndPlace::open(std::string endpoint,
                                                             std::string typeName,
                                                             std::string& why) {
    if (endpoint.empty()) {
        if (!detector_) {
            why = "no endpoint for " + typeName + ", and this component detects no skills";
            co_return nullptr;
        }
        endpoint =
            co_await skills::detectedSkillEndpoint(*detector_, typeName, options_.detectionTimeout);
        if (endpoint.empty()) {
            why = "no " + typeName + " was detected within " +
                  std::to_string(options_.detectionTimeout.count()) + " ms";
            co_return nullptr;
        }
    }
    auto opened = co_await skills::SkillConnection::open(executor_, endpoint, typeName,
                                                         options_.client, &why);
    if (!opened) co_return nullptr;
    co_return std::move(*opened);
}

asio::awaitable<std::string> PickAndPlace::openSkills(const PickRequest& request, Skills& skills) {
    std::string why;
    std::string moveEndpoint = request.moveEndpoint;
    if (moveEndpoint.empty()) {
        // Which robot: the one whose linear move is detected.
        Connection probe = co_await open(moveEndpoint, kMoveType, why);
        if (!probe) co_return why;
        moveEndpoint = probe->endpointUrl();
        co_await probe->close();
    }
    skills.move = co_await RobotMotion::open(executor_, moveEndpoint, options_.client, why);
    if (!skills.move) co_return why;
    // The tool is what the robot carries now: Grasp and Release on one component.
    skills.grasp = co_await open(request.toolEndpoint, kGraspType, why);
    if (!skills.grasp) co_return why;
    skills.release = co_await open(skills.grasp->endpointUrl(), kReleaseType, why);
    if (!skills.release) co_return why;
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::plan(const PickRequest& request, Skills& skills,
                                                GraspPlan& result, GripPointType& type) {
    auto read = [this, id = request.objectId] {
        ObjectFacts facts;
        const auto size = world_.objectSize(id);
        const auto pose = world_.objectPose(id);
        if (!size || !pose) {
            facts.status = !size ? size.status() : pose.status();
            return facts;
        }
        facts.size = {(*size)[0], (*size)[1], (*size)[2]};
        facts.pose = *pose;
        return facts;
    };
    const ObjectFacts object = co_await blockingCall(ioThread_, std::move(read));
    if (object.status.isBad()) {
        co_return "the world model has no object " + request.objectId + " (" +
            std::string(ua::statusName(object.status)) + ")";
    }
    // The grip point as the tool's Grasp skill publishes it.
    const auto offsetValue = co_await skills.grasp->readParameter("GripPointOffset");
    const auto typeValue = co_await skills.grasp->readParameter("GripPointType");
    const auto offset =
        offsetValue ? frameFromVariant(*offsetValue) : ua::Result<KDL::Frame>(offsetValue.status());
    const std::int32_t* typeNumber = typeValue ? typeValue->get<std::int32_t>() : nullptr;
    if (!offset || typeNumber == nullptr) {
        co_return "the Grasp skill at " + skills.grasp->endpointUrl() +
            " publishes no usable GripPointOffset and GripPointType";
    }
    type = static_cast<GripPointType>(*typeNumber);
    GraspRequest g;
    g.size = object.size;
    g.objectPose = object.pose;
    g.gripPointOffset = *offset;
    g.type = type;
    g.placePosition = request.placePosition;
    g.approachDistance = options_.approachDistance;
    std::string why;
    const auto planned = planGrasp(g, &why);
    if (!planned) co_return "cannot plan the grasp of " + request.objectId + ": " + why;
    result = *planned;
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::step(std::string name, skills::SkillConnection& skill,
                                                std::uint64_t generation) {
    if (subSkill_.halted(generation)) co_return std::string("halted");
    publish(name);
    const skills::SkillOutcome outcome = co_await subSkill_.run(
        skill.skill(), std::map<std::string, ua::Variant>{}, options_.skillTimeout);
    if (subSkill_.halted(generation)) co_return std::string("halted");
    if (outcome.ok()) co_return std::string();
    co_return "step " + name + ": " + skill.description().browsePathString() + " at " +
        skill.endpointUrl() + " ended " + describeOutcome(outcome);
}

asio::awaitable<std::string> PickAndPlace::move(std::string name, RobotMotion& motion,
                                                KDL::Frame flange, RobotMotion::Path path,
                                                std::uint64_t generation) {
    if (subSkill_.halted(generation)) co_return std::string("halted");
    publish(name);
    std::string why = co_await motion.moveTo(subSkill_, flange, path, options_.skillTimeout);
    if (subSkill_.halted(generation)) co_return std::string("halted");
    if (why.empty()) co_return why;
    co_return "step " + name + ": " + why;
}

asio::awaitable<std::string> PickAndPlace::execute(const GraspPlan& plan, GripPointType type,
                                                   Skills& skills, std::uint64_t generation) {
    // Parallel fingers must be open before they go round the object.
    if (type == GripPointType::Parallel) {
        if (auto why = co_await step("open", *skills.release, generation); !why.empty()) {
            co_return why;
        }
    }
    // approach, grasp, retreat, place-approach, place, place-retreat: to each approach
    // point to point (free space), everything near the object in a straight line.
    const auto poses = steps(plan);
    for (std::size_t i = 0; i < poses.size(); ++i) {
        const auto path =
            (i == 0 || i == 3) ? RobotMotion::Path::Transfer : RobotMotion::Path::Linear;
        if (auto why =
                co_await move(poses[i].first, *skills.move, poses[i].second, path, generation);
            !why.empty()) {
            co_return why;
        }
        if (i == 1 || i == 4) {
            const bool grasp = i == 1;
            skills::SkillConnection& tool = grasp ? *skills.grasp : *skills.release;
            std::string name = grasp ? "Grasp" : "Release";
            if (auto why = co_await step(name, tool, generation); !why.empty()) co_return why;
        }
    }
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::run(PickRequest request) {
    auto self = shared_from_this();
    const std::uint64_t generation = subSkill_.begin();
    Skills skills;
    publish("connecting");
    std::string why = co_await openSkills(request, skills);
    GraspPlan grasp;
    GripPointType type = GripPointType::Vacuum;
    if (why.empty()) {
        publish("planning");
        why = co_await plan(request, skills, grasp, type);
    }
    if (why.empty()) why = co_await execute(grasp, type, skills, generation);
    if (skills.move) co_await skills.move->close();
    for (Connection* c : {&skills.grasp, &skills.release}) {
        if (*c) co_await (*c)->close();
    }
    publish("");
    co_return why;
}

}  // namespace skillcell::devices::pickplace
