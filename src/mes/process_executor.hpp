#pragma once
// ProcessExecutor: runs a process, step by step, on whatever skills the cell offers (paper,
// section VII-C). For each step it picks a suitable live skill instance (step_binding.hpp)
// from the SkillDetector's map, derives the parameter values, runs the skill with a
// SkillClient, and records intent and result in the Journal before going on.
//
// A step's requirements (proc:requiresFact) are facts the KB must hold: of the skill chosen,
// or of some available skill of a given type (a gripper of the grip type a pick was planned
// for). Liveness comes from the detector, facts from the KB; the KB records a new component
// about a second after discovery, so while a step's skills are there but its facts are not,
// the MES asks the KB again, four times a second, up to skillWait.
//
// Faults stop the run in a defined state (RunState::Stopped, with the reason): a skill that
// ends Halted or times out, a step no skill can run, a process the KB cannot describe. A skill
// that cannot be reached, refuses its parameters or Start, or whose component disappears
// mid-step is replaced by another suitable instance when there is one; a Halted one is not,
// since what it did to the cell is unknown.
//
// execute() resumes the process's unfinished run if the journal has one: finished steps are
// skipped, and a step the journal shows as being started is settled by asking its skill
// (unchanged LastTransition: Start never reached it, so it runs; Running: the run is waited
// for; Ready or Halted after a transition: it finished or failed while nobody watched).
//
// Threading: on the detector's executor; journal calls run on a thread of their own, each
// awaited before the run goes on (intent before Start, result before the next step).
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <asio/thread_pool.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <type_traits>

#include "mes/journal.hpp"
#include "mes/process_description.hpp"
#include "mes/skill_facts.hpp"
#include "mes/step_binding.hpp"
#include "skills/skill_detector.hpp"
#include "skills/sub_skill_runner.hpp"
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
    std::int64_t run = 0;  // 0 when no run was begun
    std::string reason;    // why it stopped
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
    /// Runs (or resumes) `processIri` to its end or its first unrecoverable fault.
    asio::awaitable<ProcessOutcome> execute(std::string processIri);
    /// Ends the current execute(): the skill running now is halted, the run stops.
    void halt();
    /// Forwarded to the skill running now.
    void suspend() { runner_.suspend(); }
    void resume() { runner_.resume(); }

    /// Called on every change of what the executor does (on the executor).
    std::function<void(const Progress&)> onProgress;

    struct Token {
    private:
        friend class ProcessExecutor;
        Token() = default;
    };
    ProcessExecutor(Token, std::shared_ptr<skills::SkillDetector> detector, Journal& journal,
                    KnowledgeReaders kb, ExecutorOptions options);

private:
    struct StepResult {
        bool ok = false;
        std::string reason;
    };
    enum class Settled : std::uint8_t { NotStarted, Finished, Failed };

    /// `p`: the progress so far (run, step), to report this step's on.
    asio::awaitable<StepResult> runStep(std::int64_t run, const ProcessStep& step, int attempt,
                                        std::uint64_t generation, Progress p);
    /// What became of an attempt the journal shows as Starting (after a crash).
    asio::awaitable<std::pair<Settled, std::string>> settle(const StepRecord& record,
                                                            std::uint64_t generation);
    struct Choice {
        std::vector<skills::SkillInstance> skills;  // suitable and available, best first
        std::string unmet;  // when there are none: the requirements not met, and why
        /// The instances meeting the step's requirements on the cell (CellMatch).
        std::vector<std::optional<skills::SkillInstance>> cellMatches;
    };
    /// Why the cell cannot run `process` (empty: it can), after waiting up to skillWait for
    /// the skills it lacks to appear (or for the KB to record their facts).
    asio::awaitable<std::vector<std::string>> feasible(const ProcessDescription& process,
                                                       std::uint64_t generation);
    /// Suitable instances now, or after waiting up to skillWait for one to appear (or for
    /// the KB to record the facts that make one suitable).
    asio::awaitable<Choice> choose(const ProcessStep& step, const std::set<SkillKey>& excluded,
                                   std::uint64_t generation);
    /// Which of `typed` (suitable by type) meet the step's requirements, by the KB's facts.
    asio::awaitable<Choice> withRequirements(const ProcessStep& step,
                                             std::vector<skills::SkillInstance> typed,
                                             const std::vector<skills::SkillInstance>& live);
    /// Whether the detector no longer lists `componentUri`, waiting up to goneConfirmation.
    asio::awaitable<bool> componentGone(std::string componentUri);
    [[nodiscard]] std::string noSkillReason(const ProcessStep& step,
                                            const std::set<SkillKey>& tried) const;
    void report(Progress p);
    /// Runs `write` (a call of the journal) on the journal's thread, and resumes on the
    /// executor with its result: an fsync'd write must not hold up the server's thread (its
    /// other sessions, the progress variables).
    template <class Write>
    asio::awaitable<std::invoke_result_t<Write&>> journaled(Write write);
    asio::awaitable<kb::Status> record(std::int64_t run, StepRecord step);

    std::shared_ptr<skills::SkillDetector> detector_;
    Journal& journal_;
    KnowledgeReaders kb_;
    ExecutorOptions options_;
    skills::SubSkillRunner runner_;
    Progress progress_;
    bool busy_ = false;
    std::weak_ptr<asio::steady_timer> waitTimer_;  // choose(), for halt()
    std::weak_ptr<skills::SkillClient> adopted_;   // settle()'s wait, for halt()
    /// Where journal calls run (journaled()): one thread, so they stay in order. Last, so
    /// that it is joined before the rest goes.
    std::unique_ptr<asio::thread_pool> journalThread_;
};

}  // namespace skillcell::mes
