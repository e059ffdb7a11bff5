#include "skills/skill.hpp"

#include <spdlog/spdlog.h>
#include <asio/post.hpp>

#include "skills/reservation.hpp"
#include "ua/address_space/instantiate.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/server/subscriptions/event.hpp"

namespace skillcell::skills {
namespace {

using ua::AddressSpace;
using ua::NodeId;
using ua::QualifiedName;
using ua::Variant;

/// The optional children our model requires of every skill: ProgramStateMachineType
/// declares the methods OptionalPlaceholder (OPC 10000-10 1.05), ARCHITECTURE.md requires
/// them, and TransitionTime tells a client when the last change happened.
const std::vector<std::string>& requiredOptionalChildren() {
    static const std::vector<std::string> kChildren = {
        "Start", "Suspend", "Resume", "Halt", "Reset", "LastTransition/TransitionTime"};
    return kChildren;
}

/// "ParameterSet/<parameter>/EURange" (or InstrumentRange) for every parameter that the
/// type or a supertype declares with a range. The models make ranges Optional (a type
/// default); a skill creates them, so that clients see the bounds its writes are held to.
std::vector<std::string> parameterRangePaths(const AddressSpace& as, NodeId type) {
    std::vector<std::string> paths;
    auto forwardChildren = [&as](const ua::Node& n, auto&& f) {
        for (const auto& r : n.references) {
            if (!r.isForward || r.referenceTypeId == NodeId(45)) continue;  // not HasSubtype
            if (const ua::Node* c = as.find(r.target)) f(*c);
        }
    };
    for (int depth = 0; depth < 32 && !type.isNull(); ++depth) {
        const ua::Node* t = as.find(type);
        if (t == nullptr) break;
        forwardChildren(*t, [&](const ua::Node& set) {
            if (set.browseName.name != "ParameterSet") return;
            forwardChildren(set, [&](const ua::Node& parameter) {
                forwardChildren(parameter, [&](const ua::Node& property) {
                    const auto& n = property.browseName.name;
                    if (n != "EURange" && n != "InstrumentRange") return;
                    paths.push_back("ParameterSet/" + parameter.browseName.name + "/" + n);
                });
            });
        });
        type = t->superType;
    }
    return paths;
}

NodeId child(const NodeId& parent, std::string_view path) {
    NodeId id = parent;
    std::size_t begin = 0;
    while (begin <= path.size()) {
        const auto end = path.find('/', begin);
        const auto part =
            path.substr(begin, end == std::string_view::npos ? path.size() - begin : end - begin);
        id = AddressSpace::childNodeId(id, part);
        if (end == std::string_view::npos) break;
        begin = end + 1;
    }
    return id;
}

std::vector<QualifiedName> path(std::initializer_list<const char*> names) {
    std::vector<QualifiedName> out;
    for (const char* n : names) out.push_back(QualifiedName{0, n});
    return out;
}

}  // namespace

// --- SkillRun ---------------------------------------------------------------------------

void SkillRun::finished() const {
    if (auto skill = skill_.lock()) {
        asio::post(skill->executor_, [weak = skill_, id = id_] {
            if (auto s = weak.lock()) s->runEnded(id, true, {});
        });
    }
}

void SkillRun::failed(std::string reason) const {
    if (auto skill = skill_.lock()) {
        asio::post(skill->executor_, [weak = skill_, id = id_, r = std::move(reason)]() mutable {
            if (auto s = weak.lock()) s->runEnded(id, false, std::move(r));
        });
    }
}

// --- Skill ------------------------------------------------------------------------------

Skill::Skill(Token, ua::Server& server, asio::any_io_executor executor,
             std::unique_ptr<SkillBehaviour> behaviour)
    : server_(server), executor_(std::move(executor)), behaviour_(std::move(behaviour)) {}

Skill::~Skill() = default;

ua::Result<std::shared_ptr<Skill>> Skill::create(ua::Server& server, asio::any_io_executor executor,
                                                 const SkillConfig& config,
                                                 std::unique_ptr<SkillBehaviour> behaviour) {
    if (!behaviour) return ua::status::BadInvalidArgument;
    if (config.initialState != SkillState::Ready && config.initialState != SkillState::Halted) {
        return ua::status::BadInvalidArgument;
    }
    auto skill =
        std::make_shared<Skill>(Token{}, server, std::move(executor), std::move(behaviour));
    if (const auto s = skill->build(config); s.isBad()) return s;
    return skill;
}

ua::StatusCode Skill::build(const SkillConfig& config) {
    AddressSpace& as = server_.addressSpace();
    const auto skillType = ua::skillsNodeId(as, ua::companion::kSkillType);
    const auto eventType = ua::skillsNodeId(as, ua::companion::kSkillTransitionEventType);
    if (!skillType || !eventType) return ua::status::BadTypeDefinitionInvalid;
    const ua::Node* type = as.find(config.type);
    if (type == nullptr || type->nodeClass != ua::NodeClass::ObjectType || type->isAbstract ||
        !as.isSubtypeOf(config.type, *skillType)) {
        return ua::status::BadTypeDefinitionInvalid;
    }
    const ua::Node* parent = as.find(config.parent);
    if (parent == nullptr) return ua::status::BadNodeIdUnknown;

    ua::InstantiateOptions options;
    options.nodeId = config.nodeId;
    options.optionalChildren = requiredOptionalChildren();
    for (auto& p : parameterRangePaths(as, config.type)) {
        options.optionalChildren.push_back(std::move(p));
    }
    auto id = ua::instantiate(as, config.type, config.parent, NodeId(ua::ns0::HasComponent),
                              QualifiedName{config.parent.namespaceIndex(), config.name}, options);
    if (!id) return id.status();
    nodeId_ = *id;
    reservation_ = config.reservation;
    type_ = config.type;
    name_ = config.name;
    eventType_ = *eventType;
    // Clients subscribe to the skill itself for its transition events.
    as.find(nodeId_)->eventNotifier = ua::kSubscribeToEvents;

    if (const auto s = installMethods(); s.isBad()) return s;
    const NodeId parameterSet = child(nodeId_, "ParameterSet");
    parameters_ = declaredParameters(as, parameterSet);
    installParameterChecks();
    // Mandatory properties of ProgramStateMachineType: skills are fixed parts of their
    // component, neither deleted by clients nor recycled.
    (void)as.setValue(child(nodeId_, "Deletable"), false);
    (void)as.setValue(child(nodeId_, "AutoDelete"), false);
    (void)as.setValue(child(nodeId_, "RecycleCount"), std::int32_t{0});
    publishState(config.initialState);
    return ua::status::Good;
}

ua::StatusCode Skill::installMethods() {
    AddressSpace& as = server_.addressSpace();
    for (SkillMethod m : kAllMethods) {
        const NodeId methodId = child(nodeId_, skills::name(m));
        const auto s = as.setMethodCallback(
            methodId,
            [weak = weak_from_this(), m](const ua::Caller& caller, const NodeId&,
                                         std::span<const Variant>,
                                         std::vector<Variant>&) -> ua::StatusCode {
                auto self = weak.lock();
                if (!self) return ua::status::BadInvalidState;
                return self->invoke(m, caller);
            });
        if (s.isBad()) return s;
    }
    return ua::status::Good;
}

void Skill::installParameterChecks() {
    AddressSpace& as = server_.addressSpace();
    for (std::size_t i = 0; i < parameters_.size(); ++i) {
        (void)as.setValueSink(
            parameters_[i].nodeId,
            [weak = weak_from_this(), i](const ua::Caller& caller, const ua::DataValue& dv) {
                auto self = weak.lock();
                if (!self) return ua::StatusCode(ua::status::BadInvalidState);
                // A run's values are fixed at Start, so a write during a run cannot change it;
                // still, only the session that holds the run may prepare the next one.
                if (self->reservedAgainst(caller))
                    return ua::StatusCode(ua::status::BadUserAccessDenied);
                std::string why;
                const auto s = validateParameter(self->server_.addressSpace(), self->parameters_[i],
                                                 dv.value.value_or(Variant{}), &why);
                if (s.isBad()) spdlog::debug("skill {}: write refused: {}", self->name_, why);
                return s;
            });
    }
}

bool Skill::reservedAgainst(const ua::Caller& caller) const {
    if (reservation_ && !reservation_->permits(caller)) return true;
    const SkillState s = state_.load();
    if (s != SkillState::Running && s != SkillState::Suspended) return false;
    // Application code (no session) acts for the component itself; a reservation whose
    // session has gone (closed, timed out) no longer protects anything.
    if (caller.sessionId.isNull() || owner_.isNull() || caller.sessionId == owner_) return false;
    return server_.hasSession(owner_);
}

ua::StatusCode Skill::fixParameters(SkillParameters& out) const {
    const AddressSpace& as = server_.addressSpace();
    std::map<std::string, Variant> values;
    for (const auto& p : parameters_) {
        const ua::Node* node = as.find(p.nodeId);
        const ua::DataValue dv = node != nullptr ? as.readValue(*node) : ua::DataValue{};
        Variant v = dv.value.value_or(Variant{});
        std::string why;
        if (const auto s = validateParameter(as, p, v, &why); s.isBad()) {
            spdlog::info("skill {}: Start refused: {}", name_, why);
            return s;
        }
        values.emplace(p.name, std::move(v));
    }
    out = SkillParameters(std::move(values));
    return ua::status::Good;
}

ua::StatusCode Skill::invoke(SkillMethod method, const ua::Caller& caller) {
    const SkillState current = state_.load();
    const auto transition = transitionFor(method, current);
    if (!transition) return ua::status::BadInvalidState;
    if (reservation_ && !reservation_->permits(caller)) {
        spdlog::info("skill {}: {} refused: reserved by {}", name_, skills::name(method),
                     reservation_->holder());
        return ua::status::BadUserAccessDenied;
    }
    if (method != SkillMethod::Start && reservedAgainst(caller)) {
        return ua::status::BadUserAccessDenied;
    }
    switch (method) {
        case SkillMethod::Start: {
            SkillParameters parameters;
            if (const auto s = fixParameters(parameters); s.isBad()) return s;
            owner_ = caller.sessionId;
            ++runId_;
            runActive_ = true;
            enter(*transition);
            behaviour_->start(parameters, SkillRun(weak_from_this(), runId_));
            break;
        }
        case SkillMethod::Suspend:
            enter(*transition);
            behaviour_->suspend();
            break;
        case SkillMethod::Resume:
            enter(*transition);
            behaviour_->resume();
            break;
        case SkillMethod::Halt: {
            const bool hadRun = runActive_;
            runActive_ = false;  // a late report of this run must not end the next one
            owner_ = NodeId{};
            enter(*transition, "halted by a client");
            if (hadRun) behaviour_->halt();
            break;
        }
        case SkillMethod::Reset:
            behaviour_->reset();
            enter(*transition);
            break;
    }
    return ua::status::Good;
}

void Skill::runEnded(std::uint64_t runId, bool success, std::string reason) {
    if (!runActive_ || runId != runId_) return;
    const SkillState current = state_.load();
    const auto transition =
        transitionBetween(current, success ? SkillState::Ready : SkillState::Halted);
    if (!transition) return;
    runActive_ = false;
    owner_ = NodeId{};
    if (!success && reason.empty()) reason = "failed";
    enter(*transition, reason);
}

void Skill::fault(std::string reason) {
    asio::post(executor_, [weak = weak_from_this(), r = std::move(reason)]() mutable {
        auto self = weak.lock();
        if (!self) return;
        const auto t = transitionBetween(self->state_.load(), SkillState::Halted);
        if (!t) return;
        const bool hadRun = self->runActive_;
        self->runActive_ = false;
        self->owner_ = NodeId{};
        self->enter(*t, r);
        if (hadRun) self->behaviour_->halt();
    });
}

void Skill::publishState(SkillState state) {
    AddressSpace& as = server_.addressSpace();
    state_.store(state);
    (void)as.setValue(child(nodeId_, "CurrentState"),
                      ua::LocalizedText{"", std::string(skills::name(state))});
    (void)as.setValue(child(nodeId_, "CurrentState/Id"), stateNodeId(state));
    (void)as.setValue(child(nodeId_, "CurrentState/Number"), static_cast<std::uint32_t>(state));
}

void Skill::enter(SkillTransition transition, const std::string& reason) {
    AddressSpace& as = server_.addressSpace();
    const auto now = ua::DateTime::now();
    publishState(toState(transition));
    const ua::LocalizedText transitionName{"", std::string(skills::name(transition))};
    (void)as.setValue(child(nodeId_, "LastTransition"), transitionName);
    (void)as.setValue(child(nodeId_, "LastTransition/Id"), transitionNodeId(transition));
    (void)as.setValue(child(nodeId_, "LastTransition/Number"),
                      static_cast<std::uint32_t>(transition));
    (void)as.setValue(child(nodeId_, "LastTransition/TransitionTime"), now);

    const SkillState from = fromState(transition);
    const SkillState to = toState(transition);
    ua::Event event;
    event.eventType = eventType_;
    event.sourceNode = nodeId_;
    event.sourceName = name_;
    event.time = now;
    event.message = ua::LocalizedText{
        "", reason.empty() ? std::string(skills::name(transition))
                           : std::string(skills::name(transition)) + ": " + reason};
    event.severity = to == SkillState::Halted && from != SkillState::Ready ? 700 : 300;
    auto field = [&event](std::vector<QualifiedName> at, Variant value) {
        event.fields.emplace_back(std::move(at), std::move(value));
    };
    field(path({"Transition"}), transitionName);
    field(path({"Transition", "Id"}), transitionNodeId(transition));
    field(path({"FromState"}), ua::LocalizedText{"", std::string(skills::name(from))});
    field(path({"FromState", "Id"}), stateNodeId(from));
    field(path({"ToState"}), ua::LocalizedText{"", std::string(skills::name(to))});
    field(path({"ToState", "Id"}), stateNodeId(to));
    server_.fireEvent(std::move(event));
    if (to == SkillState::Halted && !reason.empty()) {
        spdlog::info("skill {}: {} ({})", name_, skills::name(transition), reason);
    } else {
        spdlog::debug("skill {}: {}", name_, skills::name(transition));
    }
}

}  // namespace skillcell::skills
