#include "devices/pickplace/pick_and_place.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "devices/common/blocking_call.hpp"
#include "devices/common/frame.hpp"
#include "devices/common/lost_device_retry.hpp"
#include "devices/pickplace/fuse_planner.hpp"
#include "skills/reservation_client.hpp"

namespace skillcell::devices::pickplace {
namespace {

constexpr const char* kMoveType = "CartesianLinearMoveSkillType";
constexpr const char* kGraspType = "GraspGripperSkillType";
constexpr const char* kReleaseType = "ReleaseGripperSkillType";
/// How fast a fuse goes into its slot: slow enough for the arm's force sensing to stop it a
/// fraction of a millimetre into a face it should not meet.
constexpr double kInsertionSpeed = 0.02;  // m/s
/// Blocks side by side may touch by as much as the world allows.
constexpr double kRailOverlapTolerance = WorldTolerances{}.railOverlap;

/// How near a pose must be to count as the one planned: the arm's accuracy and the world's
/// contact tolerances are far finer.
constexpr double kSamePosition = 0.002;  // m
constexpr double kSameAngle = 0.02;      // rad
/// The robot whose base is within this of the move skill's ReachCentre is the one it moves
/// (a shoulder stands a few decimetres above its base at most; robots stand apart).
constexpr double kShoulderAboveBase = 0.5;  // m

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
                                                             std::string typeName, std::string& why,
                                                             std::string componentUri,
                                                             Skills& skills) {
    if (endpoint.empty()) {
        if (!detector_) {
            why = "no endpoint for " + typeName + ", and this component detects no skills";
            co_return nullptr;
        }
        endpoint = co_await skills::detectedSkillEndpoint(
            *detector_, typeName, options_.detectionTimeout, componentUri, skills.gone);
        if (endpoint.empty()) {
            why = "no " + typeName + (componentUri.empty() ? "" : " of " + componentUri) +
                  " was detected within " + std::to_string(options_.detectionTimeout.count()) +
                  " ms";
            co_return nullptr;
        }
        skills.found.try_emplace(endpoint, skills::lifeAt(*detector_, endpoint));
    }
    auto opened = co_await skills::SkillConnection::open(executor_, endpoint, typeName,
                                                         options_.client, &why);
    if (!opened) {
        skills.unreachable = true;
        if (const auto f = skills.found.find(endpoint); f != skills.found.end()) {
            skills.gone.push_back(f->second);
        }
        co_return nullptr;
    }
    if (const auto& eps = (*opened)->client().serverEndpoints(); !eps.empty()) {
        skills.uris.try_emplace(endpoint, eps.front().server.applicationUri);
    }
    co_return std::move(*opened);
}

std::string PickAndPlace::componentAt(const std::string& endpoint) const {
    if (!detector_) return {};
    for (const auto& s : detector_->instances()) {
        if (s.endpointUrl == endpoint) return s.componentUri;
    }
    return {};
}

void PickAndPlace::Skills::noteLosses() {
    lost = unreachable;
    auto lose = [&](const std::string& endpoint) {
        lost = true;
        if (const auto f = found.find(endpoint); f != found.end()) gone.push_back(f->second);
    };
    if (move && !move->connected()) lose(move->endpointUrl());
    for (const Connection* c : {&grasp, &release}) {
        if (*c && !(*c)->client().isConnected()) lose((*c)->endpointUrl());
    }
}

asio::awaitable<std::string> PickAndPlace::openSkills(const PickRequest& request, Skills& skills) {
    std::string why;
    // The tool first: the robot that carries it is the one to move (its RobotUri, which its
    // tool changer gave it), where the request names no robot.
    skills.grasp = co_await open(request.toolEndpoint, kGraspType, why, request.toolUri, skills);
    if (!skills.grasp) co_return why;
    skills.release = co_await open(skills.grasp->endpointUrl(), kReleaseType, why, {}, skills);
    if (!skills.release) co_return why;
    std::string moveEndpoint = request.moveEndpoint;
    if (moveEndpoint.empty()) {
        std::string carrier;
        if (auto uri = co_await skills.grasp->readParameter("RobotUri")) {
            if (const auto* text = uri->get<ua::String>()) carrier = *text;
        }
        // Which robot: the carrier's linear move, else (a tool that does not say) the one
        // detected.
        Connection probe = co_await open(moveEndpoint, kMoveType, why, carrier, skills);
        if (!probe) co_return why;
        moveEndpoint = probe->endpointUrl();
        co_await probe->close();
    }
    skills.move = co_await RobotMotion::open(executor_, moveEndpoint, options_.client, why,
                                             /*forceLimited=*/request.fuse.has_value(),
                                             kDeadHolderLease, &skills.unreachable);
    if (!skills.move) {
        if (const auto f = skills.found.find(moveEndpoint);
            skills.unreachable && f != skills.found.end()) {
            skills.gone.push_back(f->second);
        }
        co_return why;
    }
    if (request.fuse && !skills.move->sensesForce()) {
        co_return "the robot at " + moveEndpoint +
            " offers no CartesianForceLimitedLinearMove: a fuse is inserted under a force limit";
    }
    // The tool is the composite's while it runs, as the robot is (RobotMotion).
    std::vector<ua::Client*> sessions{&skills.grasp->client(), &skills.release->client()};
    const skills::Hold held = co_await skills::hold(
        std::move(sessions), options_.client.applicationUri, kDeadHolderLease);
    if (!held.refusal.empty()) {
        co_return "the tool at " + skills.grasp->endpointUrl() +
            " cannot be driven: " + held.refusal;
    }
    skills.toolToken = held.token;
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::perceive(const PickRequest& request, Skills& skills,
                                                    Perceived& seen) {
    const auto centre = co_await skills.move->reachCentre();
    if (!centre) {
        co_return "the robot at " + skills.move->endpointUrl() + " publishes no ReachCentre (" +
            std::string(ua::statusName(centre.status())) + ")";
    }
    auto read = [this] { return world_.robots(); };
    const auto robots = co_await blockingCall(ioThread_, std::move(read));
    if (!robots) {
        co_return "cannot read the world model's robots (" +
            std::string(ua::statusName(robots.status())) + ")";
    }
    double nearest = kShoulderAboveBase;
    for (const auto& r : *robots) {
        const double d = (r.base.p - centre->p).Norm();
        if (d < nearest) {
            nearest = d;
            seen.robot = r.id;
            seen.flange = r.flange;
        }
        if (r.held == request.objectId) seen.holder = r.id;
    }
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::plan(const PickRequest& request, Skills& skills,
                                                Script& script) {
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
    const auto type = static_cast<GripPointType>(*typeNumber);
    Perceived seen;
    if (auto why = co_await perceive(request, skills, seen); !why.empty()) co_return why;
    if (!seen.holder.empty() && seen.holder != seen.robot) {
        co_return "object " + request.objectId + " is held by robot " + seen.holder +
            ", not by the one this composite moves (" +
            (seen.robot.empty() ? "none of the world's stands at its ReachCentre" : seen.robot) +
            ")";
    }
    if (!seen.holder.empty() && (request.rail || request.fuse)) {
        co_return "object " + request.objectId + " is held already (a run cut short left it " +
            "so); only a plain pick and place continues from there, not a " +
            (request.rail ? "rail mount" : "fuse insertion");
    }
    if (request.rail) {
        co_return co_await planRail(request, object.size, object.pose, *offset, type, script);
    }
    if (request.fuse) {
        co_return co_await planFuse(request, object.size, object.pose, *offset, type, script);
    }
    GraspRequest g;
    g.size = object.size;
    g.objectPose = object.pose;
    g.gripPointOffset = *offset;
    g.type = type;
    g.placePosition = request.placePosition;
    g.approachDistance = options_.approachDistance;
    std::string why;
    using K = Action::Kind;
    // A run cut short (docs/mes.md, "Settling") continues from where the object is: held by
    // this robot, it is carried on as it is held; at its place, free, with the gripper still
    // at it, the gripper lets go and lifts off; at its place otherwise, nothing is left to do.
    const bool placed = near(object.pose, request.placePosition, kSamePosition, kSameAngle);
    if (!seen.holder.empty()) {
        const GraspPlan carry = planCarryOn(seen.flange, g);
        spdlog::info("pickplace: {} is held by robot {} (a run cut short): {}", request.objectId,
                     seen.holder, placed ? "letting go of it at its place" : "carrying it on");
        if (!placed) {
            script.insert(script.end(), {{K::Linear, "retreat", carry.retreat},
                                         {K::Transfer, "place-approach", carry.placeApproach},
                                         {K::Linear, "place", carry.place}});
        }
        script.insert(script.end(), {{K::Release, "Release", {}},
                                     {K::Linear, "place-retreat", carry.placeRetreat}});
        co_return std::string();
    }
    if (placed) {
        // The gripper at it: its grip point within the box (vacuum: on its top face).
        const KDL::Vector grip = (seen.flange * *offset).p;
        const KDL::Vector inBox = object.pose.Inverse() * grip;
        const bool at = !seen.robot.empty() &&
                        std::abs(inBox.x()) <= object.size.x / 2 + kSamePosition &&
                        std::abs(inBox.y()) <= object.size.y / 2 + kSamePosition &&
                        std::abs(inBox.z()) <= object.size.z / 2 + kSamePosition;
        spdlog::info("pickplace: {} is at its place already: {}", request.objectId,
                     at ? "the gripper lets go and lifts off" : "nothing to do");
        if (at) {
            // Lifted off as a carried-on run lifts: planCarryOn's retreat from where it is.
            script.insert(script.end(),
                          {{K::Release, "Release", {}},
                           {K::Linear, "place-retreat", planCarryOn(seen.flange, g).retreat}});
        }
        co_return std::string();
    }
    const auto planned = planGrasp(g, &why);
    if (!planned) co_return "cannot plan the grasp of " + request.objectId + ": " + why;
    // Parallel fingers must be open before they go round the object. To each approach point
    // to point (free space), everything near the object in a straight line.
    if (type == GripPointType::Parallel) script.push_back({K::Open, "open", {}});
    script.insert(script.end(), {{K::Transfer, "approach", planned->approach},
                                 {K::Linear, "grasp", planned->grasp},
                                 {K::Grasp, "Grasp", {}},
                                 {K::Linear, "retreat", planned->retreat},
                                 {K::Transfer, "place-approach", planned->placeApproach},
                                 {K::Linear, "place", planned->place},
                                 {K::Release, "Release", {}},
                                 {K::Linear, "place-retreat", planned->placeRetreat}});
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::planRail(const PickRequest& request, const BoxSize& size,
                                                    const KDL::Frame& pose,
                                                    const KDL::Frame& gripOffset,
                                                    GripPointType type, Script& script) {
    // The rail, and the blocks on it now: the world model's, read where the block goes.
    struct RailFacts {
        ua::StatusCode status;
        std::string failed;  // what could not be read
        DinRail rail;
        std::vector<std::pair<std::string, WorldLink::Mount>> mounted;
    };
    const std::string railId = request.rail->railId;
    auto read = [this, railId, self = request.objectId] {
        RailFacts facts;
        const auto rail = world_.rail(railId);
        if (!rail) {
            facts.status = rail.status();
            facts.failed = "rail " + railId;
            return facts;
        }
        facts.rail = DinRail{railId, rail->pose, rail->length, rail->width};
        const auto ids = world_.objectIds();
        if (!ids) {
            facts.status = ids.status();
            facts.failed = "its objects";
            return facts;
        }
        for (const auto& id : *ids) {
            if (id == self) continue;
            const auto mount = world_.railMount(id);
            if (!mount && mount.status() == ua::StatusCode(ua::status::BadNodeIdUnknown)) {
                continue;  // no Rail: a box, not a terminal block
            }
            if (!mount) {
                facts.status = mount.status();
                facts.failed = "mount of " + id;
                return facts;
            }
            if (*mount && (*mount)->rail == railId) facts.mounted.emplace_back(id, **mount);
        }
        return facts;
    };
    const RailFacts facts = co_await blockingCall(ioThread_, std::move(read));
    if (facts.status.isBad()) {
        co_return "the world model has no " + facts.failed + " (" +
            std::string(ua::statusName(facts.status)) + ")";
    }
    // The widths of the blocks on the rail, for side by side and overlap.
    std::vector<std::pair<double, double>> spans;
    for (const auto& [id, mount] : facts.mounted) {
        // Named: GCC 12 destroys a co_await expression's temporaries twice.
        auto readSize = [this, objectId = id] { return world_.objectSize(objectId); };
        auto width = co_await blockingCall(ioThread_, std::move(readSize));
        if (!width) {
            co_return "the world model gives no size of terminal block " + id + " (" +
                std::string(ua::statusName(width.status())) + ")";
        }
        spans.emplace_back(mount.position, (*width)[0]);
    }
    double position = request.rail->position;
    if (position < 0) {
        const auto next = nextFreePosition(facts.rail, size.x, spans);
        if (!next) {
            co_return fmt::format(
                "rail {} is full: no room for a block {:.1f} mm wide after its "
                "{} blocks",
                railId, size.x * 1000, spans.size());
        }
        position = *next;
    }
    // Refused before anything moves: a block over another one would not snap.
    for (std::size_t i = 0; i < spans.size(); ++i) {
        if (spansOverlap(position, size.x, spans[i].first, spans[i].second,
                         kRailOverlapTolerance)) {
            co_return fmt::format(
                "terminal block {} at {:.1f} mm on rail {} would sit over terminal block {} at "
                "{:.1f} mm",
                request.objectId, position * 1000, railId, facts.mounted[i].first,
                spans[i].first * 1000);
        }
    }
    RailPlacementRequest r;
    r.size = size;
    r.blockPose = pose;
    r.gripPointOffset = gripOffset;
    r.type = type;
    r.rail = facts.rail;
    r.position = position;
    r.approachDistance = options_.approachDistance;
    std::string why;
    const auto planned = planRailPlacement(r, &why);
    if (!planned) co_return "cannot place " + request.objectId + ": " + why;
    spdlog::info("pick and place: terminal block {} goes to {:.1f} mm on rail {}", request.objectId,
                 position * 1000, railId);
    using K = Action::Kind;
    if (type == GripPointType::Parallel) script.push_back({K::Open, "open", {}});
    script.insert(script.end(), {{K::Transfer, "approach", planned->approach},
                                 {K::Linear, "grasp", planned->grasp},
                                 {K::Grasp, "Grasp", {}},
                                 {K::Linear, "retreat", planned->retreat},
                                 {K::Transfer, "hook-approach", planned->hookApproach},
                                 {K::Linear, "hook", planned->hook}});
    for (const auto& f : planned->rotateDown) script.push_back({K::Linear, "rotate-down", f});
    script.insert(script.end(), {{K::CheckSnapped, "snap", {}},
                                 {K::Release, "Release", {}},
                                 {K::Linear, "rail-retreat", planned->railRetreat},
                                 {K::CheckMounted, "check", {}}});
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::planFuse(const PickRequest& request, const BoxSize& size,
                                                    const KDL::Frame& pose,
                                                    const KDL::Frame& gripOffset,
                                                    GripPointType type, Script& script) {
    // The slot as drawn, and whether the object is a fuse and the slot is free.
    struct SlotFacts {
        ua::StatusCode status;
        std::string problem;
        WorldLink::Slot slot;
    };
    const FuseTarget target = *request.fuse;
    auto read = [this, target, fuseId = request.objectId] {
        SlotFacts facts;
        const auto slot = world_.fuseSlot(target.slotId);
        if (!slot) {
            facts.status = slot.status();
            facts.problem = "the world model has no fuse slot " + target.slotId;
            return facts;
        }
        facts.slot = *slot;
        const auto seat = world_.fuseSeat(fuseId);
        if (!seat) {
            facts.status = seat.status();
            facts.problem = "object " + fuseId + " is no fuse";
            return facts;
        }
        if (!slot->fuse.empty() && slot->fuse != fuseId) {
            facts.status = ua::status::BadInvalidState;
            facts.problem = "slot " + target.slotId + " holds fuse " + slot->fuse + " already";
        }
        return facts;
    };
    const SlotFacts facts = co_await blockingCall(ioThread_, std::move(read));
    if (facts.status.isBad()) {
        co_return facts.problem + " (" + std::string(ua::statusName(facts.status)) + ")";
    }
    FuseInsertionRequest r;
    r.size = size;
    r.fusePose = pose;
    r.gripPointOffset = gripOffset;
    r.type = type;
    r.slotPose = facts.slot.pose;
    r.slotDepth = facts.slot.depth;
    r.approachDistance = options_.approachDistance;
    std::string why;
    const auto planned = planFuseInsertion(r, &why);
    if (!planned) co_return "cannot insert " + request.objectId + ": " + why;
    spdlog::info("pick and place: fuse {} goes into slot {}, at most {:.1f} N", request.objectId,
                 target.slotId, target.forceLimit);
    using K = Action::Kind;
    script.insert(script.end(), {{K::Open, "open", {}},
                                 {K::Transfer, "approach", planned->approach},
                                 {K::Linear, "grasp", planned->grasp},
                                 {K::Grasp, "Grasp", {}},
                                 {K::Linear, "retreat", planned->retreat},
                                 {K::Transfer, "insert-approach", planned->insertApproach},
                                 {K::Linear, "pre-insert", planned->preInsert},
                                 {K::Insert, "insert", planned->insert},
                                 {K::Release, "Release", {}},
                                 {K::Linear, "insert-retreat", planned->insertRetreat},
                                 {K::CheckSeated, "check", {}}});
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
                                                std::uint64_t generation, MoveLimits limits) {
    if (subSkill_.halted(generation)) co_return std::string("halted");
    publish(name);
    std::string why =
        co_await motion.moveTo(subSkill_, flange, path, options_.skillTimeout, limits);
    if (subSkill_.halted(generation)) co_return std::string("halted");
    if (why.empty()) co_return why;
    co_return "step " + name + ": " + why;
}

asio::awaitable<std::string> PickAndPlace::execute(const Script& script, const PickRequest& request,
                                                   Skills& skills, std::uint64_t generation) {
    using K = Action::Kind;
    for (const Action& a : script) {
        std::string why;
        switch (a.kind) {
            case K::Transfer:
            case K::Linear: {
                const auto path =
                    a.kind == K::Transfer ? RobotMotion::Path::Transfer : RobotMotion::Path::Linear;
                why = co_await move(a.name, *skills.move, a.flange, path, generation);
                break;
            }
            case K::Insert:
                why = co_await move(a.name, *skills.move, a.flange, RobotMotion::Path::ForceLimited,
                                    generation, {request.fuse->forceLimit, kInsertionSpeed});
                break;
            case K::Open:
            case K::Release:
                why = co_await step(a.name, *skills.release, generation);
                break;
            case K::Grasp:
                why = co_await step(a.name, *skills.grasp, generation);
                break;
            case K::CheckSnapped: {
                // The world says whether the spring foot caught; a block that did not is
                // still held, on the rail but loose: the run stops there, with the reason.
                publish(a.name);
                auto readRefusal = [this, id = request.objectId] { return world_.railRefusal(id); };
                const auto refusal = co_await blockingCall(ioThread_, std::move(readRefusal));
                if (!refusal) {
                    why = "step snap: cannot read the world model's RailRefusal (" +
                          std::string(ua::statusName(refusal.status())) + ")";
                } else if (!refusal->empty()) {
                    why = "step snap: " + *refusal;
                }
                break;
            }
            case K::CheckMounted: {
                publish(a.name);
                auto readMount = [this, id = request.objectId] { return world_.railMount(id); };
                const auto mount = co_await blockingCall(ioThread_, std::move(readMount));
                if (!mount || !*mount || (*mount)->rail != request.rail->railId) {
                    why = "step check: terminal block " + request.objectId + " is not on rail " +
                          request.rail->railId + " after its release";
                }
                break;
            }
            case K::CheckSeated: {
                publish(a.name);
                auto readSeat = [this, id = request.objectId] { return world_.fuseSeat(id); };
                const auto seat = co_await blockingCall(ioThread_, std::move(readSeat));
                if (!seat || *seat != request.fuse->slotId) {
                    why = "step check: fuse " + request.objectId + " is not seated in slot " +
                          request.fuse->slotId + " after its release";
                }
                break;
            }
        }
        if (!why.empty()) co_return why;
    }
    co_return std::string();
}

asio::awaitable<std::string> PickAndPlace::attempt(const PickRequest& request,
                                                   std::uint64_t generation, Skills& skills) {
    publish("connecting");
    std::string why = co_await openSkills(request, skills);
    Script script;
    if (why.empty()) {
        publish("planning");
        why = co_await plan(request, skills, script);
    }
    if (why.empty()) why = co_await execute(script, request, skills, generation);
    skills.noteLosses();
    if (skills.move) co_await skills.move->close();
    if (skills.toolToken) (void)co_await skills::release(skills.grasp->client(), *skills.toolToken);
    for (Connection* c : {&skills.grasp, &skills.release}) {
        if (*c) co_await (*c)->close();
    }
    co_return why;
}

asio::awaitable<std::string> PickAndPlace::run(PickRequest request) {
    auto self = shared_from_this();
    const std::uint64_t generation = subSkill_.begin();
    // A robot or tool lost mid-run: the run goes on from what the scene shows (plan()
    // settles) once discovery finds the device again. A device restarted elsewhere (another
    // port) is found by its component URI: the endpoints the request named are where the
    // devices were, not where they are.
    std::string toolUri =
        request.toolEndpoint.empty() ? request.toolUri : componentAt(request.toolEndpoint);
    std::vector<skills::ComponentLife> gone;  // devices lost in earlier tries
    std::string why = co_await goOnAfterLostDevice(
        executor_,
        [this, &request, &toolUri, &gone, generation](bool& lost) -> asio::awaitable<std::string> {
            Skills skills;
            skills.gone = gone;
            world_.clearLoss();
            std::string failed = co_await attempt(request, generation, skills);
            // The world model is what the composite perceives the cell by: out of reach, it
            // is a lost device too.
            lost = skills.lost || world_.lostConnection();
            gone = std::move(skills.gone);
            // A tool named by an endpoint the detector did not list yet when the run began:
            // its server said its URI when this try connected to it.
            if (lost && toolUri.empty()) {
                if (const auto u = skills.uris.find(request.toolEndpoint); u != skills.uris.end())
                    toolUri = u->second;
            }
            if (lost && !toolUri.empty()) {
                request.toolEndpoint.clear();
                request.toolUri = toolUri;
            }
            if (lost) request.moveEndpoint.clear();  // the robot carrying the tool, detected
            co_return failed;
        },
        [this, generation] { return subSkill_.halted(generation); }, "pick and place",
        [this] { publish("waiting for the lost device"); });
    publish("");
    co_return why;
}

}  // namespace skillcell::devices::pickplace
