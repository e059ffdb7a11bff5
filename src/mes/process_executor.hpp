#pragma once
// ProcessExecutor: runs orders, each a run of a process, on whatever skills the cell offers
// (paper, section VII-C). For each step it picks a suitable live skill instance
// (step_binding.hpp) from the SkillDetector's map, derives the parameter values, runs the
// skill with a SkillClient, and records intent and result in the Journal before going on.
//
// Orders. submit() records an order (Queued) and begins it at once; many run at the same
// time. An order takes each component it uses and holds it to its end (ResourceClaims), so
// two orders never interleave on one piece of hardware; an order whose step needs a
// component another holds waits for it, the better-ranked first (priority, then age), and is
// stopped with the chain when waiting would deadlock. A restarted MES resumes every order the
// journal shows Queued or Running (resumeOpenOrders()).
//
// Steps. When no step of a process names proc:dependsOn, its steps run in order. When any
// does, the process is a DAG: every step whose dependencies have finished starts at once, on
// a component no other running step of the order uses. A failed step stops the order once
// the steps running beside it have ended; none is halted mid-motion for it.
//
// A step's requirements (proc:requiresFact) are facts the KB must hold: of the skill chosen,
// or of some available skill of a given type (a gripper of the grip type a pick was planned
// for). Liveness comes from the detector, facts from the KB; the KB records a new component
// about a second after discovery, so while a step's skills are there but its facts are not,
// the MES asks the KB again, four times a second, up to skillWait.
//
// Faults stop the order in a defined state (RunState::Stopped, with the reason): a skill that
// ends Halted (after the step's proc:retries) or times out, a step no skill can run, a
// process the KB cannot describe. A skill that cannot be reached, refuses its parameters or
// Start, or whose component disappears mid-step is replaced by another suitable instance when
// there is one; a Halted one is not, since what it did to the cell is unknown.
//
// Resuming an order: finished steps are skipped, and a step the journal shows as being
// started is settled by asking its skill (unchanged LastTransition: Start never reached it,
// so it runs; Running: the run is waited for; Ready or Halted after a transition: it finished
// or failed while nobody watched).
//
// Threading: on the detector's executor (the server's thread: submit() and cancel() are
// called from its methods); journal writes of a run go to a thread of their own, each
// awaited before the run goes on (intent before Start, result before the next step).
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <asio/thread_pool.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "mes/journal.hpp"
#include "mes/process_description.hpp"
#include "mes/resource_claims.hpp"
#include "mes/skill_connection_pool.hpp"
#include "mes/skill_facts.hpp"
#include "mes/step_binding.hpp"
#include "skills/skill_client.hpp"
#include "skills/skill_connection.hpp"
#include "skills/skill_detector.hpp"
#include "ua/client/client.hpp"

namespace skillcell::mes {

struct ExecutorOptions {
    ExecutorOptions() = default;  // not an aggregate: see ua::ClientConfig
    /// How long a step waits for a suitable skill to be detected before it fails.
    std::chrono::milliseconds skillWait{10'000};
    /// The longest a single skill may run.
    std::chrono::milliseconds stepTimeout{300'000};
    /// How the MES connects to the skills (its identity, security and user).
    ua::ClientConfig client;
    /// Its skill subscriptions (events at 10 ms, a keep-alive of 1 s).
    skills::SkillClientOptions skillClient;
    /// How long, after losing contact mid-step, to wait for the detector to confirm that the
    /// component is gone before the step may go to another instance.
    std::chrono::milliseconds goneConfirmation{5'000};
    /// How long a session to a skill is kept open after a step, for the next step that runs
    /// it (SkillConnectionPool); 0: each step opens its own.
    std::chrono::milliseconds keepConnections{30'000};
    /// How long an order waits for a component another order holds before it stops.
    std::chrono::milliseconds claimWait{3'600'000};
    /// Who reserves components (skills/reservation.hpp), followed by " order <id>": one MES
    /// and its journal (a standby on the same journal is the same holder).
    std::string holder = "urn:skillcell:mes";
};

/// What the executor is doing, for progress displays and the MES's status variables.
struct Progress {
    std::int64_t run = 0;
    std::string processIri;
    int step = 0;  // from 1; 0 before the first step
    int steps = 0;
    std::string skillType;  // short name
    std::string component;  // application URI
    std::string skill;      // browse path
    std::string state;      // "choosing", "running", "finished", "failed", "skipped", ...
    std::string message;

    /// "step 3/5 ChangeToolSkillType running Skills/ChangeTool @ urn:... - message": what a
    /// display prints, and the MES's Progress variable holds.
    [[nodiscard]] std::string line() const;
};

struct ProcessOutcome {
    bool completed = false;
    std::int64_t run = 0;  // the order; 0 when none was begun
    std::string reason;    // why it stopped
    bool cancelled = false;
};

/// What submit() did.
struct Submitted {
    std::int64_t order = 0;
    /// The process's Stopped order is resumed rather than a new one begun (what it did
    /// stays done).
    bool resumed = false;
};

/// Reads a process description (from the KB; tests give their own).
using ProcessReader =
    std::function<asio::awaitable<kb::Expected<ProcessDescription>>(std::string processIri)>;
/// Reads what the KB says of the skill instances for some properties.
using FactReader =
    std::function<asio::awaitable<kb::Expected<SkillFacts>>(std::vector<std::string> properties)>;

/// How the executor reaches the knowledge base.
struct KnowledgeReaders {
    ProcessReader process;
    FactReader facts;  // may be empty: then a step with requirements cannot run
};

class ProcessExecutor : public std::enable_shared_from_this<ProcessExecutor> {
public:
    [[nodiscard]] static std::shared_ptr<ProcessExecutor> create(
        std::shared_ptr<skills::SkillDetector> detector, Journal& journal, KnowledgeReaders kb,
        ExecutorOptions options = {});

    [[nodiscard]] const asio::any_io_executor& executor() const { return detector_->executor(); }
    [[nodiscard]] Journal& journal() { return journal_; }

    /// Records an order of `processIri` (Queued) and begins it. A Stopped order of the same
    /// process, not running now, is resumed instead. On the executor.
    [[nodiscard]] kb::Expected<Submitted> submit(const std::string& processIri, int priority = 0);
    /// Waits for the end of `order` (at once when it is not running in this MES: then from
    /// the journal).
    asio::awaitable<ProcessOutcome> outcome(std::int64_t order);
    /// Submits `processIri` and waits for its end (the ExecuteProcess skill, tests).
    asio::awaitable<ProcessOutcome> execute(std::string processIri, int priority = 0);
    /// Begins every order the journal shows Queued or Running (a restarted MES), and ends a
    /// standBy(). On the executor; returns how many.
    [[nodiscard]] kb::Expected<std::size_t> resumeOpenOrders();
    /// While another MES runs the journal's orders (JournalLock): nothing runs here, and
    /// submit() refuses (Unavailable).
    void standBy() { standingBy_ = true; }
    [[nodiscard]] bool standingBy() const { return standingBy_; }

    /// Stops `order`: a queued one at once; a running one's skills are halted. `cancel`:
    /// Cancelled, never resumed; else Stopped ("halted"), as a fault leaves it. BadInput when
    /// it has already ended or does not exist.
    [[nodiscard]] kb::Status stop(std::int64_t order, bool cancel);
    /// Stops every running order (Stopped: resumable).
    void haltAll();
    /// Forwarded to the skills `order` runs now.
    void suspend(std::int64_t order);
    void resume(std::int64_t order);

    /// How long finished steps of one skill type took, by component: ms, newest first, at
    /// most the last 20 each (what the MES ranks free instances by).
    using Durations = std::map<std::string, std::vector<std::int64_t>>;

    /// The orders running in this MES now, each with its latest progress.
    [[nodiscard]] std::vector<Progress> running() const;

    /// Called on every change of what an order does (on the executor).
    std::function<void(const Progress&)> onProgress;

    struct Token {
    private:
        friend class ProcessExecutor;
        Token() = default;
    };
    ~ProcessExecutor();
    ProcessExecutor(const ProcessExecutor&) = delete;
    ProcessExecutor& operator=(const ProcessExecutor&) = delete;
    ProcessExecutor(Token, std::shared_ptr<skills::SkillDetector> detector, Journal& journal,
                    KnowledgeReaders kb, ExecutorOptions options);

private:
    struct Order;
    struct StepResult {
        bool ok = false;
        std::string reason;
    };
    enum class Settled : std::uint8_t { NotStarted, Finished, Failed };

    /// The order's whole run, from reading its process to its end in the journal.
    asio::awaitable<ProcessOutcome> runOrder(std::shared_ptr<Order> order);
    /// Its steps, in order or as a DAG; the reason it stopped, empty when all finished.
    asio::awaitable<std::string> runSteps(std::shared_ptr<Order> order,
                                          const ProcessDescription& process,
                                          const RunRecord& previous);
    void begin(std::int64_t id, std::string processIri, int priority);
    /// Calls `method` (Suspend, Resume) on the skills order `id` runs now.
    void forward(std::int64_t id, skills::SkillMethod method);
    void finish(Order& order, ProcessOutcome outcome);
    /// `p`: the progress so far (order, step), to report this step's on.
    asio::awaitable<StepResult> runStep(std::shared_ptr<Order> order, const ProcessStep& step,
                                        int attempt, Progress p);
    /// What became of an attempt the journal shows as Starting (after a crash).
    asio::awaitable<std::pair<Settled, std::string>> settle(std::shared_ptr<Order> order,
                                                            const StepRecord& record);
    /// Time a step spent asleep for one reason, and what it waited on when it last slept.
    struct Wait {
        std::chrono::steady_clock::duration time{};
        std::string on;
    };
    struct Choice {
        std::vector<skills::SkillInstance> skills;  // suitable and available, best first
        std::string unmet;  // when there are none: the requirements not met, and why
        /// The knowledge base could not be asked (no answer, an error): unmet says why.
        bool kbUnreachable = false;
        /// It answered, but has not recorded yet some live skill the step could use (a
        /// component just plugged in, or a restarted KB recording the live cell again).
        bool kbBehind = false;
        /// The instances meeting the step's requirements on the cell (CellMatch).
        std::vector<std::optional<skills::SkillInstance>> cellMatches;
        /// Why the first of `skills` was chosen (journaled with the attempt).
        std::string why;
        /// What met the requirements on the cell, and why (CellMatch::chosen).
        std::string chosen;
        /// The robot each of `skills` acts through, where it is on one (robotOf: a tool
        /// changer's), and the one the cell matches act through (a pick's gripper's, which a
        /// composite moves when the process names no robot): the step holds it too.
        std::map<SkillKey, std::string> robots;
        std::string matchedRobot;
        /// How long the step waited for a suitable skill to be there (not for other orders
        /// or steps to free one), and what it lacked last: journaled in the attempt's note, so
        /// that a step that started late says whether it waited for its own skill.
        Wait forSkill;
        /// How long it waited for other orders, or other steps of its own, to free a suitable
        /// component, and which held them last (journaled likewise).
        Wait forHolders;
    };
    /// Why the cell cannot run `process` (empty: it can), after waiting up to skillWait for
    /// the skills it lacks to appear (or for the KB to record their facts).
    asio::awaitable<std::vector<std::string>> feasible(std::shared_ptr<Order> order,
                                                       const ProcessDescription& process,
                                                       Progress p);
    /// Suitable instances that `order` may use now, or after waiting up to skillWait for one
    /// to appear (or for the KB to record the facts that make one suitable), or as long as
    /// claimWait for another order, or another step of this one, to free one.
    asio::awaitable<Choice> choose(std::shared_ptr<Order> order, const ProcessStep& step,
                                   const std::set<TriedKey>& excluded, Progress p);
    /// Which of `typed` (suitable by type) meet the step's requirements, by the KB's facts.
    asio::awaitable<Choice> withRequirements(const ProcessStep& step,
                                             std::vector<skills::SkillInstance> typed,
                                             const std::vector<skills::SkillInstance>& live);
    /// The components a choice uses: its first skill's, the robot that skill is on, and those
    /// of its cell matches.
    [[nodiscard]] static std::set<std::string> componentsOf(const Choice& c);
    /// The components that running `skill` (none: only the matches) with `cellMatches` uses;
    /// `robots`, `matchedRobot`: the robots they act through (Choice).
    [[nodiscard]] static std::set<std::string> componentsOf(
        const skills::SkillInstance* skill,
        const std::vector<std::optional<skills::SkillInstance>>& cellMatches,
        const std::map<SkillKey, std::string>& robots = {}, const std::string& matchedRobot = {});
    /// Whether `order` may use every component of `components` now (held by no other order,
    /// used by none of its own running steps, wanted by no better-ranked waiting order).
    [[nodiscard]] bool available(const Order& order, const std::set<std::string>& components) const;
    /// Sleeps until `timer` expires or is cancelled; halt() and the events that may change
    /// the outcome of a wait cancel it.
    asio::awaitable<void> sleep(Order& order, std::shared_ptr<asio::steady_timer> timer);
    /// Wakes every order waiting for a component.
    void componentsFreed();
    /// How long the last finished steps of `skillTypeIri` took on each component: from the
    /// journal at first, then kept up to date by finishedIn(). Null when the journal cannot be
    /// read. Read it before the caller next suspends: a step finishing meanwhile changes it.
    asio::awaitable<const Durations*> expectedDurations(std::string skillTypeIri);
    /// A step of `skillTypeIri` finished on `componentUri` as `r` records.
    void finishedIn(const std::string& skillTypeIri, const std::string& componentUri,
                    const StepRecord& r);
    /// Releases the component's reservation, when `token` holds one.
    asio::awaitable<ua::StatusCode> letGo(skills::SkillConnection& connection,
                                          std::optional<std::uint64_t> token);
    /// Releases the component's reservation (when `token` holds one), then gives the
    /// connection to `skill` back to the pool (which keeps it for the next step, or closes it).
    asio::awaitable<void> hangUp(const skills::SkillInstance& skill,
                                 std::unique_ptr<skills::SkillConnection> connection,
                                 std::optional<std::uint64_t> token);
    /// What a step holds of its skill while it runs: the session, the component's fencing
    /// token (none when the component has no reservation) and the skill's LastTransition as
    /// read under the hold. Or why it could not have them.
    struct Claim {
        enum class Failure { None, Unreachable, Refused, Unreadable };
        Failure failure = Failure::None;
        std::string why;
        std::unique_ptr<skills::SkillConnection> connection;
        std::optional<std::uint64_t> token;
        ua::DateTime before;
    };
    /// Takes a session to `skill` (a kept one when there is one), reserves its component for
    /// `order` and reads the skill's LastTransition. Reserve and Read go out together, one
    /// round trip: a skill server answers one session's requests in the order they came, so
    /// the read sees the skill under the hold. A failed claim holds nothing, and its
    /// connection is closed.
    asio::awaitable<Claim> claim(const skills::SkillInstance& skill, const Order& order);
    /// Whether the life of `skill`'s component has ended: the detector no longer lists it with
    /// the StartTime it had (it left, or restarted), waiting up to goneConfirmation.
    asio::awaitable<bool> componentGone(std::shared_ptr<Order> order, skills::SkillInstance skill);
    [[nodiscard]] std::string noSkillReason(const ProcessStep& step,
                                            const std::set<TriedKey>& tried) const;
    /// The components that offered a skill suiting `step` and left lately, with why and
    /// when ("WHERE, gone (REASON) N s ago; ..."), not counting those listed again.
    [[nodiscard]] std::string departed(const ProcessStep& step) const;
    /// Remembers the skills that leave (from the detector's events, on its executor; once),
    /// so that a step that finds none can name the component that offered it.
    void watchDepartures();
    void report(Order& order, Progress p);
    /// Runs `write` (a call of the journal) on the journal's thread, and resumes on the
    /// executor with its result: an fsync'd write must not hold up the server's thread (its
    /// other sessions, the progress variables).
    template <class Write>
    asio::awaitable<std::invoke_result_t<Write&>> journaled(Write write);
    /// Records `step` in the journal, together with what other orders record meanwhile
    /// (writeRecords()).
    asio::awaitable<kb::Status> record(std::int64_t run, StepRecord step);
    /// Writes the records waiting, in one transaction per round, until none waits.
    asio::awaitable<void> writeRecords();
    struct PendingRecord {
        PendingRecord(std::int64_t r, StepRecord s, asio::steady_timer t)
            : run(r), step(std::move(s)), written(std::move(t)) {}
        std::int64_t run;
        StepRecord step;
        asio::steady_timer written;  // cancelled once done
        bool done = false;
        kb::Status result = kb::Done{};
    };

    std::shared_ptr<skills::SkillDetector> detector_;
    Journal& journal_;
    KnowledgeReaders kb_;
    ExecutorOptions options_;
    std::map<std::int64_t, std::shared_ptr<Order>> orders_;  // running in this MES, by id
    ResourceClaims claims_;
    bool standingBy_ = false;
    /// The sessions to the skills, kept between steps (shared: the destructor hands it to a
    /// last coroutine on the executor, which closes them).
    std::shared_ptr<SkillConnectionPool> connections_;
    /// Records waiting for the journal, and whether writeRecords() is at them.
    std::vector<std::shared_ptr<PendingRecord>> unrecorded_;
    bool recording_ = false;
    /// expectedDurations(), by skill type.
    std::map<std::string, Durations> durations_;
    /// Orders' waits for a component, cancelled when one is freed.
    std::vector<std::weak_ptr<asio::steady_timer>> claimWaits_;
    /// The skills that left lately (the newest last, at most kDepartures), and the detector
    /// subscription that hears them.
    struct Departure {
        skills::SkillInstance instance;
        skills::RemovalReason reason = skills::RemovalReason::Disconnected;
        std::chrono::steady_clock::time_point at;
    };
    static constexpr std::size_t kDepartures = 64;
    std::vector<Departure> departures_;
    std::optional<std::size_t> departuresWatch_;
    /// Where journal calls run (journaled()): one thread, so they stay in order. Last, so
    /// that it is joined before the rest goes.
    std::unique_ptr<asio::thread_pool> journalThread_;
};

}  // namespace skillcell::mes
