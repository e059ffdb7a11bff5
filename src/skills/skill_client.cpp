#include "skills/skill_client.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include <asio/experimental/as_tuple.hpp>
#include <asio/use_awaitable.hpp>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/client/subscription.hpp"

namespace skillcell::skills {
namespace {

using ua::NodeId;
using ua::QualifiedName;
using ua::StatusCode;
using ua::Variant;

constexpr std::size_t kMaxTransitionsKept = 256;
/// How long an end read back waits for its own event, which carries the reason.
constexpr std::chrono::milliseconds kEventGrace{500};

/// Select clauses, in the order onEvent reads them: fewer than transitionEventFilter() has,
/// since a client needs only the transition and its time.
ua::EventFilter clientEventFilter() {
    ua::EventFilter filter;
    auto select = [&filter](std::uint32_t type, std::vector<QualifiedName> path) {
        ua::SimpleAttributeOperand op;
        op.typeDefinitionId = NodeId(type);
        op.browsePath = std::move(path);
        filter.selectClauses.push_back(std::move(op));
    };
    select(ua::ns0::BaseEventType, {{0, "Time"}});
    select(ua::ns0::BaseEventType, {{0, "Message"}});
    select(ua::ns0::TransitionEventType, {{0, "FromState"}, {0, "Id"}});
    select(ua::ns0::TransitionEventType, {{0, "ToState"}, {0, "Id"}});
    select(ua::ns0::TransitionEventType, {{0, "Transition"}, {0, "Id"}});
    return filter;
}

/// "RunningToHalted: gripper jammed" -> "gripper jammed" (the reason without the
/// transition's name that our skills put first).
std::string reasonOf(const SkillTransitionRecord& r) {
    if (r.transition) {
        const std::string prefix = std::string(name(*r.transition)) + ": ";
        if (r.message.starts_with(prefix)) return r.message.substr(prefix.size());
        if (r.message == name(*r.transition)) return {};
    }
    return r.message;
}

}  // namespace

std::string_view name(SkillOutcome::Kind kind) {
    switch (kind) {
        case SkillOutcome::Kind::Finished:
            return "Finished";
        case SkillOutcome::Kind::Failed:
            return "Failed";
        case SkillOutcome::Kind::Refused:
            return "Refused";
        case SkillOutcome::Kind::TimedOut:
            return "TimedOut";
        case SkillOutcome::Kind::Cancelled:
            return "Cancelled";
        case SkillOutcome::Kind::Lost:
            return "Lost";
    }
    return "?";
}

SkillClient::SkillClient(Token, ua::Client& client, NodeId skill)
    : client_(client), skill_(std::move(skill)), wakeUp_(client.executor()) {}

SkillClient::~SkillClient() = default;

asio::awaitable<ua::Result<std::shared_ptr<SkillClient>>> SkillClient::attach(
    ua::Client& client, NodeId skill, SkillClientOptions options) {
    auto self = std::make_shared<SkillClient>(Token{}, client, std::move(skill));
    self->confirmAfter_ = options.confirmAfter;
    if (const auto s = co_await self->resolve(); s.isBad()) co_return s;
    if (const auto s = co_await self->subscribe(options); s.isBad()) co_return s;
    co_return self;
}

asio::awaitable<StatusCode> SkillClient::resolve() {
    auto children = co_await client_.browse(skill_);
    if (!children) co_return children.status();
    NodeId parameterSet;
    NodeId lastTransition;
    for (const auto& ref : children->references) {
        if (!ref.nodeId.isLocal()) continue;
        const auto& bn = ref.browseName;
        if (bn.namespaceIndex == 0 && ref.nodeClass == ua::NodeClass::Method) {
            if (const auto m = methodFromName(bn.name)) methods_[*m] = ref.nodeId.nodeId;
        } else if (bn.namespaceIndex == 0 && bn.name == "CurrentState") {
            currentStateId_ = ref.nodeId.nodeId;
        } else if (bn.namespaceIndex == 0 && bn.name == "LastTransition") {
            lastTransition = ref.nodeId.nodeId;
        } else if (bn.name == "ParameterSet" && ref.nodeClass == ua::NodeClass::Object) {
            parameterSet = ref.nodeId.nodeId;
        }
    }
    if (methods_.size() != kAllMethods.size() || currentStateId_.isNull()) {
        co_return ua::status::BadNotSupported;
    }

    if (!parameterSet.isNull()) {
        auto params = co_await client_.browse(parameterSet);
        if (!params) co_return params.status();
        ua::ReadRequest read;
        for (const auto& ref : params->references) {
            if (!ref.nodeId.isLocal() || ref.nodeClass != ua::NodeClass::Variable) continue;
            RemoteParameter p;
            p.name = ref.browseName.name;
            p.nodeId = ref.nodeId.nodeId;
            parameters_.push_back(std::move(p));
            for (auto attribute : {ua::AttributeId::DataType, ua::AttributeId::ValueRank}) {
                ua::ReadValueId item;
                item.nodeId = ref.nodeId.nodeId;
                item.attributeId = static_cast<std::uint32_t>(attribute);
                read.nodesToRead.push_back(std::move(item));
            }
        }
        if (!read.nodesToRead.empty()) {
            auto values = co_await client_.read(std::move(read));
            if (!values) co_return values.status();
            for (std::size_t i = 0; i < parameters_.size() && 2 * i + 1 < values->results.size();
                 ++i) {
                const auto& type = values->results[2 * i].value;
                const auto& rank = values->results[2 * i + 1].value;
                if (type && type->get<NodeId>()) parameters_[i].dataType = *type->get<NodeId>();
                if (rank && rank->get<std::int32_t>()) {
                    parameters_[i].valueRank = *rank->get<std::int32_t>();
                }
            }
        }
    }

    // LastTransition's Id and TransitionTime, to read a run's end back when its event is lost
    // (optional in the model: without them, only events tell).
    if (!lastTransition.isNull()) {
        auto parts = co_await client_.browse(lastTransition);
        if (!parts) co_return parts.status();
        for (const auto& ref : parts->references) {
            if (!ref.nodeId.isLocal() || ref.browseName.namespaceIndex != 0) continue;
            if (ref.browseName.name == "Id") lastTransitionId_ = ref.nodeId.nodeId;
            if (ref.browseName.name == "TransitionTime") lastTransitionTime_ = ref.nodeId.nodeId;
        }
    }

    auto current = co_await client_.readValue(currentStateId_);
    if (!current) co_return current.status();
    if (const auto* text = current->get<ua::LocalizedText>()) state_ = stateFromName(text->text);
    co_return ua::status::Good;
}

asio::awaitable<StatusCode> SkillClient::subscribe(SkillClientOptions options) {
    std::weak_ptr<SkillClient> weak = weak_from_this();
    // Named, not temporaries inside the co_await expressions: GCC 12 destroys such
    // temporaries twice, which would drop the weak references twice.
    ua::Subscription::StatusCallback onStatus = [weak](StatusCode s) {
        if (auto self = weak.lock()) self->onSubscriptionStatus(s);
    };
    ua::Subscription::EventCallback onEvents = [weak](const std::vector<Variant>& fields) {
        if (auto self = weak.lock()) self->onEvent(fields);
    };
    ua::SubscriptionSettings settings(options.publishingIntervalMs, 3 * options.maxKeepAliveCount,
                                      options.maxKeepAliveCount);
    auto sub = co_await client_.createSubscription(settings, std::move(onStatus));
    if (!sub) co_return sub.status();
    subscription_ = *sub;
    ua::EventFilter filter = clientEventFilter();
    auto item =
        co_await subscription_->monitorEvents(skill_, std::move(filter), std::move(onEvents));
    if (!item) co_return item.status();
    co_return ua::status::Good;
}

void SkillClient::onEvent(const std::vector<Variant>& fields) {
    if (fields.size() < 5) return;
    SkillTransitionRecord r;
    if (const auto* t = fields[0].get<ua::DateTime>()) r.time = *t;
    if (const auto* m = fields[1].get<ua::LocalizedText>()) r.message = m->text;
    if (const auto* id = fields[2].get<NodeId>()) r.from = stateFromNodeId(*id);
    if (const auto* id = fields[3].get<NodeId>()) r.to = stateFromNodeId(*id);
    if (const auto* id = fields[4].get<NodeId>()) r.transition = transitionFromNodeId(*id);
    if (!r.to) return;  // not a transition of the skill state machine
    ++eventsHeard_;
    // The same transition read back before its event came late: not twice.
    for (const auto& known : transitions_) {
        if (known.time == r.time && known.transition == r.transition) return;
    }
    record(std::move(r));
}

void SkillClient::record(SkillTransitionRecord r) {
    state_ = r.to;
    transitions_.push_back(std::move(r));
    if (transitions_.size() > kMaxTransitionsKept) transitions_.pop_front();
    wakeUp_.cancel();
    if (transitionListener_) transitionListener_(transitions_.back());
}

void SkillClient::onSubscriptionStatus(StatusCode s) {
    if (s.isGood()) return;
    // Notifications lost in a gap, or a keep-alive that is late: the state is read back (a
    // server that does not answer that read is lost then).
    if (s == ua::status::BadMessageNotAvailable || s == ua::status::BadTimeout) {
        confirm_ = true;
        wakeUp_.cancel();
        return;
    }
    // Any other Bad status ends the wait: the connection or session is gone, or the server
    // dropped the subscription.
    lost_ = s;
    wakeUp_.cancel();
}

asio::awaitable<StatusCode> SkillClient::readBack() {
    if (lastTransitionId_.isNull() || lastTransitionTime_.isNull()) co_return ua::status::Good;
    ua::ReadRequest read;
    for (const auto& node : {currentStateId_, lastTransitionId_, lastTransitionTime_}) {
        ua::ReadValueId item;
        item.nodeId = node;
        item.attributeId = static_cast<std::uint32_t>(ua::AttributeId::Value);
        read.nodesToRead.push_back(std::move(item));
    }
    auto values = co_await client_.read(std::move(read));
    if (!values) co_return values.status();
    if (values->results.size() != 3 || !runStartedAt_) co_return ua::status::Good;
    const auto& v = values->results;
    const auto* text = v[0].value ? v[0].value->get<ua::LocalizedText>() : nullptr;
    const auto* id = v[1].value ? v[1].value->get<NodeId>() : nullptr;
    const auto* time = v[2].value ? v[2].value->get<ua::DateTime>() : nullptr;
    if (text == nullptr || id == nullptr || time == nullptr) co_return ua::status::Good;
    const auto state = stateFromName(text->text);
    const auto transition = transitionFromNodeId(*id);
    // Only an end of this run: after its Start (both times are the server's), from Running or
    // Suspended to where the skill is now.
    if (!state || !transition || *time < *runStartedAt_) co_return ua::status::Good;
    const SkillState from = fromState(*transition);
    const SkillState to = toState(*transition);
    if ((from != SkillState::Running && from != SkillState::Suspended) ||
        (to != SkillState::Ready && to != SkillState::Halted) || *state != to) {
        co_return ua::status::Good;
    }
    const auto heard = [&] {
        return std::any_of(transitions_.begin(), transitions_.end(), [&](const auto& known) {
            return known.time == *time && known.transition == transition;
        });
    };
    if (heard()) co_return ua::status::Good;
    // The end may be read just before its event arrives (a read every quiet second races
    // every end): the event, which carries the reason, gets a moment to come first.
    {
        using asio::experimental::as_tuple;
        const auto until = std::chrono::steady_clock::now() + kEventGrace;
        while (!heard() && std::chrono::steady_clock::now() < until && lost_.isGood() &&
               !cancelled_) {
            wakeUp_.expires_at(until);
            co_await wakeUp_.async_wait(as_tuple(asio::use_awaitable));
        }
        if (heard()) co_return ua::status::Good;
    }
    spdlog::warn("skill {}: its run ended ({}) without an event reaching us; read back",
                 skill_.toString(), name(*transition));
    record({*time, from, to, transition,
            std::string(name(*transition)) +
                ": its event was lost, so its reason is only in the skill server's log"});
    co_return ua::status::Good;
}

const RemoteParameter* SkillClient::parameter(std::string_view name) const {
    const auto it = std::find_if(parameters_.begin(), parameters_.end(),
                                 [name](const RemoteParameter& p) { return p.name == name; });
    return it != parameters_.end() ? &*it : nullptr;
}

asio::awaitable<StatusCode> SkillClient::setParameter(std::string parameterName, Variant value) {
    const RemoteParameter* p = parameter(parameterName);
    if (p == nullptr) co_return ua::status::BadNoMatch;
    co_return co_await client_.writeValue(p->nodeId, std::move(value));
}

asio::awaitable<StatusCode> SkillClient::call(SkillMethod method) {
    // A run begins: a cancel() from now on is this run's, even one that comes while the
    // Start call is on its way (before its answer, the server may already be Running).
    if (method == SkillMethod::Start) cancelled_ = false;
    co_return co_await callMethod(method);
}

asio::awaitable<StatusCode> SkillClient::callMethod(SkillMethod method) {
    ua::CallRequest req;
    req.methodsToCall.push_back(ua::CallMethodRequest{skill_, methods_.at(method), {}});
    auto resp = co_await client_.request<ua::CallRequest, ua::CallResponse>(std::move(req));
    if (!resp) co_return resp.status();
    if (resp->results.size() != 1) co_return ua::status::BadUnknownResponse;
    const StatusCode s = resp->results.front().statusCode;
    if (method == SkillMethod::Start && s.isGood()) runStartedAt_ = resp->responseHeader.timestamp;
    co_return s;
}

asio::awaitable<StatusCode> SkillClient::start() {
    co_return co_await call(SkillMethod::Start);
}

std::optional<SkillOutcome> SkillClient::endOfRun() const {
    if (!runStartedAt_) return std::nullopt;
    for (const auto& r : transitions_) {
        if (r.time < *runStartedAt_ || !r.from || !r.to) continue;
        if (*r.from != SkillState::Running && *r.from != SkillState::Suspended) continue;
        if (*r.to == SkillState::Ready) return SkillOutcome{SkillOutcome::Kind::Finished, {}, {}};
        if (*r.to == SkillState::Halted) {
            return SkillOutcome{SkillOutcome::Kind::Failed, ua::status::Good, reasonOf(r)};
        }
    }
    return std::nullopt;
}

asio::awaitable<SkillOutcome> SkillClient::haltAfter(SkillOutcome::Kind kind) {
    SkillOutcome outcome{kind, ua::status::Good, {}};
    // Halt may race with the run's own end: BadInvalidState then just means it ended.
    const StatusCode halted = co_await callMethod(SkillMethod::Halt);
    cancelled_ = false;  // taken: it ended this run
    if (halted.isBad() && halted != ua::status::BadInvalidState) outcome.status = halted;
    outcome.reason = kind == SkillOutcome::Kind::TimedOut ? "no end within the timeout; halted"
                                                          : "cancelled; halted";
    runStartedAt_.reset();
    co_return outcome;
}

asio::awaitable<SkillOutcome> SkillClient::waitForEnd(std::chrono::milliseconds timeout) {
    using asio::experimental::as_tuple;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    if (!runStartedAt_) {
        co_return SkillOutcome{SkillOutcome::Kind::Refused, ua::status::BadInvalidState,
                               "no run was started"};
    }
    for (;;) {
        if (auto end = endOfRun()) {
            runStartedAt_.reset();
            co_return *end;
        }
        if (lost_.isBad()) {
            co_return SkillOutcome{SkillOutcome::Kind::Lost, lost_,
                                   "lost the skill's server before the run ended"};
        }
        if (cancelled_) co_return co_await haltAfter(SkillOutcome::Kind::Cancelled);
        const auto now = std::chrono::steady_clock::now();
        if (now >= deadline) co_return co_await haltAfter(SkillOutcome::Kind::TimedOut);
        if (confirm_) {
            confirm_ = false;
            if (const StatusCode s = co_await readBack(); s.isBad()) lost_ = s;
            continue;
        }
        // Quiet for confirmAfter: an event may have been lost on the way, so ask.
        const std::uint64_t heard = eventsHeard_;
        wakeUp_.expires_at(std::min(deadline, now + confirmAfter_));
        auto [ec] = co_await wakeUp_.async_wait(as_tuple(asio::use_awaitable));
        if (!ec && eventsHeard_ == heard) confirm_ = true;
    }
}

asio::awaitable<SkillOutcome> SkillClient::run(std::map<std::string, Variant> parameters,
                                               std::chrono::milliseconds timeout) {
    if (auto refused = co_await writeParameters(std::move(parameters))) co_return *refused;
    co_return co_await startAndAwaitEnd(timeout);
}

asio::awaitable<std::optional<SkillOutcome>> SkillClient::writeParameters(
    std::map<std::string, Variant> parameters) {
    cancelled_ = false;  // the run begins here: a cancel() from now on is its own
    auto refusal = [](StatusCode s, const std::string& name) {
        return SkillOutcome{SkillOutcome::Kind::Refused, s, "parameter " + name + " refused"};
    };
    ua::WriteRequest req;
    std::vector<std::string> names;  // of req.nodesToWrite, in its order
    for (auto& [parameterName, value] : parameters) {
        const RemoteParameter* p = parameter(parameterName);
        if (p == nullptr) co_return refusal(ua::status::BadNoMatch, parameterName);
        ua::WriteValue wv;
        wv.nodeId = p->nodeId;
        wv.attributeId = static_cast<std::uint32_t>(ua::AttributeId::Value);
        wv.value.value = std::move(value);
        req.nodesToWrite.push_back(std::move(wv));
        names.push_back(parameterName);
    }
    if (req.nodesToWrite.empty()) co_return std::nullopt;
    // One request for all: a skill with several parameters costs one round trip, not one each.
    auto resp = co_await client_.write(std::move(req));
    if (!resp) co_return refusal(resp.status(), names.front());
    if (resp->results.size() != names.size()) {
        co_return refusal(ua::status::BadUnknownResponse, names.front());
    }
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (resp->results[i].isBad()) co_return refusal(resp->results[i], names[i]);
    }
    co_return std::nullopt;
}

asio::awaitable<SkillOutcome> SkillClient::startAndAwaitEnd(std::chrono::milliseconds timeout) {
    if (cancelled_) {
        cancelled_ = false;
        co_return SkillOutcome{SkillOutcome::Kind::Cancelled, ua::status::Good,
                               "cancelled before Start"};
    }
    const StatusCode started = co_await callMethod(SkillMethod::Start);
    if (started.isBad()) {
        const bool lost = started == ua::status::BadConnectionClosed ||
                          started == ua::status::BadServerNotConnected ||
                          started == ua::status::BadTimeout;
        co_return SkillOutcome{lost ? SkillOutcome::Kind::Lost : SkillOutcome::Kind::Refused,
                               started, "Start refused"};
    }
    co_return co_await waitForEnd(timeout);
}

void SkillClient::adoptRun(ua::DateTime startedAt) {
    runStartedAt_ = startedAt;
    cancelled_ = false;
}

void SkillClient::cancel() {
    cancelled_ = true;
    wakeUp_.cancel();
}

asio::awaitable<void> SkillClient::detach() {
    if (subscription_) {
        (void)co_await subscription_->remove();
        subscription_.reset();
    }
}

}  // namespace skillcell::skills
