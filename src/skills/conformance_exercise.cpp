#include "skills/conformance_exercise.hpp"

#include <deque>
#include <memory>
#include <vector>

#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include "skills/skill_transition_event.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/encoding/codec.hpp"

namespace skillcell::skills {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

std::string stateText(std::optional<SkillState> s) {
    return s ? std::string(name(*s)) : std::string("unknown");
}

std::string msText(milliseconds ms) {
    return std::to_string(ms.count()) + " ms";
}

/// The transition events of one skill, as they arrive from the subscription's publish
/// loop, for a coroutine that waits for them with a deadline. Shared with the event
/// callback, which may outlive the exercise by a publish cycle.
class EventInbox {
public:
    explicit EventInbox(const asio::any_io_executor& executor) : signal_(executor) {}

    void push(TransitionEvent e) {
        events_.push_back(std::move(e));
        signal_.cancel();
    }
    /// The subscription is gone: waits end now.
    void lose(ua::StatusCode why) {
        lost_ = why;
        signal_.cancel();
    }
    [[nodiscard]] ua::StatusCode lost() const { return lost_; }

    [[nodiscard]] bool empty() const { return events_.empty(); }

    /// Waits until an event is there (true) or `deadline` passed (false); takes nothing.
    asio::awaitable<bool> wait(Clock::time_point deadline) {
        while (events_.empty()) {
            if (lost_.isBad() || Clock::now() >= deadline) co_return false;
            signal_.expires_at(deadline);
            (void)co_await signal_.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        }
        co_return true;
    }

    /// The next event, or nullopt once `deadline` passed (or the subscription was lost).
    asio::awaitable<std::optional<TransitionEvent>> next(Clock::time_point deadline) {
        if (!co_await wait(deadline)) co_return std::nullopt;
        TransitionEvent e = std::move(events_.front());
        events_.pop_front();
        co_return e;
    }

private:
    asio::steady_timer signal_;
    std::deque<TransitionEvent> events_;
    ua::StatusCode lost_ = ua::status::Good;
};

/// CurrentState and LastTransition as read in one Read.
struct StateSnapshot {
    ua::StatusCode status = ua::status::Good;  // Bad: not readable
    std::optional<SkillState> state;           // from CurrentState's text
    std::string text;
    std::optional<ua::NodeId> id;
    std::optional<std::uint32_t> number;
    std::optional<ua::NodeId> lastTransitionId;
};

class Exerciser {
public:
    Exerciser(RemoteAddressSpace& remote, const SkillUnderTest& skill, ExerciseOptions options,
              ConformanceReport& report)
        : remote_(remote), skill_(skill), options_(std::move(options)), report_(report) {}

    asio::awaitable<void> run() {
        std::string missing;
        for (const auto m : kAllMethods) {
            if (!skill_.methods.at(static_cast<std::size_t>(m))) {
                missing += (missing.empty() ? "" : ", ") + std::string(name(m));
            }
        }
        if (!skill_.currentState)
            missing += (missing.empty() ? "" : ", ") + std::string("CurrentState");
        if (!missing.empty()) {
            fail("exercise", "Start, Suspend, Resume, Halt, Reset and CurrentState",
                 "missing " + missing + ": not exercised");
            co_return;
        }
        if (!co_await subscribe()) co_return;
        if (co_await drive()) co_await restore();
        if (subscription_) (void)co_await subscription_->remove();
    }

private:
    // --- Steps ------------------------------------------------------------------------

    /// The steps; false when the skill was left alone (not readable, or in use), so that
    /// nothing needs restoring.
    asio::awaitable<bool> drive() {
        const StateSnapshot start = co_await readState();
        if (start.status.isBad() || !start.state) {
            fail("exercise", "a readable CurrentState to begin with",
                 start.status.isBad() ? statusText(start.status) : "'" + start.text + "'");
            co_return false;
        }
        if (*start.state == SkillState::Running || *start.state == SkillState::Suspended) {
            report_.warn(skill_.path, "exercise", "the skill Ready or Halted to begin with",
                         stateText(start.state) + " (in use by someone else?): not exercised");
            co_return false;
        }
        if (*start.state == SkillState::Halted &&
            !co_await step(SkillMethod::Reset, SkillState::Halted)) {
            co_return true;
        }
        if (stopped() || !co_await refusals(SkillState::Ready)) co_return true;
        if (stopped() || !co_await step(SkillMethod::Halt, SkillState::Ready)) co_return true;
        if (stopped() || !co_await refusals(SkillState::Halted)) co_return true;
        if (stopped() || !co_await step(SkillMethod::Reset, SkillState::Halted)) co_return true;
        if (!stopped()) co_await startRun();
        co_return true;
    }

    /// Every method `state` does not allow answers BadInvalidState and changes nothing.
    asio::awaitable<bool> refusals(SkillState state) {
        for (const auto m : kAllMethods) {
            if (transitionFor(m, state)) continue;
            const std::string check = std::string(name(m)) + " in " + std::string(name(state));
            const ua::StatusCode s = co_await call(m);
            if (s == ua::status::BadInvalidState) {
                report_.pass(skill_.path, check, "BadInvalidState");
            } else {
                fail(check,
                     "BadInvalidState (" + std::string(name(state)) + " does not allow " +
                         std::string(name(m)) + ")",
                     statusText(s));
                if (!connected()) co_return false;
            }
        }
        const StateSnapshot after = co_await readState();
        if (after.state != state) {
            fail("refused calls in " + std::string(name(state)),
                 "CurrentState still " + std::string(name(state)),
                 after.status.isBad() ? statusText(after.status) : stateText(after.state));
            co_return false;
        }
        co_return true;
    }

    /// Calls `method` in `from` and expects its transition: Good, the event, then
    /// CurrentState and LastTransition after it.
    asio::awaitable<bool> step(SkillMethod method, SkillState from) {
        const auto transition = transitionFor(method, from);
        if (!transition) co_return false;  // not a step of the table
        const std::string check = std::string(name(method)) + " in " + std::string(name(from));
        const ua::StatusCode s = co_await call(method);
        if (s.isBad()) {
            fail(check, "Good and the transition " + std::string(name(*transition)), statusText(s));
            co_return false;
        }
        if (!co_await expectEvent(*transition, Clock::now() + options_.eventTimeout))
            co_return false;
        if (!co_await expectState(*transition)) co_return false;
        report_.pass(skill_.path, check,
                     "Good, event " + std::string(name(*transition)) + ", CurrentState " +
                         std::string(name(toState(*transition))));
        co_return true;
    }

    /// Start with the parameters as they are; the run ends in Ready or Halted in time.
    asio::awaitable<void> startRun() {
        const auto started = Clock::now();
        const ua::StatusCode s = co_await call(SkillMethod::Start);
        if (s.isBad()) {
            // A skill may refuse parameters it cannot work with (validated on Start).
            report_.warn(skill_.path, "Start in Ready", "Good (a run with the current parameters)",
                         statusText(s) + ": the run was not exercised");
            co_return;
        }
        if (!co_await expectEvent(SkillTransition::ReadyToRunning,
                                  Clock::now() + options_.eventTimeout)) {
            co_return;
        }
        report_.pass(skill_.path, "Start in Ready", "Good, event ReadyToRunning");

        // Suspend and Resume while the run lasts; a run that has already ended (its event
        // is waiting) is too short for that, which is no fault of the skill.
        auto deadline = started + options_.runTimeout;
        std::string note = " (too short to try Suspend)";
        if (inbox_->empty() && !stopped()) {
            const SuspendOutcome outcome = co_await suspendAndResume();
            if (outcome == SuspendOutcome::Failed) co_return;
            if (outcome == SuspendOutcome::Done) {
                note.clear();
                deadline = Clock::now() + options_.runTimeout;
            }
        }
        for (;;) {
            auto e = co_await inbox_->next(deadline);
            if (!e) {
                const StateSnapshot now = co_await readState();
                fail("run",
                     "RunningToReady or RunningToHalted within " + msText(options_.runTimeout),
                     "no event; CurrentState " + stateText(now.state));
                co_return;
            }
            const auto t = checkEvent(*e);
            if (t == SkillTransition::RunningToReady || t == SkillTransition::RunningToHalted) {
                const auto took = std::chrono::duration_cast<milliseconds>(Clock::now() - started);
                if (!co_await expectState(*t)) co_return;
                report_.pass(skill_.path, "run",
                             std::string(name(*t)) + " after " + msText(took) + note +
                                 (*t == SkillTransition::RunningToHalted
                                      ? " (it could not do its job with its current parameters)"
                                      : ""));
                co_return;
            }
            fail("run", "RunningToReady or RunningToHalted", "event " + eventText(*e));
        }
    }

    enum class SuspendOutcome : std::uint8_t { Done, EndedFirst, Failed };

    /// Running: Suspend, the refusals of Suspended, Resume.
    asio::awaitable<SuspendOutcome> suspendAndResume() {
        ua::StatusCode s = co_await call(SkillMethod::Suspend);
        if (s == ua::status::BadInvalidState) {
            // Right if the run ended meanwhile: its end event shows that.
            if (co_await inbox_->wait(Clock::now() + options_.eventTimeout)) {
                co_return SuspendOutcome::EndedFirst;
            }
            fail("Suspend in Running", "Good (Running allows Suspend), or the run's end event",
                 "BadInvalidState and no event");
            co_return SuspendOutcome::Failed;
        }
        if (s.isBad()) {
            fail("Suspend in Running", "Good (Running allows Suspend)", statusText(s));
            co_return SuspendOutcome::Failed;
        }
        if (!co_await expectEvent(SkillTransition::RunningToSuspended,
                                  Clock::now() + options_.eventTimeout) ||
            !co_await expectState(SkillTransition::RunningToSuspended)) {
            co_return SuspendOutcome::Failed;
        }
        report_.pass(skill_.path, "Suspend in Running",
                     "Good, event RunningToSuspended, CurrentState Suspended");
        if (!co_await refusals(SkillState::Suspended)) co_return SuspendOutcome::Failed;
        s = co_await call(SkillMethod::Resume);
        if (s.isBad()) {
            fail("Resume in Suspended", "Good and the transition SuspendedToRunning",
                 statusText(s));
            co_return SuspendOutcome::Failed;
        }
        // No state check after it: the run may end at once.
        if (!co_await expectEvent(SkillTransition::SuspendedToRunning,
                                  Clock::now() + options_.eventTimeout)) {
            co_return SuspendOutcome::Failed;
        }
        report_.pass(skill_.path, "Resume in Suspended", "Good, event SuspendedToRunning");
        co_return SuspendOutcome::Done;
    }

    /// Leaves the skill in Ready: Halt if it still runs, Reset if it is Halted.
    asio::awaitable<void> restore() {
        for (int attempt = 0; attempt < 3 && connected(); ++attempt) {
            const StateSnapshot now = co_await readState();
            if (now.state == SkillState::Ready) {
                report_.pass(skill_.path, "exercise end", "left in Ready");
                co_return;
            }
            if (!now.state) break;
            const SkillMethod method =
                *now.state == SkillState::Halted ? SkillMethod::Reset : SkillMethod::Halt;
            const ua::StatusCode s = co_await call(method);
            if (s.isBad()) break;
            // Wait for the transition, so that the next read sees its result.
            const auto transition = transitionFor(method, *now.state);
            const auto deadline = Clock::now() + options_.eventTimeout;
            while (auto e = co_await inbox_->next(deadline)) {
                if (transitionFromNodeId(e->transitionId) == transition) break;
            }
        }
        const StateSnapshot end = co_await readState();
        fail("exercise end", "the skill left in Ready",
             end.status.isBad() ? statusText(end.status) : stateText(end.state));
    }

    // --- Events -------------------------------------------------------------------------

    asio::awaitable<bool> subscribe() {
        auto& client = remote_.client();
        inbox_ = std::make_shared<EventInbox>(client.executor());
        std::weak_ptr<EventInbox> weak = inbox_;
        // Callbacks and the filter are named before co_await: GCC 12 destroys temporaries
        // inside a co_await expression twice (see ua::ClientConfig).
        ua::SubscriptionSettings settings(50, 600, 20);
        ua::Subscription::StatusCallback onStatus = [weak](ua::StatusCode s) {
            if (auto inbox = weak.lock(); inbox && s.isBad() && s != ua::status::BadTimeout) {
                inbox->lose(s);
            }
        };
        auto sub = co_await client.createSubscription(settings, std::move(onStatus));
        if (!sub) {
            fail("event subscription", "a subscription (CreateSubscription)",
                 statusText(sub.status()));
            co_return false;
        }
        subscription_ = *sub;
        const ua::NodeId notifier =
            skill_.eventNotifier ? skill_.nodeId : ua::NodeId(ua::ns0::Server);
        ua::Subscription::EventCallback onEvent =
            [weak, source = skill_.nodeId](const std::vector<ua::Variant>& fields) {
                auto inbox = weak.lock();
                if (!inbox) return;
                TransitionEvent e = parseTransitionEvent(fields);
                // On the Server object every event of the server arrives: keep the skill's.
                if (e.sourceNode == source) inbox->push(std::move(e));
            };
        ua::EventFilter filter = transitionEventFilter();
        auto item =
            co_await subscription_->monitorEvents(notifier, std::move(filter), std::move(onEvent));
        const std::string where = skill_.eventNotifier ? "the skill" : "the Server object";
        if (!item) {
            fail("event subscription", "a monitored item for the skill's events on " + where,
                 statusText(item.status()));
            (void)co_await subscription_->remove();
            subscription_.reset();
            co_return false;
        }
        ua::EventFilterResult result;
        if (!item->filterResult.empty() &&
            ua::fromExtensionObject(item->filterResult, result).isGood()) {
            std::string refused;
            for (std::size_t i = 0; i < result.selectClauseResults.size(); ++i) {
                const auto s = result.selectClauseResults[i];
                if (s.isGood()) continue;
                refused += (refused.empty() ? "" : ", ") +
                           fieldName(static_cast<TransitionEventField>(i)) + " " + statusText(s);
            }
            if (!refused.empty()) {
                fail("event subscription", "every field of TransitionEventType selectable",
                     refused);
            }
        }
        report_.pass(skill_.path, "event subscription", "on " + where);
        co_return true;
    }

    /// The next events until `expected` arrives; others are failures.
    asio::awaitable<bool> expectEvent(SkillTransition expected, Clock::time_point deadline) {
        const std::string check = "event " + std::string(name(expected));
        for (;;) {
            auto e = co_await inbox_->next(deadline);
            if (!e) {
                fail(check, "the event within " + msText(options_.eventTimeout),
                     inbox_->lost().isBad() ? "subscription lost: " + statusText(inbox_->lost())
                                            : "none");
                co_return false;
            }
            const auto t = checkEvent(*e);
            if (t == expected) {
                co_await checkEventType(*e, check);
                co_return true;
            }
            fail(check, "this event next", "event " + eventText(*e));
        }
    }

    /// The event's transition if its fields agree with each other and with the table.
    std::optional<SkillTransition> checkEvent(const TransitionEvent& e) {
        const auto t = transitionFromNodeId(e.transitionId);
        const std::string check = "event " + (t ? std::string(name(*t)) : eventText(e));
        if (!e.missing.empty()) {
            std::string fields;
            for (const auto& m : e.missing) fields += (fields.empty() ? "" : ", ") + m;
            fail(check, "every TransitionEventType field", "missing " + fields);
        }
        if (!t) {
            fail(check, "Transition/Id one of ProgramStateMachineType's transitions",
                 e.transitionId.toString());
            return std::nullopt;
        }
        const SkillState from = fromState(*t);
        const SkillState to = toState(*t);
        if (e.transition.text != name(*t)) {
            fail(check, "Transition '" + std::string(name(*t)) + "'",
                 "'" + e.transition.text + "'");
        }
        if (e.fromStateId != stateNodeId(from) || e.fromState.text != name(from)) {
            fail(check,
                 "FromState " + std::string(name(from)) + " (" + stateNodeId(from).toString() + ")",
                 "'" + e.fromState.text + "' (" + e.fromStateId.toString() + ")");
        }
        if (e.toStateId != stateNodeId(to) || e.toState.text != name(to)) {
            fail(check,
                 "ToState " + std::string(name(to)) + " (" + stateNodeId(to).toString() + ")",
                 "'" + e.toState.text + "' (" + e.toStateId.toString() + ")");
        }
        if (e.time.ticks == 0) fail(check, "a Time", "none");
        return t;
    }

    asio::awaitable<void> checkEventType(const TransitionEvent& e, const std::string& check) {
        auto sub = co_await remote_.isSubtypeOf(e.eventType, options_.skillTransitionEventType);
        if (!sub || !*sub) {
            fail(check,
                 "EventType " + co_await remote_.describe(options_.skillTransitionEventType) +
                     " or a subtype",
                 e.eventType.isNull() ? "none" : co_await remote_.describe(e.eventType));
        }
    }

    static std::string eventText(const TransitionEvent& e) {
        std::string s = e.transition.text.empty() ? e.transitionId.toString() : e.transition.text;
        return s + " (" + e.fromState.text + " -> " + e.toState.text + ")";
    }

    // --- State --------------------------------------------------------------------------

    asio::awaitable<StateSnapshot> readState() {
        StateSnapshot snap;
        std::vector<ua::ReadValueId> ids;
        auto ask = [&ids](const std::optional<ua::NodeId>& node) {
            ua::ReadValueId id;
            id.nodeId = node.value_or(ua::NodeId());
            ids.push_back(std::move(id));
        };
        ask(skill_.currentState);
        ask(skill_.currentStateId);
        ask(skill_.currentStateNumber);
        ask(skill_.lastTransitionId);
        auto values = co_await remote_.read(std::move(ids));
        if (!values) {
            snap.status = values.status();
            co_return snap;
        }
        const auto& v = *values;
        if (v[0].statusOrGood().isBad()) {
            snap.status = v[0].statusOrGood();
            co_return snap;
        }
        if (const auto* lt = v[0].value ? v[0].value->get<ua::LocalizedText>() : nullptr) {
            snap.text = lt->text;
            snap.state = stateFromName(lt->text);
        }
        if (const auto* id = v[1].value ? v[1].value->get<ua::NodeId>() : nullptr) snap.id = *id;
        if (const auto* n = v[2].value ? v[2].value->get<std::uint32_t>() : nullptr)
            snap.number = *n;
        if (const auto* id = v[3].value ? v[3].value->get<ua::NodeId>() : nullptr) {
            snap.lastTransitionId = *id;
        }
        co_return snap;
    }

    /// After `transition`'s event: CurrentState (text, Id, Number) is its ToState and
    /// LastTransition/Id is the transition.
    asio::awaitable<bool> expectState(SkillTransition transition) {
        const SkillState to = toState(transition);
        const StateSnapshot snap = co_await readState();
        const std::string check = "after " + std::string(name(transition));
        if (snap.status.isBad()) {
            fail(check, "CurrentState readable", statusText(snap.status));
            co_return false;
        }
        bool ok = true;
        if (snap.state != to || (skill_.currentStateId && snap.id != stateNodeId(to)) ||
            (skill_.currentStateNumber && snap.number != static_cast<std::uint32_t>(to))) {
            ok = false;
            fail(check,
                 "CurrentState " + std::string(name(to)) + " (Id " + stateNodeId(to).toString() +
                     ", Number " + std::to_string(static_cast<std::uint32_t>(to)) + ")",
                 "'" + snap.text + "' (Id " + (snap.id ? snap.id->toString() : "none") +
                     ", Number " + (snap.number ? std::to_string(*snap.number) : "none") + ")");
        }
        if (skill_.lastTransitionId && snap.lastTransitionId != transitionNodeId(transition)) {
            ok = false;
            fail(check, "LastTransition/Id " + transitionNodeId(transition).toString(),
                 snap.lastTransitionId ? snap.lastTransitionId->toString() : "none");
        }
        co_return ok;
    }

    // --- Helpers ------------------------------------------------------------------------

    asio::awaitable<ua::StatusCode> call(SkillMethod method) {
        const auto& id = skill_.methods.at(static_cast<std::size_t>(method));
        if (!id) co_return ua::status::BadMethodInvalid;
        std::vector<ua::Variant> inputs;  // the state machine's methods take none
        auto result = co_await remote_.client().call(skill_.nodeId, *id, std::move(inputs));
        co_return result.status();
    }

    bool connected() { return remote_.client().isConnected(); }

    /// A stop was asked for: reported once, and the steps that remain are skipped.
    bool stopped() {
        if (!options_.stopRequested || !options_.stopRequested()) return false;
        if (!stopReported_) {
            stopReported_ = true;
            fail("exercise", "every step", "interrupted: the remaining steps were skipped");
        }
        return true;
    }

    void fail(const std::string& check, std::string expected, std::string found) {
        report_.fail(skill_.path, check, std::move(expected), std::move(found));
    }

    RemoteAddressSpace& remote_;
    const SkillUnderTest& skill_;
    ExerciseOptions options_;
    ConformanceReport& report_;
    std::shared_ptr<EventInbox> inbox_;
    std::shared_ptr<ua::Subscription> subscription_;
    bool stopReported_ = false;
};

}  // namespace

asio::awaitable<void> exerciseSkill(RemoteAddressSpace& remote, const SkillUnderTest& skill,
                                    ExerciseOptions options, ConformanceReport& report) {
    Exerciser exerciser(remote, skill, std::move(options), report);
    co_await exerciser.run();
}

}  // namespace skillcell::skills
