#pragma once
// SkillClient: a typed proxy for one skill on a remote server. It writes parameters, calls
// the methods, and learns how a run ended from the skill's transition events (an event
// subscription on the skill object), with a timeout and cancellation (both Halt the skill).
// A server that goes away ends a wait as Lost: a caller never hangs on a vanished component.
//
// Events can be lost on the way (a Publish response that never arrives, a gap Republish
// cannot fill). So the client reads CurrentState and LastTransition back when the
// subscription reports lost notifications or a late keep-alive, and after every second of
// quiet while a run is awaited: a run that ended without its event still ends, within about
// a second and a half. An end read back waits up to half a second for its event, which
// carries the reason (a Halted run read back without it says so). A server that does not
// answer that read is lost.
//
// Which end belongs to which run: events carry the server's Time. The end of the run this
// client started is the first transition to Ready or Halted whose Time is not before the
// Start call's response timestamp (both from the server's clock): transitions of earlier
// runs happened before that Start could succeed, and the end of this run happens after the
// Start call returned (skills report ends asynchronously).
//
// Threading: like ua::Client, use it from the client's executor only.
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "skills/skill_state_machine.hpp"
#include "ua/client/client.hpp"

namespace skillcell::skills {

/// How a run ended, as the client saw it.
struct SkillOutcome {
    enum class Kind : std::uint8_t {
        Finished,   // the skill went back to Ready
        Failed,     // the skill went to Halted; `reason` says why
        Refused,    // a parameter write or Start was refused; `status` says why
        TimedOut,   // no end within the timeout; the client halted the skill
        Cancelled,  // cancel() was called; the client halted the skill
        Lost,       // the connection, session or subscription was lost; `status` says how
    };
    Kind kind = Kind::Lost;
    ua::StatusCode status = ua::status::Good;
    std::string reason;
    [[nodiscard]] bool ok() const { return kind == Kind::Finished; }
};
[[nodiscard]] std::string_view name(SkillOutcome::Kind kind);

/// A parameter of the remote skill, as its ParameterSet declares it.
struct RemoteParameter {
    std::string name;
    ua::NodeId nodeId;
    ua::NodeId dataType;
    std::int32_t valueRank = -1;
};

/// One transition event as received.
struct SkillTransitionRecord {
    ua::DateTime time;
    std::optional<SkillState> from;
    std::optional<SkillState> to;
    std::optional<SkillTransition> transition;
    std::string message;
};

struct SkillClientOptions {
    SkillClientOptions() = default;  // not an aggregate: GCC 12 (see ua::ClientConfig)
    /// Asked of the server for the event subscription; it may revise it upwards. Events come
    /// within one interval.
    double publishingIntervalMs = 10;
    /// Publishes without events before the server sends a keep-alive: 100 x 10 ms, so the
    /// client takes a server for lost after 1.5 s of silence. Much less (0.15 s) mistook a
    /// loaded machine's late publish, under the sanitizers on 2 cores, for a lost component.
    std::uint32_t maxKeepAliveCount = 100;
    /// While a run is awaited and no event arrives for this long, the skill's CurrentState
    /// and LastTransition are read: a run whose end event was lost still ends (at once, too,
    /// when the subscription reports lost notifications or a late keep-alive).
    std::chrono::milliseconds confirmAfter{1000};
};

class SkillClient : public std::enable_shared_from_this<SkillClient> {
public:
    /// Resolves the skill object's methods, CurrentState and parameters (by browsing it)
    /// and subscribes to its events. BadNodeIdUnknown, or BadNotSupported for an object
    /// that lacks the skill methods or CurrentState; the client's errors otherwise.
    static asio::awaitable<ua::Result<std::shared_ptr<SkillClient>>> attach(
        ua::Client& client, ua::NodeId skill, SkillClientOptions options = {});
    ~SkillClient();
    SkillClient(const SkillClient&) = delete;
    SkillClient& operator=(const SkillClient&) = delete;

    [[nodiscard]] const ua::NodeId& nodeId() const { return skill_; }
    [[nodiscard]] const std::vector<RemoteParameter>& parameters() const { return parameters_; }
    /// The declared parameter called `name`; null when the skill has none of that name.
    [[nodiscard]] const RemoteParameter* parameter(std::string_view name) const;
    /// The state last learnt (read at attach, then from events).
    [[nodiscard]] std::optional<SkillState> state() const { return state_; }
    /// Good while the event subscription lives; once the subscription or the session is
    /// lost, why (and every later run ends Lost at once).
    [[nodiscard]] ua::StatusCode lost() const { return lost_; }
    /// LastTransition/TransitionTime, as found at attach (null when the skill has none).
    [[nodiscard]] const ua::NodeId& lastTransitionTimeNode() const { return lastTransitionTime_; }
    /// Every transition event received since attach, oldest first (at most 256 kept).
    [[nodiscard]] const std::deque<SkillTransitionRecord>& transitions() const {
        return transitions_;
    }

    /// Called on the executor with each transition event as it arrives, after state() and
    /// transitions() took it in (a watcher such as the dashboard; one listener).
    void onTransition(std::function<void(const SkillTransitionRecord&)> listener) {
        transitionListener_ = std::move(listener);
    }

    /// Writes one parameter by name: BadNoMatch for a name the skill does not declare,
    /// else the server's answer (BadOutOfRange, BadTypeMismatch, BadUserAccessDenied...).
    asio::awaitable<ua::StatusCode> setParameter(std::string name, ua::Variant value);
    /// Calls one method: Good, BadInvalidState, BadUserAccessDenied, ... Start begins a run:
    /// a cancel() from the moment it is sent is that run's.
    asio::awaitable<ua::StatusCode> call(SkillMethod method);
    /// Start: Good (then await it with waitForEnd) or the refusal.
    asio::awaitable<ua::StatusCode> start();
    /// Waits for the end of the run start() began. On timeout or cancel() it calls Halt.
    asio::awaitable<SkillOutcome> waitForEnd(std::chrono::milliseconds timeout);
    /// Takes over a run someone else started (a restarted MES finding its step's skill
    /// Running): waitForEnd() then waits for the first end at or after `startedAt` (the
    /// server's time of the transition to Running).
    void adoptRun(ua::DateTime startedAt);
    /// Writes `parameters`, starts, waits for the end: the whole invocation
    /// (writeParameters(), then startAndAwaitEnd()).
    asio::awaitable<SkillOutcome> run(std::map<std::string, ua::Variant> parameters,
                                      std::chrono::milliseconds timeout);
    /// The first half of run(): writes `parameters` in one Write request. Nothing when all
    /// were written, else the refusal naming the first one refused (BadNoMatch, before
    /// anything is sent, for a name the skill does not declare). The run begins here: a
    /// cancel() from now on is its own.
    asio::awaitable<std::optional<SkillOutcome>> writeParameters(
        std::map<std::string, ua::Variant> parameters);
    /// The second half of run(): Start, then waitForEnd(). Cancelled, without a Start, when
    /// cancel() came since writeParameters().
    asio::awaitable<SkillOutcome> startAndAwaitEnd(std::chrono::milliseconds timeout);
    /// Makes a pending waitForEnd/run halt the skill and return Cancelled (any thread of
    /// the executor; safe when nothing waits).
    void cancel();
    /// Deletes the event subscription (the destructor cannot talk to the server).
    asio::awaitable<void> detach();

    struct Token {  // attach() only
    private:
        friend class SkillClient;
        Token() = default;
    };
    SkillClient(Token, ua::Client& client, ua::NodeId skill);

private:
    asio::awaitable<ua::StatusCode> resolve();
    asio::awaitable<ua::StatusCode> subscribe(SkillClientOptions options);
    void onEvent(const std::vector<ua::Variant>& fields);
    void onSubscriptionStatus(ua::StatusCode status);
    /// The end of the current run among the transitions received, if it came.
    [[nodiscard]] std::optional<SkillOutcome> endOfRun() const;
    /// Reads CurrentState and LastTransition; a run's end that no event brought becomes a
    /// transition record, as if its event had come. Bad when the server does not answer.
    asio::awaitable<ua::StatusCode> readBack();
    void record(SkillTransitionRecord r);
    asio::awaitable<SkillOutcome> haltAfter(SkillOutcome::Kind kind);
    /// call() without beginning a run (run() began it before the parameters).
    asio::awaitable<ua::StatusCode> callMethod(SkillMethod method);

    ua::Client& client_;
    ua::NodeId skill_;
    std::map<SkillMethod, ua::NodeId> methods_;
    ua::NodeId currentStateId_;
    ua::NodeId lastTransitionId_;    // LastTransition/Id (null: not offered, no read-back)
    ua::NodeId lastTransitionTime_;  // LastTransition/TransitionTime
    std::chrono::milliseconds confirmAfter_{1000};
    bool confirm_ = false;  // read back at the next chance (a gap, a late keep-alive)
    std::uint64_t eventsHeard_ = 0;
    std::vector<RemoteParameter> parameters_;
    std::shared_ptr<ua::Subscription> subscription_;
    std::optional<SkillState> state_;
    std::deque<SkillTransitionRecord> transitions_;
    std::function<void(const SkillTransitionRecord&)> transitionListener_;
    std::optional<ua::DateTime> runStartedAt_;  // the Start response's timestamp
    ua::StatusCode lost_ = ua::status::Good;
    bool cancelled_ = false;
    asio::steady_timer wakeUp_;
};

}  // namespace skillcell::skills
