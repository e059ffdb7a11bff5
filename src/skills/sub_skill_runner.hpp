#pragma once
// SubSkillRunner: what a composite skill (a tool changer, a pick and place) needs to run its
// sub-skills one at a time under its own state machine: Halt of the composite halts the
// sub-skill running now and ends the composite's run; Suspend and Resume go to that
// sub-skill.
//
// Threading: on the composite's executor (the one its SkillClients use).
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <chrono>
#include <map>
#include <memory>
#include <string>

#include "skills/skill_client.hpp"

namespace skillcell::skills {

class SubSkillRunner {
public:
    explicit SubSkillRunner(asio::any_io_executor executor) : executor_(std::move(executor)) {}

    /// Starts a composite run; returns its generation for halted().
    std::uint64_t begin() { return ++generation_; }
    /// Whether halt() was called since begin() returned `generation`.
    [[nodiscard]] bool halted(std::uint64_t generation) const { return generation != generation_; }

    /// Runs `skill` with `parameters` as the current sub-skill (SkillClient::run); a skill
    /// left Halted (by an earlier failure) is reset first.
    asio::awaitable<SkillOutcome> run(SkillClient& skill,
                                      std::map<std::string, ua::Variant> parameters,
                                      std::chrono::milliseconds timeout);
    /// Ends the current composite run: the sub-skill running now is halted.
    void halt();
    void suspend() { forward(SkillMethod::Suspend); }
    void resume() { forward(SkillMethod::Resume); }

private:
    void forward(SkillMethod method);

    asio::any_io_executor executor_;
    std::uint64_t generation_ = 0;
    std::weak_ptr<SkillClient> current_;
};

}  // namespace skillcell::skills
