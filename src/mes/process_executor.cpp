#include "mes/process_executor.hpp"

#include <spdlog/spdlog.h>

#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include <algorithm>

#include "devices/common/blocking_call.hpp"
#include "mes/feasibility.hpp"
#include "skills/skill_connection.hpp"

namespace skillcell::mes {
namespace {

using skills::SkillOutcome;
using skills::SkillState;

// How many skill instances one step tries before it gives up: a bound on a cell whose
// components keep failing in turn.
constexpr int kMaxInstancesPerStep = 8;

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
      runner_(detector_->executor()),
      journalThread_(std::make_unique<asio::thread_pool>(1)) {}

void ProcessExecutor::report(Progress p) {
    progress_ = std::move(p);
    if (onProgress) onProgress(progress_);
}

template <class Write>
asio::awaitable<std::invoke_result_t<Write&>> ProcessExecutor::journaled(Write write) {
    auto self = shared_from_this();
    co_return co_await devices::blockingCall(*journalThread_, std::move(write));
}

asio::awaitable<kb::Status> ProcessExecutor::record(std::int64_t run, StepRecord step) {
    auto write = [this, run, &step] { return journal_.recordStep(run, step); };
    auto s = co_await journaled(write);
    if (!s) spdlog::error("mes: {}", s.error());
    co_return s;
}

void ProcessExecutor::halt() {
    runner_.halt();
    if (auto timer = waitTimer_.lock()) timer->cancel();
    if (auto adopted = adopted_.lock()) adopted->cancel();
}

asio::awaitable<ProcessOutcome> ProcessExecutor::execute(std::string processIri) {
    auto self = shared_from_this();
    ProcessOutcome out;
    if (busy_) {
        out.reason = "the MES is running a process already";
        co_return out;
    }
    busy_ = true;
    struct Idle {
        bool& busy;
        ~Idle() { busy = false; }
    } idle{busy_};
    const std::uint64_t generation = runner_.begin();
    Progress p;
    p.processIri = processIri;
    p.state = "reading";
    p.message = "asking the knowledge base for the process";
    report(p);
    auto description = co_await kb_.process(processIri);
    if (!description) {
        out.reason = "cannot read the process " + processIri + ": " + description.error();
        p.state = "stopped";
        p.message = out.reason;
        report(p);
        co_return out;
    }
    const auto& steps = description->steps;
    p.steps = static_cast<int>(steps.size());
    // Before the first motion: can the cell run it at all? Every reason at once.
    if (auto lacking = co_await feasible(*description, generation); !lacking.empty()) {
        out.reason = "the cell cannot run " + processIri + ": ";
        for (std::size_t i = 0; i < lacking.size(); ++i) {
            out.reason += (i == 0 ? "" : "; ") + lacking[i];
        }
        spdlog::warn("mes: refused {}", out.reason);
        p.state = "refused";
        p.message = out.reason;
        report(p);
        co_return out;
    }

    // Resume the unfinished run of this process, or begin one.
    RunRecord previous;
    auto findUnfinished = [this, &processIri] { return journal_.unfinishedRun(processIri); };
    auto unfinished = co_await journaled(findUnfinished);
    if (!unfinished) {
        out.reason = unfinished.error();
        co_return out;
    }
    if (*unfinished) {
        previous = std::move(**unfinished);
        for (const auto& r : previous.steps) {
            const bool same = r.index >= 1 && r.index <= p.steps &&
                              steps[static_cast<std::size_t>(r.index - 1)].iri == r.stepIri;
            if (!same) {
                out.run = previous.id;
                out.reason = "run " + std::to_string(previous.id) + " of " + processIri +
                             " cannot be resumed: the process changed since (step " +
                             std::to_string(r.index) + " was <" + r.stepIri + ">)";
                co_return out;
            }
        }
        auto resume = [this, id = previous.id] {
            return journal_.setRunState(id, RunState::Running, {});
        };
        if (auto s = co_await journaled(resume); !s) {
            out.reason = s.error();
            co_return out;
        }
        spdlog::info("mes: resuming run {} of {} (it was {}{})", previous.id, processIri,
                     toString(unfinished->value().state),
                     previous.reason.empty() ? "" : ": " + previous.reason);
    } else {
        auto begin = [this, &processIri] { return journal_.beginRun(processIri); };
        auto id = co_await journaled(begin);
        if (!id) {
            out.reason = id.error();
            co_return out;
        }
        previous.id = *id;
        previous.processIri = processIri;
        spdlog::info("mes: run {} of {}: {} steps", previous.id, processIri, steps.size());
    }
    out.run = previous.id;
    p.run = previous.id;

    std::string stopReason;  // set (and the loop left) when the run stops
    for (const auto& step : steps) {
        p.step = step.index;
        p.skillType = shortName(step.skillTypeIri);
        p.component.clear();
        p.skill.clear();
        if (runner_.halted(generation)) {
            stopReason = "halted before " + step.label();
            break;
        }
        const StepRecord* last = previous.lastAttempt(step.index);
        int attempt = last != nullptr ? last->attempt + 1 : 1;
        if (last != nullptr && last->state == StepState::Finished) {
            p.component = last->componentUri;
            p.state = "done";
            p.message = "finished in an earlier attempt";
            report(p);
            continue;
        }
        if (last != nullptr &&
            (last->state == StepState::Starting || last->state == StepState::Running)) {
            // The MES stopped while this step was being started or run: ask its skill.
            p.component = last->componentUri;
            p.skill = last->skillNodeId;
            p.state = "checking";
            p.message = "the MES stopped during this step: asking the skill what became of it";
            report(p);
            auto [settled, why] = co_await settle(*last, generation);
            StepRecord r = *last;
            r.endedMs = unixMillis();
            r.state = settled == Settled::Finished ? StepState::Finished : StepState::Failed;
            r.reason = why;
            if (auto s = co_await record(out.run, r); !s) {
                stopReason = s.error();
                break;
            }
            spdlog::info("mes: {} (attempt {}, interrupted): {}", step.label(), r.attempt, why);
            if (settled == Settled::Finished) {
                p.component = r.componentUri;
                p.state = "finished";
                p.message = why;
                report(p);
                continue;
            }
            if (settled == Settled::Failed) {
                stopReason = step.label() + ": " + why;
                break;
            }
        }
        auto result = co_await runStep(out.run, step, attempt, generation, p);
        if (!result.ok) {
            stopReason = std::move(result.reason);
            break;
        }
    }
    if (!stopReason.empty()) {
        out.reason = std::move(stopReason);
        auto stopped = [this, run = out.run, reason = out.reason] {
            return journal_.setRunState(run, RunState::Stopped, reason);
        };
        if (auto s = co_await journaled(stopped); !s) {
            out.reason += " (and the journal failed: " + s.error() + ")";
        }
        spdlog::warn("mes: run {} stopped: {}", out.run, out.reason);
        p.state = "stopped";
        p.message = out.reason;
        report(p);
        co_return out;
    }
    auto completed = [this, run = out.run] {
        return journal_.setRunState(run, RunState::Completed, {});
    };
    if (auto s = co_await journaled(completed); !s) {
        out.reason = s.error();
        co_return out;
    }
    out.completed = true;
    p.state = "completed";
    p.message = "every step finished";
    report(p);
    spdlog::info("mes: run {} of {} completed", out.run, processIri);
    co_return out;
}

asio::awaitable<std::pair<ProcessExecutor::Settled, std::string>> ProcessExecutor::settle(
    const StepRecord& r, std::uint64_t generation) {
    auto self = shared_from_this();
    skills::SkillInstance target;
    target.componentUri = r.componentUri;
    target.endpointUrl = r.endpointUrl;
    target.nodeId = ua::NodeId::parse(r.skillNodeId).value_or(ua::NodeId());
    // Where the detector sees the component now (it may have moved).
    for (const auto& s : detector_->instances()) {
        if (s.componentUri == r.componentUri && s.nodeId.toString() == r.skillNodeId) target = s;
    }
    std::string why;
    auto conn = co_await skills::SkillConnection::open(detector_->executor(), target,
                                                       options_.client, &why, options_.skillClient);
    if (!conn) {
        co_return std::pair(Settled::Failed, "cannot tell whether the skill " + r.skillNodeId +
                                                 " of " + r.componentUri + " ran: " + why);
    }
    auto& skill = (*conn)->skill();
    auto time = co_await (*conn)->lastTransitionTime();
    std::pair<Settled, std::string> result{Settled::Failed, {}};
    const auto state = skill.state();
    if (!time) {
        result.second = "cannot read the LastTransition of " + r.skillNodeId + " of " +
                        r.componentUri + ": " + std::string(ua::statusName(time.status()));
    } else if (time->ticks == r.transitionTimeBefore && state == SkillState::Ready) {
        result = {Settled::NotStarted, "Start never reached the skill: the MES stopped first"};
    } else if (state == SkillState::Running || state == SkillState::Suspended) {
        // Still running the Start this step gave: wait for its end as if we had stayed.
        spdlog::info("mes: {} of {} is still running the interrupted step: waiting for it",
                     r.skillNodeId, r.componentUri);
        skill.adoptRun(ua::DateTime{r.transitionTimeBefore + 1});
        adopted_ = skill.shared_from_this();
        const SkillOutcome o = co_await skill.waitForEnd(options_.stepTimeout);
        adopted_.reset();
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
    co_await (*conn)->close();
    if (runner_.halted(generation) && result.first != Settled::Finished) {
        result = {Settled::Failed, "halted"};
    }
    co_return result;
}

asio::awaitable<ProcessExecutor::Choice> ProcessExecutor::withRequirements(
    const ProcessStep& step, std::vector<skills::SkillInstance> typed,
    const std::vector<skills::SkillInstance>& live) {
    auto self = shared_from_this();
    Choice c;
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
        co_return c;
    }
    auto cell = matchCellRequirements(step, live, *facts);
    c.unmet = std::move(cell.unmet);
    if (!c.unmet.empty()) co_return c;
    c.cellMatches = std::move(cell.byRequirement);
    std::string unfit;
    for (auto& s : typed) {
        const std::string why = unmetSkillRequirements(step, s, *facts);
        if (why.empty()) {
            c.skills.push_back(std::move(s));
        } else {
            unfit += (unfit.empty() ? "" : "; ") + where(s) + ": " + why;
        }
    }
    if (c.skills.empty()) c.unmet = "no skill of its type meets its requirements: " + unfit;
    co_return c;
}

asio::awaitable<std::vector<std::string>> ProcessExecutor::feasible(
    const ProcessDescription& process, std::uint64_t generation) {
    using Clock = std::chrono::steady_clock;
    constexpr std::chrono::milliseconds kFactRetry{250};  // as choose(): the KB records late
    auto self = shared_from_this();
    const auto deadline = Clock::now() + options_.skillWait;
    const auto properties = requiredProperties(process);
    std::string shown;
    for (;;) {
        std::optional<SkillFacts> facts;
        if (kb_.facts && !properties.empty()) {
            auto read = co_await kb_.facts(properties);
            if (!read)
                co_return std::vector<std::string>{"cannot ask the knowledge base: " +
                                                   read.error()};
            facts = std::move(*read);
        }
        auto lacking = infeasibility(process, detector_->instances(), facts ? &*facts : nullptr);
        if (lacking.empty() || runner_.halted(generation) || Clock::now() >= deadline) {
            co_return lacking;
        }
        Progress p = progress_;
        p.state = "checking";
        p.message = "waiting up to " + std::to_string(options_.skillWait.count()) +
                    " ms for what the process needs: " + lacking.front();
        if (p.message != shown) {
            shown = p.message;
            report(p);
        }
        const auto wake = std::min(deadline, Clock::now() + kFactRetry);
        auto timer = std::make_shared<asio::steady_timer>(detector_->executor(), wake);
        waitTimer_ = timer;
        const std::size_t id = detector_->subscribe([timer](const skills::SkillEvent& e) {
            if (e.kind == skills::SkillEvent::Kind::Added) timer->cancel();
        });
        co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        detector_->unsubscribe(id);
        if (runner_.halted(generation)) co_return std::vector<std::string>{"halted"};
    }
}

asio::awaitable<ProcessExecutor::Choice> ProcessExecutor::choose(const ProcessStep& step,
                                                                 const std::set<SkillKey>& excluded,
                                                                 std::uint64_t generation) {
    using Clock = std::chrono::steady_clock;
    // How often to ask the KB again while the skills are there but their facts are not.
    constexpr std::chrono::milliseconds kFactRetry{250};
    auto self = shared_from_this();
    const auto deadline = Clock::now() + options_.skillWait;
    std::string shown;
    for (;;) {
        const auto live = detector_->instances();
        auto typed = candidates(step, live, excluded);
        Choice c;
        bool askAgain = false;  // whether the KB may soon know what it does not know now
        if (typed.empty() || step.requirements.empty()) {
            c.skills = std::move(typed);
        } else {
            c = co_await withRequirements(step, std::move(typed), live);
            askAgain = c.skills.empty() && static_cast<bool>(kb_.facts);
        }
        if (!c.skills.empty() || runner_.halted(generation) || Clock::now() >= deadline) {
            co_return c;
        }
        Progress p = progress_;
        p.state = "waiting";
        p.component.clear();
        p.skill.clear();
        p.message = "waiting up to " + std::to_string(options_.skillWait.count()) +
                    " ms for a suitable " + shortName(step.skillTypeIri) +
                    (c.unmet.empty() ? "" : ": " + c.unmet);
        if (p.message != shown) {
            shown = p.message;
            report(p);
        }
        const auto wake = askAgain ? std::min(deadline, Clock::now() + kFactRetry) : deadline;
        auto timer = std::make_shared<asio::steady_timer>(detector_->executor(), wake);
        waitTimer_ = timer;
        // A new instance of the step's type, or of a type a requirement names, may fit.
        const std::size_t id =
            detector_->subscribe([timer, step, excluded](const skills::SkillEvent& e) {
                if (e.kind != skills::SkillEvent::Kind::Added) return;
                const bool wanted = (!excluded.contains(keyOf(e.instance)) &&
                                     unsuitability(step, e.instance).empty()) ||
                                    std::any_of(step.requirements.begin(), step.requirements.end(),
                                                [&](const FactRequirement& r) {
                                                    return !r.skillTypeIri.empty() &&
                                                           isOfType(e.instance, r.skillTypeIri);
                                                });
                if (wanted) timer->cancel();
            });
        co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        detector_->unsubscribe(id);
        if (runner_.halted(generation)) co_return Choice{};
    }
}

asio::awaitable<bool> ProcessExecutor::componentGone(std::string componentUri) {
    auto self = shared_from_this();
    auto listed = [this, &componentUri] {
        const auto all = detector_->instances();
        return std::any_of(all.begin(), all.end(),
                           [&](const auto& s) { return s.componentUri == componentUri; });
    };
    if (!listed()) co_return true;
    auto timer =
        std::make_shared<asio::steady_timer>(detector_->executor(), options_.goneConfirmation);
    waitTimer_ = timer;
    const std::size_t id = detector_->subscribe([timer, componentUri](const skills::SkillEvent& e) {
        if (e.kind == skills::SkillEvent::Kind::Removed &&
            e.instance.componentUri == componentUri) {
            timer->cancel();
        }
    });
    co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    detector_->unsubscribe(id);
    co_return !listed();
}

std::string ProcessExecutor::noSkillReason(const ProcessStep& step,
                                           const std::set<SkillKey>& tried) const {
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
    return text;
}

asio::awaitable<ProcessExecutor::StepResult> ProcessExecutor::runStep(
    std::int64_t run, const ProcessStep& step, int attempt, std::uint64_t generation, Progress p) {
    auto self = shared_from_this();
    std::set<SkillKey> tried;
    std::string lastFailure;
    std::string note;  // why the next attempt is made, and what was done first: journaled
    int retried = 0;
    for (int i = 0; i < kMaxInstancesPerStep + step.retries; ++i) {
        p.state = "choosing";
        p.component.clear();
        p.skill.clear();
        p.message.clear();
        report(p);
        const Choice found = co_await choose(step, tried, generation);
        if (runner_.halted(generation)) co_return StepResult{false, "halted in " + step.label()};
        if (found.skills.empty()) {
            std::string why;
            if (found.unmet.empty()) {
                why = noSkillReason(step, tried);
            } else {
                why = step.label() + ": " + found.unmet;
                why += " (waited " + std::to_string(options_.skillWait.count()) + " ms)";
            }
            if (!lastFailure.empty()) why += "; " + lastFailure;
            co_return StepResult{false, why};
        }
        const skills::SkillInstance& skill = found.skills.front();
        auto values = parameterValues(step, skill, found.cellMatches);
        if (!values) co_return StepResult{false, values.error()};
        p.component = skill.componentUri;
        p.skill = skill.browsePathString();
        std::string why;
        auto conn = co_await skills::SkillConnection::open(
            detector_->executor(), skill, options_.client, &why, options_.skillClient);
        if (!conn) {
            tried.insert(keyOf(skill));
            lastFailure = where(skill) + ": " + why;
            p.state = "unreachable";
            p.message = why;
            report(p);
            continue;
        }
        skills::SkillClient& client = (*conn)->skill();
        // A Halted skill runs again only after a Reset, which the journal records with the
        // attempt it precedes: a retry's, or that of a skill an earlier fault left Halted.
        if (client.state() == SkillState::Halted) {
            const ua::StatusCode reset = co_await client.call(skills::SkillMethod::Reset);
            if (reset.isBad()) {
                tried.insert(keyOf(skill));
                lastFailure = where(skill) + ": Halted, and its Reset was refused (" +
                              std::string(ua::statusName(reset)) + ")";
                co_await (*conn)->close();
                continue;
            }
            const std::string what =
                retried > 0 ? "the skill was reset"
                            : "the skill was Halted (an earlier fault left it so) and was reset";
            note += (note.empty() ? "" : "; ") + what;
            spdlog::warn("mes: {}: {}, before {} (attempt {})", where(skill), what, step.label(),
                         attempt);
        }
        auto before = co_await (*conn)->lastTransitionTime();
        if (!before) {
            tried.insert(keyOf(skill));
            lastFailure = where(skill) + ": cannot read its LastTransition: " +
                          std::string(ua::statusName(before.status()));
            co_await (*conn)->close();
            continue;
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
        r.transitionTimeBefore = before->ticks;
        r.startedMs = unixMillis();
        r.note = note;
        if (auto s = co_await record(run, r); !s) {
            co_await (*conn)->close();
            co_return StepResult{false, s.error()};
        }
        p.state = "running";
        p.message.clear();
        report(p);
        spdlog::info("mes: {} on {} (attempt {})", step.label(), where(skill), attempt);
        const SkillOutcome outcome =
            co_await runner_.run(client, std::move(*values), options_.stepTimeout);
        r.endedMs = unixMillis();
        r.state = outcome.ok() ? StepState::Finished : StepState::Failed;
        r.reason = outcome.ok() ? std::string() : describe(outcome);
        const auto recorded = co_await record(run, r);
        co_await (*conn)->close();
        if (!recorded) co_return StepResult{false, recorded.error()};
        if (outcome.ok()) {
            p.state = "finished";
            report(p);
            co_return StepResult{true, {}};
        }
        p.state = "failed";
        p.message = r.reason;
        report(p);
        spdlog::warn("mes: {} on {}: {}", step.label(), where(skill), r.reason);
        if (runner_.halted(generation)) co_return StepResult{false, "halted in " + step.label()};
        // The skill ended Halted: the process's retry policy says whether it runs again.
        if (outcome.kind == SkillOutcome::Kind::Failed && retried < step.retries) {
            ++retried;
            ++attempt;
            note = "retry " + std::to_string(retried) + " of " + std::to_string(step.retries) +
                   " after: " + r.reason;
            spdlog::warn("mes: {}: {}", step.label(), note);
            p.state = "retrying";
            p.message = note;
            report(p);
            continue;  // chosen again: the same instance, unless a better one appeared
        }
        // Lost contact: another instance may take the step only once the component is
        // gone; one still there may still be running the skill.
        if (outcome.kind == SkillOutcome::Kind::Lost &&
            !co_await componentGone(skill.componentUri)) {
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
        tried.insert(keyOf(skill));
        lastFailure = where(skill) + ": " + r.reason;
        note = "another instance, after " + lastFailure;
        ++attempt;
    }
    co_return StepResult{false, step.label() + ": gave up after " +
                                    std::to_string(kMaxInstancesPerStep) +
                                    " skill instances; last: " + lastFailure};
}

}  // namespace skillcell::mes
