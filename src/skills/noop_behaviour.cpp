#include "skills/noop_behaviour.hpp"

namespace skillcell::skills {

NoOpBehaviour::NoOpBehaviour(const asio::any_io_executor& executor,
                             std::chrono::milliseconds duration, int haltFirst)
    : timer_(executor), duration_(duration), haltsLeft_(haltFirst) {}

void NoOpBehaviour::start(const SkillParameters& parameters, SkillRun run) {
    last_ = parameters;
    run_ = run;
    ++runs_;
    if (haltsLeft_ > 0) {
        --haltsLeft_;
        run.failed("run " + std::to_string(runs_) + " halts on purpose (--noop-halts)");
        return;
    }
    if (duration_.count() == 0) {
        run.finished();
        return;
    }
    arm(duration_);
}

void NoOpBehaviour::arm(std::chrono::steady_clock::duration remaining) {
    remaining_ = remaining;
    armedAt_ = std::chrono::steady_clock::now();
    const std::uint64_t generation = ++armed_;
    timer_.expires_after(remaining);
    timer_.async_wait([this, generation](const std::error_code& ec) {
        if (ec || generation != armed_) return;
        run_.finished();
    });
}

void NoOpBehaviour::suspend() {
    ++armed_;
    timer_.cancel();
    const auto elapsed = std::chrono::steady_clock::now() - armedAt_;
    remaining_ =
        elapsed >= remaining_ ? std::chrono::steady_clock::duration::zero() : remaining_ - elapsed;
}

void NoOpBehaviour::resume() {
    arm(remaining_);
}

void NoOpBehaviour::halt() {
    ++armed_;
    timer_.cancel();
}

}  // namespace skillcell::skills
