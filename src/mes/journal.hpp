#pragma once
// Journal: the semantic MES's record of every order and its run, in SQLite (WAL, synchronous=FULL:
// a row is on disk before the call returns). A step is written three times: its intent
// (which skill it is about to start, and that skill's LastTransition time as the skill's
// server reported it just before), once its Start was accepted, and with its result. That is
// what lets a restarted MES resume a run: a completed step is never repeated, and a step
// whose Start may or may not have reached the skill is settled by asking the skill (see
// ProcessExecutor::resume).
//
// Threading: SQLite serializes calls (FULLMUTEX); the MES writes from its journal thread and
// answers its order methods from the server's.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kb/expected.hpp"

struct sqlite3;

namespace skillcell::mes {

/// An order is a run of a process from the moment it is submitted: one row, one id.
enum class RunState : std::uint8_t {
    Running,    // being executed, or the MES died while it was (a restarted MES resumes it)
    Stopped,    // stopped by a fault; `reason` says why; submitting it again resumes it
    Completed,  // every step finished
    Queued,     // submitted, not yet begun (a restarted MES begins it)
    Cancelled,  // cancelled by a user: never resumed
};
enum class StepState : std::uint8_t {
    Starting,  // about to call Start on the skill recorded
    Running,   // Start was accepted
    Finished,  // the skill went back to Ready
    Failed,    // it did not: `reason` says why
};
[[nodiscard]] const char* toString(RunState state);
[[nodiscard]] const char* toString(StepState state);

/// One attempt at one step: the skill instance chosen and what became of it.
struct StepRecord {
    int index = 0;  // the step's position in the process, from 1
    int attempt = 1;
    std::string stepIri;
    StepState state = StepState::Starting;
    std::string skillTypeIri;
    std::string componentUri;
    std::string endpointUrl;
    std::string skillNodeId;  // as the component's server names it ("ns=1;s=Skills/Move")
    /// The skill's LastTransition/TransitionTime (DateTime ticks) read just before Start: if
    /// it is unchanged after a crash, Start never reached the skill.
    std::int64_t transitionTimeBefore = 0;
    std::string reason;
    /// Why this attempt was made, or what the MES did before it: a retry after a Halted
    /// attempt, a reset of a skill that an earlier fault had left Halted.
    std::string note;
    /// Why this instance was chosen among the candidates (expected durations learned from
    /// the journal, candidates held by other orders).
    std::string choice;
    /// What the order held for this step: its component and the others it acted through (the
    /// robot a composite or a tool changer moves). A resumed order takes them all back.
    std::vector<std::string> held;
    std::int64_t startedMs = 0;  // Unix time, ms
    std::int64_t endedMs = 0;
};

struct RunRecord {
    std::int64_t id = 0;
    std::string processIri;
    RunState state = RunState::Running;
    std::string reason;
    int priority = 0;  // higher first; among equals, the older order first
    std::int64_t startedMs = 0;
    std::int64_t endedMs = 0;
    std::vector<StepRecord> steps;  // by index, then attempt

    /// The last attempt at step `index`, if any.
    [[nodiscard]] const StepRecord* lastAttempt(int index) const;
};

class Journal {
public:
    /// Opens (creating it and its tables if needed) the journal at `path`. An error names the
    /// file and SQLite's reason (not a database, locked, no permission).
    [[nodiscard]] static kb::Expected<std::unique_ptr<Journal>> open(const std::string& path);
    ~Journal();
    Journal(const Journal&) = delete;
    Journal& operator=(const Journal&) = delete;

    /// A new run of `processIri`, Running; returns its id.
    [[nodiscard]] kb::Expected<std::int64_t> beginRun(const std::string& processIri);
    /// A new order of `processIri`, Queued; returns its id. Safe beside the MES's other
    /// thread (the id comes from the insert itself).
    [[nodiscard]] kb::Expected<std::int64_t> submitOrder(const std::string& processIri,
                                                         int priority);
    /// Inserts or replaces the row of (run, step.index, step.attempt).
    [[nodiscard]] kb::Status recordStep(std::int64_t run, const StepRecord& step);
    /// recordStep() for each of `steps` (run, record), in one transaction: one fsync for all
    /// (group commit). All or none: on an error nothing of them is recorded.
    [[nodiscard]] kb::Status recordSteps(
        const std::vector<std::pair<std::int64_t, StepRecord>>& steps);
    [[nodiscard]] kb::Status setRunState(std::int64_t run, RunState state,
                                         const std::string& reason);

    [[nodiscard]] kb::Expected<std::optional<RunRecord>> run(std::int64_t id);
    /// The latest run of `processIri` that is not Completed, if any: the one to resume.
    [[nodiscard]] kb::Expected<std::optional<RunRecord>> unfinishedRun(
        const std::string& processIri);
    /// The latest run of `processIri`, whatever its state (what a report shows).
    [[nodiscard]] kb::Expected<std::optional<RunRecord>> latestRun(const std::string& processIri);
    /// Every run not Completed (for the MES's start-up report).
    [[nodiscard]] kb::Expected<std::vector<RunRecord>> unfinishedRuns();
    /// The orders a (re)started MES runs: Queued or Running, oldest first.
    [[nodiscard]] kb::Expected<std::vector<RunRecord>> openOrders();
    /// How long finished attempts at steps of `skillTypeIri` took (ms), newest first, at most
    /// `perComponent` for each component: what the MES expects of each.
    [[nodiscard]] kb::Expected<std::map<std::string, std::vector<std::int64_t>>> finishedDurations(
        const std::string& skillTypeIri, std::size_t perComponent);
    /// The last `count` runs, whatever their state, oldest first (what a dashboard shows).
    [[nodiscard]] kb::Expected<std::vector<RunRecord>> recentRuns(std::int64_t count);

    struct Token {
    private:
        friend class Journal;
        Token() = default;
    };
    Journal(Token, sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}

private:
    [[nodiscard]] kb::Status exec(const std::string& sql);
    [[nodiscard]] kb::Error error(const std::string& what) const;
    [[nodiscard]] kb::Expected<std::optional<RunRecord>> lastRun(const std::string& where,
                                                                 const std::string& processIri);
    [[nodiscard]] kb::Expected<std::vector<RunRecord>> runs(const std::string& where,
                                                            const std::string& text,
                                                            std::int64_t number);

    sqlite3* db_;
    std::string path_;
};

/// The current Unix time in ms (what the journal's timestamps are).
[[nodiscard]] std::int64_t unixMillis();

}  // namespace skillcell::mes
