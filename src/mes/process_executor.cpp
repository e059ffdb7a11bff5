#include "mes/process_executor.hpp"

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/experimental/awaitable_operators.hpp>
#include <asio/post.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include <algorithm>
#include <limits>
#include <set>

#include "devices/common/blocking_call.hpp"
#include "mes/feasibility.hpp"
#include "skills/reservation_client.hpp"
#include "skills/skill_connection.hpp"
#include "ua/types/connection_loss.hpp"

namespace skillcell::mes {
namespace {

using asio::experimental::awaitable_operators::operator&&;  // two requests, one round trip
using skills::SkillOutcome;
using skills::SkillState;

// How many skill instances one step tries before it gives up: a bound on a cell whose
// components keep failing in turn.
constexpr int kMaxInstancesPerStep = 8;
// How often to ask the KB again while the skills are there but their facts are not.
constexpr std::chrono::milliseconds kFactRetry{250};
using Clock = std::chrono::steady_clock;

// Adds `part` to a journal note, whose parts are joined by "; ".
void appendNote(std::string& note, std::string_view part) {
    if (!note.empty()) note += "; ";
    note += part;
}

// "waited N ms for WHAT ON" added to a journal note, when the wait took a millisecond or more.
void appendWait(std::string& note, Clock::duration time, std::string_view what,
                std::string_view on) {
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(time).count();
    if (ms <= 0) return;
    appendNote(note, "waited " + std::to_string(ms) + " ms for " + std::string(what) + " " +
                         std::string(on));
}

// How many of the components that other orders hold a choice's reason names (the rest it
// counts).
constexpr std::size_t kNamedHolders = 5;

// Why a step cannot use a skill whose LastTransition it could not read.
std::string unreadable(ua::StatusCode s) {
    return "cannot read its LastTransition: " + std::string(ua::statusName(s));
}

// How long, in all, the knowledge base may be out of reach without using up a step's or an
// order's skill wait: a KB cut off by a link down answers nothing for its whole request
// timeout, and a KB restarting (its Virtuoso, then its recordings) refuses for seconds; once it
// answers again, the step asks again. Bounded, so that a KB that stays away ends the wait.
constexpr Clock::duration kMaxKbOutage = std::chrono::seconds(60);

/// The time the knowledge base could not be asked, not counted against a wait.
class KbOutage {
public:
    /// A request begun at `asked` failed: the time from the start of this outage (the first
    /// failure in a row, or the last time counted) to now moves `deadline` on, within
    /// kMaxKbOutage in all.
    void failed(Clock::time_point& deadline, Clock::time_point asked) {
        const auto now = Clock::now();
        const auto from = since_.value_or(asked);
        const auto add = std::min(now - from, kMaxKbOutage - forgiven_);
        if (add > Clock::duration::zero()) {
            deadline += add;
            forgiven_ += add;
        }
        since_ = now;
    }
    /// It answered: the outage, if any, is over.
    void answered() { since_.reset(); }

private:
    std::optional<Clock::time_point> since_;
    Clock::duration forgiven_{};
};

/// Whether the KB has not recorded yet some live skill of one of `types`: while it
/// records them, after a component plugged in or after its own restart, its time is not
/// counted against a wait either (KbOutage), as its time out of reach is not.
bool kbBehind(const SkillFacts& facts, const std::vector<skills::SkillInstance>& live,
              const std::set<std::string>& types) {
    return std::any_of(live.begin(), live.end(), [&](const skills::SkillInstance& s) {
        return !facts.recorded(keyOf(s)) &&
               std::any_of(types.begin(), types.end(),
                           [&](const std::string& t) { return isOfType(s, t); });
    });
}

/// The skill types a step may use: its own and those its requirements name.
std::set<std::string> typesOf(const ProcessStep& step) {
    std::set<std::string> types{step.skillTypeIri};
    for (const auto& r : step.requirements) {
        if (!r.skillTypeIri.empty()) types.insert(r.skillTypeIri);
    }
    return types;
}

std::set<std::string> typesOf(const ProcessDescription& process) {
    std::set<std::string> types;
    for (const auto& step : process.steps) types.merge(typesOf(step));
    return types;
}

// The median of some durations (ms).
std::int64_t median(std::vector<std::int64_t> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// How many finished runs of a skill type on a component the MES learns its duration from.
constexpr std::size_t kDurationHistory = 20;

// Orders `skills` (suitable and free) by their expected duration, shortest first: the median of
// their component's last finished runs in `durations` (none: the journal could not be read);
// those without a history after, in the order given (URI order). Returns why the first was
// chosen, over the others.
std::string rankByExpectedDuration(std::vector<skills::SkillInstance>& skills,
                                   const ProcessExecutor::Durations* durations) {
    std::map<std::string, std::int64_t> expected;
    if (durations != nullptr) {
        for (const auto& [component, ms] : *durations) {
            if (!ms.empty()) expected[component] = median(ms);
        }
    }
    auto rank = [&](const skills::SkillInstance& s) {
        const auto it = expected.find(s.componentUri);
        return it != expected.end() ? it->second : std::numeric_limits<std::int64_t>::max();
    };
    std::stable_sort(skills.begin(), skills.end(),
                     [&](const auto& x, const auto& y) { return rank(x) < rank(y); });
    auto describeCandidate = [&](const skills::SkillInstance& s) {
        const auto it = expected.find(s.componentUri);
        if (it == expected.end()) return s.componentUri + " (no finished run yet)";
        return s.componentUri + " (expected " + std::to_string(it->second) +
               " ms, the median of its last " +
               std::to_string(durations->at(s.componentUri).size()) + ")";
    };
    std::string why = describeCandidate(skills.front());
    std::string others;
    for (std::size_t i = 1; i < skills.size(); ++i) {
        others += (others.empty() ? "" : ", ") + describeCandidate(skills[i]);
    }
    if (!others.empty()) why += " over " + others;
    return why;
}

std::string describe(const SkillOutcome& o) {
    std::string text(skills::name(o.kind));
    if (o.status.isBad()) text += " (" + std::string(ua::statusName(o.status)) + ")";
    if (!o.reason.empty()) text += ": " + o.reason;
    return text;
}

}  // namespace

std::string Progress::line() const {
    std::string out = "step " + std::to_string(step) + "/" + std::to_string(steps);
    if (!skillType.empty()) out += " " + skillType;
    out += " " + state;
    if (!skill.empty()) out += " " + skill + " @ " + component;
    if (!message.empty()) out += " - " + message;
    return out;
}

/// One order running in this MES: what halting it must reach, and who waits for its end.
struct ProcessExecutor::Order {
    std::int64_t id = 0;
    std::string processIri;
    int priority = 0;
    bool halted = false;     // stop() was called: no new step begins
    bool cancelled = false;  // ... by a user's cancel: the order ends Cancelled
    /// The skills its steps run now, and a skill a resumed step waits for: halted on stop().
    std::set<std::shared_ptr<skills::SkillClient>> running;
    /// Its waits (for a skill, a component, a confirmation): ended on stop().
    std::vector<std::weak_ptr<asio::steady_timer>> waits;
    /// The components its running steps use: its other steps use others.
    std::multiset<std::string> busy;
    /// How long its steps wait for a suitable skill: the process's, else the MES's.
    std::chrono::milliseconds skillWait{0};
    Progress progress;  // the latest
    std::optional<ProcessOutcome> outcome;
    /// Never expires: cancelled at the end, for outcome()'s waits.
    std::shared_ptr<asio::steady_timer> ended;

    [[nodiscard]] OrderRank rank() const { return {id, priority}; }
    void halt() {
        halted = true;
        for (const auto& skill : running) skill->cancel();  // its run() halts it
        for (const auto& w : waits) {
            if (auto timer = w.lock()) timer->cancel();
        }
    }
};

std::shared_ptr<ProcessExecutor> ProcessExecutor::create(
    std::shared_ptr<skills::SkillDetector> detector, Journal& journal, KnowledgeReaders kb,
    ExecutorOptions options) {
    return std::make_shared<ProcessExecutor>(Token{}, std::move(detector), journal, std::move(kb),
                                             std::move(options));
}

ProcessExecutor::ProcessExecutor(Token, std::shared_ptr<skills::SkillDetector> detector,
                                 Journal& journal, KnowledgeReaders kb, ExecutorOptions options)
    : detector_(std::move(detector)),
      journal_(journal),
      kb_(std::move(kb)),
      options_(std::move(options)),
      connections_(std::make_shared<SkillConnectionPool>(
          detector_->executor(), options_.client, options_.skillClient, options_.keepConnections)),
      journalThread_(std::make_unique<asio::thread_pool>(1)) {}

ProcessExecutor::~ProcessExecutor() {
    if (departuresWatch_) {
        asio::post(detector_->executor(),
                   [detector = detector_, id = *departuresWatch_] { detector->unsubscribe(id); });
    }
    // The kept sessions are closed on the executor, where they live (this may run elsewhere).
    asio::co_spawn(
        detector_->executor(),
        [pool = std::move(connections_)]() -> asio::awaitable<void> { co_await pool->closeAll(); },
        asio::detached);
}

void ProcessExecutor::report(Order& order, Progress p) {
    order.progress = std::move(p);
    if (onProgress) onProgress(order.progress);
}

template <class Write>
asio::awaitable<std::invoke_result_t<Write&>> ProcessExecutor::journaled(Write write) {
    auto self = shared_from_this();
    co_return co_await devices::blockingCall(*journalThread_, std::move(write));
}

asio::awaitable<kb::Status> ProcessExecutor::record(std::int64_t run, StepRecord step) {
    auto self = shared_from_this();
    auto pending = std::make_shared<PendingRecord>(
        run, std::move(step), asio::steady_timer(detector_->executor(), Clock::time_point::max()));
    unrecorded_.push_back(pending);
    if (!recording_) {
        recording_ = true;
        asio::co_spawn(detector_->executor(), writeRecords(), asio::detached);
    }
    if (!pending->done) {
        (void)co_await pending->written.async_wait(
            asio::experimental::as_tuple(asio::use_awaitable));
    }
    if (!pending->result) spdlog::error("mes: {}", pending->result.error());
    co_return pending->result;
}

asio::awaitable<void> ProcessExecutor::writeRecords() {
    auto self = shared_from_this();
    // Group commit: what the orders asked to record while the last transaction was on its
    // way to the disk goes in the next one, with one fsync for all of it.
    while (!unrecorded_.empty()) {
        auto batch = std::move(unrecorded_);
        unrecorded_.clear();
        std::vector<std::pair<std::int64_t, StepRecord>> rows;
        rows.reserve(batch.size());
        for (const auto& p : batch) rows.emplace_back(p->run, p->step);
        auto all = [this, &rows] { return journal_.recordSteps(rows); };
        const kb::Status written = co_await journaled(all);
        for (auto& p : batch) {
            if (written || batch.size() == 1) {
                p->result = written;
            } else {
                // Each on its own: one bad record must not fail the others.
                auto one = [this, &p] { return journal_.recordStep(p->run, p->step); };
                p->result = co_await journaled(one);
            }
        }
        for (auto& p : batch) {
            p->done = true;
            p->written.cancel();
        }
    }
    recording_ = false;
}

asio::awaitable<void> ProcessExecutor::sleep(Order& order,
                                             std::shared_ptr<asio::steady_timer> timer) {
    auto self = shared_from_this();
    std::erase_if(order.waits, [](const auto& w) { return w.expired(); });
    order.waits.push_back(timer);
    co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
}

void ProcessExecutor::componentsFreed() {
    for (const auto& w : claimWaits_) {
        if (auto timer = w.lock()) timer->cancel();
    }
    claimWaits_.clear();
}

// --- Orders ---------------------------------------------------------------------------

void ProcessExecutor::watchDepartures() {
    if (departuresWatch_) return;
    std::weak_ptr<ProcessExecutor> weak = shared_from_this();
    departuresWatch_ = detector_->subscribe([weak](const skills::SkillEvent& e) {
        auto self = weak.lock();
        if (!self || e.kind != skills::SkillEvent::Kind::Removed) return;
        auto& d = self->departures_;
        const auto same = [&e](const Departure& x) {
            return keyOf(x.instance) == keyOf(e.instance);
        };
        d.erase(std::remove_if(d.begin(), d.end(), same), d.end());
        if (d.size() == kDepartures) d.erase(d.begin());
        d.push_back({e.instance, e.reason, Clock::now()});
    });
}

kb::Expected<Submitted> ProcessExecutor::submit(const std::string& processIri, int priority) {
    if (processIri.empty()) return kb::badInput("which process? The process IRI is empty");
    watchDepartures();
    if (standingBy_) {
        return kb::Error{"standing by: another MES runs this journal's orders",
                         kb::ErrorKind::Unavailable};
    }
    // A Stopped order of the process is resumed: what it did stays done.
    auto unfinished = journal_.unfinishedRun(processIri);
    if (!unfinished) return unfinished.failure();
    if (*unfinished && (*unfinished)->state == RunState::Stopped &&
        !orders_.contains((*unfinished)->id)) {
        const RunRecord& stopped = **unfinished;
        if (auto s = journal_.setRunState(stopped.id, RunState::Queued, {}); !s) {
            return s.failure();
        }
        spdlog::info("mes: order {} of {} resumed (it had stopped: {})", stopped.id, processIri,
                     stopped.reason);
        begin(stopped.id, processIri, stopped.priority);
        return Submitted{stopped.id, true};
    }
    auto id = journal_.submitOrder(processIri, priority);
    if (!id) return id.failure();
    spdlog::info("mes: order {} of {} (priority {})", *id, processIri, priority);
    begin(*id, processIri, priority);
    return Submitted{*id, false};
}

kb::Expected<std::size_t> ProcessExecutor::resumeOpenOrders() {
    watchDepartures();
    auto open = journal_.openOrders();
    if (!open) return open.failure();
    standingBy_ = false;
    // Each order takes back, before any of them runs, the components its steps used in the
    // MES's earlier life (each step's own, and those it acted through): it holds them to its
    // end, and another order taking one meanwhile
    // (its first step, on the tool changer the first still needs) would deadlock both.
    for (const auto& r : *open) {
        if (orders_.contains(r.id)) continue;
        auto done = journal_.run(r.id);
        if (!done) return done.failure();
        if (!*done) continue;
        for (const auto& step : (*done)->steps) {
            if (!step.componentUri.empty()) (void)claims_.take(r.id, step.componentUri);
            for (const auto& held : step.held) (void)claims_.take(r.id, held);
        }
    }
    std::size_t begun = 0;
    for (const auto& r : *open) {
        if (orders_.contains(r.id)) continue;
        spdlog::info("mes: order {} of {} was {} when the MES stopped: resuming it", r.id,
                     r.processIri, toString(r.state));
        begin(r.id, r.processIri, r.priority);
        ++begun;
    }
    return begun;
}

void ProcessExecutor::begin(std::int64_t id, std::string processIri, int priority) {
    auto order = std::make_shared<Order>();
    order->id = id;
    order->processIri = std::move(processIri);
    order->priority = priority;
    order->ended = std::make_shared<asio::steady_timer>(detector_->executor(),
                                                        asio::steady_timer::time_point::max());
    order->progress.run = id;
    order->progress.processIri = order->processIri;
    order->progress.state = "queued";
    order->skillWait = options_.skillWait;
    orders_[id] = order;
    asio::co_spawn(
        detector_->executor(),
        [self = shared_from_this(), order]() -> asio::awaitable<void> {
            auto outcome = co_await self->runOrder(order);
            self->finish(*order, std::move(outcome));
        },
        asio::detached);
}

void ProcessExecutor::finish(Order& order, ProcessOutcome outcome) {
    order.outcome = std::move(outcome);
    claims_.release(order.id);
    orders_.erase(order.id);
    componentsFreed();
    order.ended->cancel();
}

asio::awaitable<ProcessOutcome> ProcessExecutor::outcome(std::int64_t id) {
    auto self = shared_from_this();
    if (auto it = orders_.find(id); it != orders_.end()) {
        auto order = it->second;
        co_await order->ended->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        if (order->outcome) co_return *order->outcome;
    }
    ProcessOutcome out;
    out.run = id;
    auto read = [this, id] { return journal_.run(id); };
    auto r = co_await journaled(read);
    if (!r) {
        out.reason = r.error();
    } else if (!*r) {
        out.reason = "no order " + std::to_string(id);
    } else {
        out.completed = (*r)->state == RunState::Completed;
        out.cancelled = (*r)->state == RunState::Cancelled;
        out.reason = (*r)->reason;
        if (!out.completed && out.reason.empty()) {
            out.reason = std::string("the order is ") + toString((*r)->state);
        }
    }
    co_return out;
}

asio::awaitable<ProcessOutcome> ProcessExecutor::execute(std::string processIri, int priority) {
    auto self = shared_from_this();
    auto submitted = submit(processIri, priority);
    if (!submitted) co_return ProcessOutcome{false, 0, submitted.error(), false};
    co_return co_await outcome(submitted->order);
}

kb::Status ProcessExecutor::stop(std::int64_t id, bool cancel) {
    if (auto it = orders_.find(id); it != orders_.end()) {
        Order& order = *it->second;
        order.cancelled = order.cancelled || cancel;
        spdlog::info("mes: order {} {}", id, cancel ? "cancelled" : "halted");
        order.halt();
        return kb::Done{};
    }
    auto r = journal_.run(id);
    if (!r) return r.failure();
    if (!*r) return kb::badInput("no order " + std::to_string(id));
    const RunState state = (*r)->state;
    if (state == RunState::Completed || state == RunState::Cancelled) {
        return kb::badInput("order " + std::to_string(id) + " has ended already (" +
                            toString(state) + ")");
    }
    if (!cancel) {
        return kb::badInput("order " + std::to_string(id) + " is not running (" + toString(state) +
                            ")");
    }
    // Queued or Stopped here (or Running in a journal no MES runs now): never resumed.
    spdlog::info("mes: order {} cancelled (it was {})", id, toString(state));
    return journal_.setRunState(id, RunState::Cancelled, "cancelled");
}

void ProcessExecutor::haltAll() {
    for (const auto& [id, order] : orders_) order->halt();
}

void ProcessExecutor::suspend(std::int64_t id) {
    forward(id, skills::SkillMethod::Suspend);
}

void ProcessExecutor::resume(std::int64_t id) {
    forward(id, skills::SkillMethod::Resume);
}

void ProcessExecutor::forward(std::int64_t id, skills::SkillMethod method) {
    const auto it = orders_.find(id);
    if (it == orders_.end()) return;
    for (const auto& skill : it->second->running) {
        asio::co_spawn(
            detector_->executor(),
            [skill, method]() -> asio::awaitable<void> { (void)co_await skill->call(method); },
            asio::detached);
    }
}

std::vector<Progress> ProcessExecutor::running() const {
    std::vector<Progress> out;
    out.reserve(orders_.size());
    for (const auto& [id, order] : orders_) out.push_back(order->progress);
    return out;
}

// --- One order ------------------------------------------------------------------------

asio::awaitable<ProcessOutcome> ProcessExecutor::runOrder(std::shared_ptr<Order> order) {
    auto self = shared_from_this();
    ProcessOutcome out;
    out.run = order->id;
    Progress p = order->progress;
    const std::string& processIri = order->processIri;
    std::string stopReason;
    bool refused = false;  // before any motion: the cell cannot run the process
    std::optional<ProcessDescription> description;
    p.state = "reading";
    p.message = "asking the knowledge base for the process";
    report(*order, p);
    if (auto read = co_await kb_.process(processIri); !read) {
        stopReason = "cannot read the process " + processIri + ": " + read.error();
    } else {
        description = std::move(*read);
        p.steps = static_cast<int>(description->steps.size());
        if (description->skillWait) order->skillWait = *description->skillWait;
    }
    // Before the first motion: can the cell run it at all? Every reason at once.
    if (stopReason.empty() && !order->halted) {
        if (auto lacking = co_await feasible(order, *description, p); !lacking.empty()) {
            stopReason = "the cell cannot run " + processIri + ": ";
            for (std::size_t i = 0; i < lacking.size(); ++i) {
                stopReason += (i == 0 ? "" : "; ") + lacking[i];
            }
            spdlog::warn("mes: order {} refused: {}", order->id, stopReason);
            refused = true;
        }
    }
    // What the journal holds of this order: steps done in an earlier life of the MES.
    RunRecord previous;
    if (stopReason.empty() && !order->halted) {
        auto read = [this, id = order->id] { return journal_.run(id); };
        auto found = co_await journaled(read);
        if (!found) {
            stopReason = found.error();
        } else if (*found) {
            previous = std::move(**found);
        }
        const auto& steps = description->steps;
        for (const auto& r : previous.steps) {
            const bool same = r.index >= 1 && r.index <= p.steps &&
                              steps[static_cast<std::size_t>(r.index - 1)].iri == r.stepIri;
            if (!same && stopReason.empty()) {
                stopReason = "order " + std::to_string(order->id) + " of " + processIri +
                             " cannot be resumed: the process changed since (step " +
                             std::to_string(r.index) + " was <" + r.stepIri + ">)";
            }
        }
    }
    if (stopReason.empty() && !order->halted) {
        auto running = [this, id = order->id] {
            return journal_.setRunState(id, RunState::Running, {});
        };
        if (auto s = co_await journaled(running); !s) stopReason = s.error();
    }
    if (stopReason.empty() && !order->halted) {
        spdlog::info("mes: order {} of {}: {} steps{}", order->id, processIri, p.steps,
                     previous.steps.empty() ? "" : " (resumed)");
        stopReason = co_await runSteps(order, *description, previous);
    }
    if (stopReason.empty() && order->halted) stopReason = "halted before its first step";
    if (order->cancelled) stopReason = "cancelled (" + stopReason + ")";

    p = order->progress;
    if (stopReason.empty()) {
        auto completed = [this, id = order->id] {
            return journal_.setRunState(id, RunState::Completed, {});
        };
        if (auto s = co_await journaled(completed); !s) {
            out.reason = s.error();
            co_return out;
        }
        out.completed = true;
        p.state = "completed";
        p.message = "every step finished";
        report(*order, p);
        spdlog::info("mes: order {} of {} completed", order->id, processIri);
        co_return out;
    }
    out.reason = std::move(stopReason);
    out.cancelled = order->cancelled;
    const RunState end = order->cancelled ? RunState::Cancelled : RunState::Stopped;
    auto stopped = [this, id = order->id, end, reason = out.reason] {
        return journal_.setRunState(id, end, reason);
    };
    if (auto s = co_await journaled(stopped); !s) {
        out.reason += " (and the journal failed: " + s.error() + ")";
    }
    spdlog::warn("mes: order {} {}: {}", order->id, toString(end), out.reason);
    p.state = refused && !order->cancelled ? "refused" : toString(end);
    p.message = out.reason;
    report(*order, p);
    co_return out;
}

asio::awaitable<std::string> ProcessExecutor::runSteps(std::shared_ptr<Order> order,
                                                       const ProcessDescription& process,
                                                       const RunRecord& previous) {
    auto self = shared_from_this();
    const auto& steps = process.steps;
    const std::size_t n = steps.size();
    // Each step's prerequisites: the steps it names with proc:dependsOn, in a DAG; else the
    // step before it.
    const bool dag = std::any_of(steps.begin(), steps.end(),
                                 [](const ProcessStep& s) { return !s.dependsOn.empty(); });
    std::vector<std::vector<std::size_t>> prerequisites(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!dag) {
            if (i > 0) prerequisites[i].push_back(i - 1);
            continue;
        }
        for (const auto& d : steps[i].dependsOn) {
            const auto it = std::find_if(steps.begin(), steps.end(),
                                         [&](const ProcessStep& s) { return s.iri == d; });
            if (it == steps.end())
                co_return steps[i].label() + ": depends on <" + d +
                    ">, which is not a step of the process";
            prerequisites[i].push_back(static_cast<std::size_t>(it - steps.begin()));
        }
    }
    enum class State : std::uint8_t { Pending, Running, Done, Failed };
    // Shared with the steps' completions.
    struct Board {
        std::vector<State> state;
        std::vector<int> attempt;
        int running = 0;
        std::string stopReason;
        std::shared_ptr<asio::steady_timer> wake;
    };
    auto board = std::make_shared<Board>();
    board->state.assign(n, State::Pending);
    board->attempt.assign(n, 1);
    board->wake = std::make_shared<asio::steady_timer>(detector_->executor(),
                                                       asio::steady_timer::time_point::max());
    Progress p = order->progress;
    // What the journal shows: finished steps stay done; a step interrupted by the MES's end
    // is settled by asking its skill.
    for (std::size_t i = 0; i < n && board->stopReason.empty(); ++i) {
        const ProcessStep& step = steps[i];
        const StepRecord* last = previous.lastAttempt(step.index);
        if (last == nullptr) continue;
        board->attempt[i] = last->attempt + 1;
        p.step = step.index;
        p.skillType = shortName(step.skillTypeIri);
        p.component = last->componentUri;
        p.skill.clear();
        if (last->state == StepState::Finished) {
            board->state[i] = State::Done;
            p.state = "done";
            p.message = "finished in an earlier attempt";
            report(*order, p);
            continue;
        }
        if (last->state != StepState::Starting && last->state != StepState::Running) continue;
        p.skill = last->skillNodeId;
        p.state = "checking";
        p.message = "the MES stopped during this step: asking the skill what became of it";
        report(*order, p);
        auto [settled, why] = co_await settle(order, *last);
        StepRecord r = *last;
        r.endedMs = unixMillis();
        r.state = settled == Settled::Finished ? StepState::Finished : StepState::Failed;
        r.reason = why;
        if (auto s = co_await record(order->id, r); !s) co_return s.error();
        spdlog::info("mes: order {}: {} (attempt {}, interrupted): {}", order->id, step.label(),
                     r.attempt, why);
        if (settled == Settled::Finished) {
            board->state[i] = State::Done;
            p.state = "finished";
            p.message = why;
            report(*order, p);
        } else if (settled == Settled::Failed) {
            board->stopReason = step.label() + ": " + why;
        }
    }
    // Start every step whose prerequisites are done; wait for one to end; again.
    for (;;) {
        if (board->stopReason.empty() && !order->halted) {
            for (std::size_t i = 0; i < n; ++i) {
                if (board->state[i] != State::Pending) continue;
                const bool ready =
                    std::all_of(prerequisites[i].begin(), prerequisites[i].end(),
                                [&](std::size_t d) { return board->state[d] == State::Done; });
                if (!ready) continue;
                board->state[i] = State::Running;
                ++board->running;
                Progress sp = order->progress;
                sp.step = steps[i].index;
                sp.steps = static_cast<int>(n);
                sp.skillType = shortName(steps[i].skillTypeIri);
                asio::co_spawn(detector_->executor(),
                               runStep(order, steps[i], board->attempt[i], std::move(sp)),
                               [board, i](const std::exception_ptr& e, StepResult r) {
                                   if (e) r = StepResult{false, "the step failed inside the MES"};
                                   board->state[i] = r.ok ? State::Done : State::Failed;
                                   if (!r.ok && board->stopReason.empty())
                                       board->stopReason = r.reason;
                                   --board->running;
                                   board->wake->cancel();
                               });
            }
        }
        if (board->running == 0) break;
        co_await board->wake->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    }
    if (!board->stopReason.empty()) co_return board->stopReason;
    for (std::size_t i = 0; i < n; ++i) {
        if (board->state[i] != State::Done) co_return "halted before " + steps[i].label();
    }
    co_return std::string();
}

asio::awaitable<std::pair<ProcessExecutor::Settled, std::string>> ProcessExecutor::settle(
    std::shared_ptr<Order> order, const StepRecord& r) {
    auto self = shared_from_this();
    skills::SkillInstance target;
    target.componentUri = r.componentUri;
    target.endpointUrl = r.endpointUrl;
    target.nodeId = ua::NodeId::parse(r.skillNodeId).value_or(ua::NodeId());
    // Where the detector sees the component now (it may have moved).
    for (const auto& s : detector_->instances()) {
        if (s.componentUri == r.componentUri && s.nodeId.toString() == r.skillNodeId) target = s;
    }
    // The step's component is the order's, as it was before the MES stopped.
    claims_.take(order->id, r.componentUri);
    Claim held = co_await claim(target, *order);
    if (held.failure != Claim::Failure::None) {
        co_return std::pair(Settled::Failed, "cannot tell whether the skill " + r.skillNodeId +
                                                 " of " + r.componentUri + " ran: " + held.why);
    }
    auto& skill = held.connection->skill();
    const ua::DateTime time = held.before;
    std::pair<Settled, std::string> result{Settled::Failed, {}};
    const auto state = skill.state();
    if (time.ticks == r.transitionTimeBefore && state == SkillState::Ready) {
        result = {Settled::NotStarted, "Start never reached the skill: the MES stopped first"};
    } else if (state == SkillState::Running || state == SkillState::Suspended) {
        // Still running the Start this step gave: wait for its end as if we had stayed.
        spdlog::info("mes: {} of {} is still running the interrupted step: waiting for it",
                     r.skillNodeId, r.componentUri);
        skill.adoptRun(ua::DateTime{r.transitionTimeBefore + 1});
        auto adopted = skill.shared_from_this();
        order->running.insert(adopted);
        if (order->halted) adopted->cancel();
        const SkillOutcome o = co_await skill.waitForEnd(options_.stepTimeout);
        order->running.erase(adopted);
        result = o.ok() ? std::pair(Settled::Finished, std::string("finished (after a restart of "
                                                                   "the MES)"))
                        : std::pair(Settled::Failed, describe(o));
    } else if (state == SkillState::Ready) {
        result = {Settled::Finished, "finished while the MES was not running"};
    } else {
        result.second = "the skill is " +
                        std::string(state ? skills::name(*state) : std::string_view("unknown")) +
                        ": it failed while the MES was not running";
    }
    co_await hangUp(target, std::move(held.connection), held.token);
    if (order->halted && result.first != Settled::Finished) {
        result = {Settled::Failed, "halted"};
    }
    co_return result;
}

asio::awaitable<ProcessExecutor::Choice> ProcessExecutor::withRequirements(
    const ProcessStep& step, std::vector<skills::SkillInstance> typed,
    const std::vector<skills::SkillInstance>& live) {
    auto self = shared_from_this();
    Choice c;
    if (!kb_.facts && step.requirements.empty()) {
        c.skills = std::move(typed);  // positions, but no KB to tell any robot's reach
        co_return c;
    }
    if (!kb_.facts) {
        c.unmet = "it has requirements (" + step.requirements.front().describe() +
                  "), and this MES has no knowledge base to check them";
        co_return c;
    }
    auto properties = requiredProperties(step);
    auto facts = co_await kb_.facts(std::move(properties));
    if (!facts) {
        c.unmet =
            "cannot ask the knowledge base whether its requirements are met: " + facts.error();
        c.kbUnreachable = true;
        co_return c;
    }
    c.kbBehind = kbBehind(*facts, live, typesOf(step));
    auto cell = matchCellRequirements(step, live, *facts);
    c.unmet = std::move(cell.unmet);
    if (!c.unmet.empty()) co_return c;
    c.cellMatches = std::move(cell.byRequirement);
    c.chosen = std::move(cell.chosen);
    c.matchedRobot = cell.robot;
    std::string unfit;
    for (auto& s : typed) {
        const std::string why = unmetSkillRequirements(step, s, *facts, cell.robot);
        if (why.empty()) {
            if (auto robot = robotOf(s, *facts); !robot.empty() && robot != s.componentUri) {
                c.robots.emplace(keyOf(s), std::move(robot));
            }
            c.skills.push_back(std::move(s));
        } else {
            unfit += (unfit.empty() ? "" : "; ") + where(s) + ": " + why;
        }
    }
    if (c.skills.empty()) {
        c.unmet = "no skill of its type meets its requirements: " + unfit;
    } else if (!unfit.empty()) {
        c.chosen += (c.chosen.empty() ? "" : "; ") + std::string("passed over: ") + unfit;
    }
    co_return c;
}

asio::awaitable<std::vector<std::string>> ProcessExecutor::feasible(
    std::shared_ptr<Order> order, const ProcessDescription& process, Progress p) {
    auto self = shared_from_this();
    auto deadline = Clock::now() + order->skillWait;
    KbOutage kbOutage;
    const auto properties = requiredProperties(process);
    std::string shown;
    for (;;) {
        std::optional<SkillFacts> facts;
        std::string kbError;
        if (kb_.facts && !properties.empty()) {
            const auto asked = Clock::now();
            auto read = co_await kb_.facts(properties);
            if (read) {
                facts = std::move(*read);
                if (kbBehind(*facts, *detector_->snapshot(), typesOf(process))) {
                    kbOutage.failed(deadline, asked);  // still recording the live cell
                } else {
                    kbOutage.answered();
                }
            } else {
                kbError = "cannot ask the knowledge base: " + read.error();
                kbOutage.failed(deadline, asked);
            }
        }
        auto lacking = kbError.empty() ? infeasibility(process, *detector_->snapshot(),
                                                       facts ? &*facts : nullptr)
                                       : std::vector<std::string>{kbError};
        if (!lacking.empty() && kbError.empty() && !order->halted && Clock::now() >= deadline) {
            for (const auto& step : process.steps) {
                if (const auto gone = departed(step); !gone.empty()) {
                    lacking.push_back(step.label() + " was offered by " + gone);
                }
            }
        }
        if (lacking.empty() || order->halted || Clock::now() >= deadline) co_return lacking;
        p.state = "checking";
        p.message = "waiting up to " + std::to_string(order->skillWait.count()) +
                    " ms for what the process needs: " + lacking.front();
        if (p.message != shown) {
            shown = p.message;
            report(*order, p);
        }
        const auto wake = std::min(deadline, Clock::now() + kFactRetry);
        auto timer = std::make_shared<asio::steady_timer>(detector_->executor(), wake);
        const std::size_t id = detector_->subscribe([timer](const skills::SkillEvent& e) {
            if (e.kind == skills::SkillEvent::Kind::Added) timer->cancel();
        });
        co_await sleep(*order, timer);
        detector_->unsubscribe(id);
        if (order->halted) co_return std::vector<std::string>{"halted"};
    }
}

std::set<std::string> ProcessExecutor::componentsOf(
    const skills::SkillInstance* skill,
    const std::vector<std::optional<skills::SkillInstance>>& cellMatches,
    const std::map<SkillKey, std::string>& robots, const std::string& matchedRobot) {
    std::set<std::string> out;
    if (!matchedRobot.empty()) out.insert(matchedRobot);
    if (skill != nullptr) {
        out.insert(skill->componentUri);
        if (const auto r = robots.find(keyOf(*skill)); r != robots.end()) out.insert(r->second);
    }
    for (const auto& m : cellMatches) {
        if (m) out.insert(m->componentUri);
    }
    return out;
}

std::set<std::string> ProcessExecutor::componentsOf(const Choice& c) {
    return componentsOf(c.skills.empty() ? nullptr : &c.skills.front(), c.cellMatches, c.robots,
                        c.matchedRobot);
}

bool ProcessExecutor::available(const Order& order, const std::set<std::string>& components) const {
    return std::all_of(components.begin(), components.end(), [&](const std::string& c) {
        return !order.busy.contains(c) && claims_.mayTake(order.rank(), c);
    });
}

asio::awaitable<ProcessExecutor::Choice> ProcessExecutor::choose(std::shared_ptr<Order> order,
                                                                 const ProcessStep& step,
                                                                 const std::set<TriedKey>& excluded,
                                                                 Progress p) {
    auto self = shared_from_this();
    // skillWait counts from the moment no suitable skill is there, not from the step's start:
    // a step that waited for another order's component may see that component leave (a link
    // down) long after it began, and then it still has the whole bound for it to come back.
    std::optional<Clock::time_point> deadline;
    KbOutage kbOutage;
    std::optional<Clock::time_point> claimDeadline;  // from the first wait for a component
    // Registered as waiting for components: no longer on any return, and the orders that
    // gave way to it look again.
    struct Waiting {
        ProcessExecutor& executor;
        std::int64_t order;
        bool registered = false;
        ~Waiting() {
            if (!registered) return;
            executor.claims_.stopWaiting(order);
            executor.componentsFreed();
        }
    } waiting{*this, order->id};
    std::string shown;
    Wait waitedForSkill;
    Wait waitedForHolders;
    for (;;) {
        // Shared, not copied: each step of every order looks through all of them.
        const auto live = detector_->snapshot();
        const auto typed = candidates(step, *live, excluded);
        Choice c;
        // The suitable instances: in `live` when the step takes any instance of its type, in
        // c.skills when the KB was asked. Only the free ones are copied, below.
        std::vector<const skills::SkillInstance*> suitable;
        bool askAgain = false;  // whether the KB may soon know what it does not know now
        // The KB is asked when the step has requirements or names positions (whose reach a
        // robot's facts tell); a step without either takes any instance of its type.
        if (typed.empty() || (step.requirements.empty() && stepTargets(step).empty())) {
            suitable = typed;
        } else {
            std::vector<skills::SkillInstance> copies;
            copies.reserve(typed.size());
            for (const auto* s : typed) copies.push_back(*s);
            const auto asked = Clock::now();
            c = co_await withRequirements(step, std::move(copies), *live);
            if (!c.kbUnreachable && !c.kbBehind) {
                kbOutage.answered();
            } else if (deadline) {
                kbOutage.failed(*deadline, asked);
            }
            askAgain = c.skills.empty() && static_cast<bool>(kb_.facts);
            for (const auto& s : c.skills) suitable.push_back(&s);
        }
        if (order->halted) co_return Choice{};
        if (!suitable.empty()) {
            deadline.reset();
            // What the journal knows of how long each candidate takes (read before the
            // availability below, which must not be separated from the take by a wait).
            const Durations* durations = co_await expectedDurations(step.skillTypeIri);
            if (order->halted) co_return Choice{};
            // Suitable: those the order may use now (no other order holds them, no other
            // of its steps uses them), else wait for one to be freed.
            // Without copying the choice per candidate: with many components and many orders
            // that copying was most of the MES's time (bench/mes_overhead).
            Choice free;
            std::set<std::string> wanted;
            // The first few held ones by name, the rest counted: with 50 components the whole
            // list was 2.7 kB in each of a step's two journal rows.
            std::string holders;
            std::size_t heldCount = 0;
            auto held = [&holders, &heldCount](const std::string& component,
                                               const std::string& by) {
                if (++heldCount > kNamedHolders) return;
                if (!holders.empty()) holders += ", ";
                holders.append(component).append(" (").append(by).append(")");
            };
            for (const auto* s : suitable) {
                const auto components = componentsOf(s, c.cellMatches, c.robots, c.matchedRobot);
                if (available(*order, components)) {
                    free.skills.push_back(*s);
                    continue;
                }
                for (const auto& component : components) {
                    wanted.insert(component);
                    if (order->busy.contains(component)) {
                        held(component, "another step of this order uses it");
                    } else if (const auto h = claims_.holder(component); h && *h != order->id) {
                        held(component, "order " + std::to_string(*h) + " holds it");
                    }
                }
            }
            if (heldCount > kNamedHolders) {
                holders += " and " + std::to_string(heldCount - kNamedHolders) + " more";
            }
            if (!free.skills.empty()) {
                free.cellMatches = std::move(c.cellMatches);
                free.robots = std::move(c.robots);
                free.matchedRobot = std::move(c.matchedRobot);
                free.why = rankByExpectedDuration(free.skills, durations);
                if (!c.chosen.empty()) free.why += "; " + c.chosen;
                if (!holders.empty()) free.why += "; not free: " + holders;
                free.forSkill = std::move(waitedForSkill);
                free.forHolders = std::move(waitedForHolders);
                co_return free;
            }
            if (auto chain = claims_.wait(order->rank(), wanted)) {
                Choice none;
                none.unmet = "waiting for a component would deadlock: " + *chain;
                co_return none;
            }
            waiting.registered = true;
            if (!claimDeadline) claimDeadline = Clock::now() + options_.claimWait;
            if (Clock::now() >= *claimDeadline) {
                Choice none;
                none.unmet = "waited " + std::to_string(options_.claimWait.count()) + " ms for " +
                             (holders.empty() ? "a better-ranked order" : holders);
                co_return none;
            }
            p.state = "waiting";
            p.component.clear();
            p.skill.clear();
            p.message = "waiting for " + (holders.empty() ? "orders of higher priority" : holders);
            if (p.message != shown) {
                shown = p.message;
                report(*order, p);
            }
            auto timer =
                std::make_shared<asio::steady_timer>(detector_->executor(), *claimDeadline);
            claimWaits_.push_back(timer);
            waitedForHolders.on = holders.empty() ? "orders of higher priority" : holders;
            const auto asleep = Clock::now();
            co_await sleep(*order, timer);
            waitedForHolders.time += Clock::now() - asleep;
            continue;
        }
        if (!deadline) deadline = Clock::now() + order->skillWait;
        if (Clock::now() >= *deadline) co_return c;
        p.state = "waiting";
        p.component.clear();
        p.skill.clear();
        waitedForSkill.on = shortName(step.skillTypeIri) + (c.unmet.empty() ? "" : ": " + c.unmet);
        p.message = "waiting up to " + std::to_string(order->skillWait.count()) +
                    " ms for a suitable " + waitedForSkill.on;
        if (p.message != shown) {
            shown = p.message;
            report(*order, p);
        }
        const auto asleep = Clock::now();
        const auto wake = askAgain ? std::min(*deadline, Clock::now() + kFactRetry) : *deadline;
        auto timer = std::make_shared<asio::steady_timer>(detector_->executor(), wake);
        // A new instance of the step's type, or of a type a requirement names, may fit.
        const std::size_t id =
            detector_->subscribe([timer, step, excluded](const skills::SkillEvent& e) {
                if (e.kind != skills::SkillEvent::Kind::Added) return;
                const bool wanted = (!excluded.contains(triedKeyOf(e.instance)) &&
                                     unsuitability(step, e.instance).empty()) ||
                                    std::any_of(step.requirements.begin(), step.requirements.end(),
                                                [&](const FactRequirement& r) {
                                                    return !r.skillTypeIri.empty() &&
                                                           isOfType(e.instance, r.skillTypeIri);
                                                });
                if (wanted) timer->cancel();
            });
        co_await sleep(*order, timer);
        waitedForSkill.time += Clock::now() - asleep;
        detector_->unsubscribe(id);
        if (order->halted) co_return Choice{};
    }
}

asio::awaitable<const ProcessExecutor::Durations*> ProcessExecutor::expectedDurations(
    std::string skillTypeIri) {
    auto self = shared_from_this();
    if (!durations_.contains(skillTypeIri)) {
        // Read once per skill type from the journal (what earlier runs of this MES, or of
        // another on the same journal, learnt), then kept here as steps finish.
        auto read = [this, &skillTypeIri] {
            return journal_.finishedDurations(skillTypeIri, kDurationHistory);
        };
        auto fromJournal = co_await journaled(read);
        if (!fromJournal) {
            spdlog::warn("mes: {}", fromJournal.error());
            co_return nullptr;
        }
        durations_.try_emplace(skillTypeIri, std::move(*fromJournal));
    }
    // Not a copy: this runs for every step, and the map grows with the cell's components.
    co_return &durations_.at(skillTypeIri);
}

void ProcessExecutor::finishedIn(const std::string& skillTypeIri, const std::string& componentUri,
                                 const StepRecord& r) {
    const auto type = durations_.find(skillTypeIri);
    if (type == durations_.end() || r.endedMs <= r.startedMs) return;  // read when first needed
    auto& ms = type->second[componentUri];
    ms.insert(ms.begin(), r.endedMs - r.startedMs);  // newest first, as the journal gives them
    if (ms.size() > kDurationHistory) ms.resize(kDurationHistory);
}

asio::awaitable<ua::StatusCode> ProcessExecutor::letGo(skills::SkillConnection& connection,
                                                       std::optional<std::uint64_t> token) {
    auto self = shared_from_this();
    if (!token) co_return ua::status::Good;
    const ua::StatusCode s = co_await skills::release(connection.client(), *token);
    // Taken over meanwhile (a failover): the new holder's now.
    if (s.isBad()) spdlog::warn("mes: releasing the reservation: {}", ua::statusName(s));
    co_return s;
}

asio::awaitable<void> ProcessExecutor::hangUp(const skills::SkillInstance& skill,
                                              std::unique_ptr<skills::SkillConnection> connection,
                                              std::optional<std::uint64_t> token) {
    auto self = shared_from_this();
    (void)co_await letGo(*connection, token);
    co_await connections_->giveBack(skill, std::move(connection));
}

asio::awaitable<ProcessExecutor::Claim> ProcessExecutor::claim(const skills::SkillInstance& skill,
                                                               const Order& order) {
    auto self = shared_from_this();
    const std::string holder = options_.holder + " order " + std::to_string(order.id);
    skills::Hold held;
    ua::Result<ua::DateTime> time = ua::status::BadNothingToDo;
    // The pool runs this on a kept session, and again on a new one when the kept one did
    // not answer: the Reserve and the read are also what proves a kept session alive.
    auto first = [&held, &time, &holder](skills::SkillConnection& c) -> asio::awaitable<bool> {
        std::vector<ua::Client*> sessions{&c.client()};  // named: see reservation_client
        auto both = skills::hold(std::move(sessions), holder) && c.lastTransitionTime();
        std::tie(held, time) = co_await std::move(both);
        co_return time.ok() || !ua::isConnectionLoss(time.status());
    };
    Claim c;
    auto conn = co_await connections_->take(skill, &c.why, first);
    if (!conn) {
        c.failure = Claim::Failure::Unreachable;
        co_return c;
    }
    if (!held.refusal.empty()) {
        c.failure = Claim::Failure::Refused;
        c.why = held.refusal;
        co_await (*conn)->close();
        co_return c;
    }
    c.connection = std::move(*conn);
    c.token = held.token;
    if (!time) {
        c.failure = Claim::Failure::Unreadable;
        c.why = unreadable(time.status());
        co_await hangUp(skill, std::move(c.connection), c.token);
        co_return c;
    }
    c.before = *time;
    co_return c;
}

asio::awaitable<bool> ProcessExecutor::componentGone(std::shared_ptr<Order> order,
                                                     skills::SkillInstance skill) {
    auto self = shared_from_this();
    const std::string componentUri = skill.componentUri;
    const std::int64_t life = skill.componentStartTime.ticks;
    // Listed as it was: a restarted component (a new StartTime) is not its former life.
    auto listed = [this, &componentUri, life] {
        const auto all = detector_->instances();
        return std::any_of(all.begin(), all.end(), [&](const auto& s) {
            return s.componentUri == componentUri && s.componentStartTime.ticks == life;
        });
    };
    if (!listed()) co_return true;
    auto timer =
        std::make_shared<asio::steady_timer>(detector_->executor(), options_.goneConfirmation);
    const std::size_t id = detector_->subscribe([timer, componentUri](const skills::SkillEvent& e) {
        if (e.kind == skills::SkillEvent::Kind::Removed &&
            e.instance.componentUri == componentUri) {
            timer->cancel();
        }
    });
    co_await sleep(*order, timer);
    detector_->unsubscribe(id);
    co_return !listed();
}

std::string ProcessExecutor::noSkillReason(const ProcessStep& step,
                                           const std::set<TriedKey>& tried) const {
    const std::string type = shortName(step.skillTypeIri);
    std::string text = step.label() + ": no " + (tried.empty() ? "" : "other ") +
                       "available skill of type " + type + " can run it";
    // Instances of the type that do not fit say why.
    std::string unfit;
    for (const auto& s : detector_->instances()) {
        const std::string why = unsuitability(step, s);
        if (!why.empty() && why.rfind("it is not", 0) != 0) {
            unfit += (unfit.empty() ? "" : "; ") + where(s) + ": " + why;
        }
    }
    if (!unfit.empty()) text += " (unsuitable: " + unfit + ")";
    if (const auto gone = departed(step); !gone.empty()) {
        text += " (it was offered by " + gone + ")";
    }
    return text;
}

std::string ProcessExecutor::departed(const ProcessStep& step) const {
    // Who offered it and left: the component a stop names, so that an operator knows what to
    // bring back (a skill still listed is not a departure).
    const auto live = detector_->snapshot();
    std::string gone;
    const auto now = Clock::now();
    for (auto it = departures_.rbegin(); it != departures_.rend(); ++it) {
        const auto& s = it->instance;
        if (!unsuitability(step, s).empty() ||
            std::any_of(live->begin(), live->end(),
                        [&](const skills::SkillInstance& l) { return keyOf(l) == keyOf(s); })) {
            continue;
        }
        const auto ago = std::chrono::duration_cast<std::chrono::seconds>(now - it->at).count();
        gone += (gone.empty() ? "" : "; ") + where(s) + ", gone (" +
                std::string(skills::toString(it->reason)) + ") " + std::to_string(ago) + " s ago";
    }
    return gone;
}

asio::awaitable<ProcessExecutor::StepResult> ProcessExecutor::runStep(std::shared_ptr<Order> order,
                                                                      const ProcessStep& step,
                                                                      int attempt, Progress p) {
    auto self = shared_from_this();
    const std::int64_t run = order->id;
    std::set<TriedKey> tried;
    std::string lastFailure;
    std::string note;  // why the next attempt is made, and what was done first: journaled
    int retried = 0;
    for (int i = 0; i < kMaxInstancesPerStep + step.retries; ++i) {
        p.state = "choosing";
        p.component.clear();
        p.skill.clear();
        p.message.clear();
        report(*order, p);
        const Choice found = co_await choose(order, step, tried, p);
        if (order->halted) co_return StepResult{false, "halted in " + step.label()};
        if (found.skills.empty()) {
            std::string why;
            if (found.unmet.empty()) {
                why = noSkillReason(step, tried);
            } else {
                why = step.label() + ": " + found.unmet;
                why += " (waited " + std::to_string(order->skillWait.count()) + " ms)";
            }
            if (!lastFailure.empty()) why += "; " + lastFailure;
            co_return StepResult{false, why};
        }
        const skills::SkillInstance& skill = found.skills.front();
        auto values = parameterValues(step, skill, found.cellMatches);
        if (!values) co_return StepResult{false, values.error()};
        // The order holds what this step uses from now to its end; this step, until it ends.
        struct Busy {
            ProcessExecutor& executor;
            Order& order;
            std::set<std::string> components;
            ~Busy() {
                for (const auto& c : components) {
                    if (auto it = order.busy.find(c); it != order.busy.end()) order.busy.erase(it);
                }
                executor.componentsFreed();
            }
        } busy{*this, *order, componentsOf(found)};
        for (const auto& c : busy.components) {
            claims_.take(order->id, c);
            order->busy.insert(c);
        }
        p.component = skill.componentUri;
        p.skill = skill.browsePathString();
        // The component is this order's while the step runs: a second MES, or this one's
        // stale self after a failover, cannot drive it (docs/skills.md, "Reservation").
        Claim held = co_await claim(skill, *order);
        if (held.failure != Claim::Failure::None) {
            tried.insert(triedKeyOf(skill));
            lastFailure = where(skill) + ": " + held.why;
            if (held.failure != Claim::Failure::Unreadable) {
                p.state = held.failure == Claim::Failure::Unreachable ? "unreachable" : "reserved";
                p.message = held.why;
                report(*order, p);
            }
            continue;
        }
        skills::SkillClient& client = held.connection->skill();
        // A Halted skill runs again only after a Reset, which the journal records with the
        // attempt it precedes: a retry's, or that of a skill an earlier fault left Halted.
        if (client.state() == SkillState::Halted) {
            const ua::StatusCode reset = co_await client.call(skills::SkillMethod::Reset);
            // The Reset is a transition: what tells whether this attempt's Start reached the
            // skill is the LastTransition after it.
            ua::Result<ua::DateTime> after = ua::status::BadInvalidState;
            if (reset.isGood()) after = co_await held.connection->lastTransitionTime();
            if (reset.isBad() || !after) {
                tried.insert(triedKeyOf(skill));
                lastFailure =
                    where(skill) + (reset.isBad() ? ": Halted, and its Reset was refused (" +
                                                        std::string(ua::statusName(reset)) + ")"
                                                  : ": " + unreadable(after.status()));
                co_await hangUp(skill, std::move(held.connection), held.token);
                continue;
            }
            held.before = *after;
            const std::string what =
                retried > 0 ? "the skill was reset"
                            : "the skill was Halted (an earlier fault left it so) and was reset";
            appendNote(note, what);
            spdlog::warn("mes: {}: {}, before {} (attempt {})", where(skill), what, step.label(),
                         attempt);
        }
        StepRecord r;
        r.index = step.index;
        r.attempt = attempt;
        r.stepIri = step.iri;
        r.state = StepState::Starting;
        r.skillTypeIri = step.skillTypeIri;
        r.componentUri = skill.componentUri;
        r.endpointUrl = skill.endpointUrl;
        r.skillNodeId = skill.nodeId.toString();
        r.transitionTimeBefore = held.before.ticks;
        r.startedMs = unixMillis();
        r.note = note;
        // This attempt's own waits: a step that started late tells whether it waited for a
        // skill of its own (a gripper a tool change powers) or for others to end.
        appendWait(r.note, found.forSkill.time, "a suitable", found.forSkill.on);
        appendWait(r.note, found.forHolders.time, "components others held:", found.forHolders.on);
        r.choice = found.why;
        r.held.assign(busy.components.begin(), busy.components.end());
        // Halting the order halts this skill (SkillClient::cancel).
        auto running = client.shared_from_this();
        order->running.insert(running);
        // The Starting row must be on disk before Start, not before the parameters: writing
        // them leaves LastTransition as it was, so both go at once.
        auto prepared = record(run, r) && client.writeParameters(std::move(*values));
        auto [recordedStart, refused] = co_await std::move(prepared);
        if (!recordedStart) {
            order->running.erase(running);
            co_await hangUp(skill, std::move(held.connection), held.token);
            co_return StepResult{false, recordedStart.error()};
        }
        p.state = "running";
        p.message.clear();
        report(*order, p);
        spdlog::info("mes: order {}: {} on {} (attempt {})", run, step.label(), where(skill),
                     attempt);
        if (order->halted) running->cancel();  // before Start: it is not sent
        SkillOutcome outcome;
        if (refused) {
            outcome = std::move(*refused);
        } else {
            outcome = co_await client.startAndAwaitEnd(options_.stepTimeout);
        }
        order->running.erase(running);
        r.endedMs = unixMillis();
        r.state = outcome.ok() ? StepState::Finished : StepState::Failed;
        r.reason = outcome.ok() ? std::string() : describe(outcome);
        // The end's record and the Release go out together: a restarted MES settles a step
        // recorded as started from the skill's LastTransition, whoever holds it by then.
        auto both = record(run, r) && letGo(*held.connection, held.token);
        const auto [recorded, released] = co_await std::move(both);
        if (recorded && outcome.ok()) finishedIn(step.skillTypeIri, skill.componentUri, r);
        co_await connections_->giveBack(skill, std::move(held.connection));
        if (!recorded) co_return StepResult{false, recorded.error()};
        if (outcome.ok()) {
            p.state = "finished";
            report(*order, p);
            co_return StepResult{true, {}};
        }
        p.state = "failed";
        p.message = r.reason;
        report(*order, p);
        spdlog::warn("mes: {} on {}: {}", step.label(), where(skill), r.reason);
        if (order->halted) co_return StepResult{false, "halted in " + step.label()};
        // The skill ended Halted: the process's retry policy says whether it runs again.
        if (outcome.kind == SkillOutcome::Kind::Failed && retried < step.retries) {
            ++retried;
            ++attempt;
            note = "retry " + std::to_string(retried) + " of " + std::to_string(step.retries) +
                   " after: " + r.reason;
            spdlog::warn("mes: {}: {}", step.label(), note);
            p.state = "retrying";
            p.message = note;
            report(*order, p);
            continue;  // chosen again: the same instance, unless a better one appeared
        }
        // Lost contact: another instance may take the step only once the component is
        // gone; one still there may still be running the skill.
        if (outcome.kind == SkillOutcome::Kind::Lost && !co_await componentGone(order, skill)) {
            co_return StepResult{false, step.label() + ": lost contact with " + where(skill) +
                                            " mid-step (" + r.reason +
                                            "), but the component is still there: it may still "
                                            "be running the skill, so no other takes the step"};
        }
        const bool anotherMayDo =
            outcome.kind == SkillOutcome::Kind::Lost || outcome.kind == SkillOutcome::Kind::Refused;
        if (!anotherMayDo) {
            co_return StepResult{false,
                                 step.label() + " failed on " + where(skill) + ": " + r.reason};
        }
        tried.insert(triedKeyOf(skill));
        lastFailure = where(skill) + ": " + r.reason;
        // What the lost run did, the next one settles: it starts from the cell as it is
        // (a composite plans from what it perceives), on another instance or on the same
        // component's next life (docs/mes.md, "Settling").
        note = outcome.kind == SkillOutcome::Kind::Lost
                   ? "another instance, after " + lastFailure +
                         "; the run lost with its component is settled from the cell's state"
                   : "another instance, after " + lastFailure;
        ++attempt;
    }
    co_return StepResult{false, step.label() + ": gave up after " +
                                    std::to_string(kMaxInstancesPerStep) +
                                    " skill instances; last: " + lastFailure};
}

}  // namespace skillcell::mes
