#pragma once
// NoOpBehaviour: a skill that does nothing, successfully, at once or after a fixed time.
// It serves `skillcell server --noop-skill`, the benchmarks (the cost of the skill
// machinery itself) and tests of everything around a skill. Suspend pauses the remaining
// time; Halt cancels it. Told to, its first runs end Halted instead, as a skill whose
// hardware faults does (tests of retries).
#include <asio/any_io_executor.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <memory>

#include "skills/skill_behaviour.hpp"

namespace skillcell::skills {

class NoOpBehaviour final : public SkillBehaviour {
public:
    /// `haltFirst`: how many runs, from the first, end Halted rather than finished.
    explicit NoOpBehaviour(const asio::any_io_executor& executor,
                           std::chrono::milliseconds duration = std::chrono::milliseconds(0),
                           int haltFirst = 0);

    void start(const SkillParameters& parameters, SkillRun run) override;
    void suspend() override;
    void resume() override;
    void halt() override;

    /// The parameters of the last run (tests check that a run saw the values fixed at
    /// Start).
    [[nodiscard]] const SkillParameters& lastParameters() const { return last_; }

private:
    void arm(std::chrono::steady_clock::duration remaining);

    asio::steady_timer timer_;
    std::chrono::milliseconds duration_;
    std::chrono::steady_clock::duration remaining_{};
    std::chrono::steady_clock::time_point armedAt_{};
    SkillRun run_;
    SkillParameters last_;
    int haltsLeft_ = 0;
    int runs_ = 0;
    std::uint64_t armed_ = 0;  // bumps on every arm/cancel, so a stale wait does nothing
};

}  // namespace skillcell::skills
