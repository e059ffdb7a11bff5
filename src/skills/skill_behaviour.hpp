#pragma once
// SkillBehaviour: the only part a concrete skill writes. The Skill (skill.hpp) owns the
// state machine, the methods, interlocking, reservation, parameters and events; the
// behaviour gets the parameters of a run and reports how the run ended, and hears Suspend,
// Resume and Halt.
//
// Threading: every hook is called on the server's io_context thread and must not block
// (start a timer, post to a device thread, ...). A SkillRun may be used from any thread.
#include <cstdint>
#include <memory>
#include <string>

#include "skills/skill_parameters.hpp"

namespace skillcell::skills {

class Skill;

/// One run of a skill, handed to SkillBehaviour::start. The behaviour calls finished() or
/// failed() once, from any thread, now or later. A run that has ended (halted, or already
/// reported) ignores further reports, so a late report from a halted motion cannot end
/// the next run.
class SkillRun {
public:
    SkillRun() = default;
    /// Success: the skill goes to Ready.
    void finished() const;
    /// Failure: the skill goes to Halted; `reason` is the transition event's message.
    void failed(std::string reason) const;
    [[nodiscard]] std::uint64_t id() const { return id_; }

private:
    friend class Skill;
    SkillRun(std::weak_ptr<Skill> skill, std::uint64_t id) : skill_(std::move(skill)), id_(id) {}
    std::weak_ptr<Skill> skill_;
    std::uint64_t id_ = 0;
};

class SkillBehaviour {
public:
    SkillBehaviour() = default;
    virtual ~SkillBehaviour() = default;
    SkillBehaviour(const SkillBehaviour&) = delete;
    SkillBehaviour& operator=(const SkillBehaviour&) = delete;

    /// Begins a run with the parameters fixed at Start (validated against their
    /// declarations). The skill is Running when this is called.
    virtual void start(const SkillParameters& parameters, SkillRun run) = 0;
    /// Pause the run (the skill is now Suspended); it continues after resume(). A run
    /// may still finish or fail while suspended (the state machine allows it).
    virtual void suspend() {}
    virtual void resume() {}
    /// Stop the run now (the skill is now Halted); its SkillRun is already void.
    virtual void halt() {}
    /// Called on Reset (Halted to Ready): clear whatever a failure left behind.
    virtual void reset() {}
};

}  // namespace skillcell::skills
