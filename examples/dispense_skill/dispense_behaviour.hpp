#pragma once
// The one class a new skill type needs: its behaviour. A simulated glue dispenser: it pumps
// Volume millilitres at FlowRate ml/s from a reservoir, pauses on Suspend, stops on Halt,
// and fails (the skill goes to Halted with the reason) when the reservoir runs dry.
// States, methods, events, parameter checks and reservation come from skills::Skill.
#include <algorithm>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <string>

#include "skills/skill_behaviour.hpp"

namespace skillcell::examples {

class DispenseBehaviour final : public skills::SkillBehaviour {
public:
    DispenseBehaviour(asio::any_io_executor executor, double reservoirMl, double speedFactor)
        : timer_(std::move(executor)), reservoirMl_(reservoirMl), speed_(speedFactor) {}

    void start(const skills::SkillParameters& parameters, skills::SkillRun run) override {
        run_ = run;
        // Parameters arrive checked against the model (type, EURange) and fixed for the run.
        const double volume = parameters.get<double>("Volume").value_or(0);
        flowRate_ = parameters.get<double>("FlowRate").value_or(1);
        if (volume > reservoirMl_) {
            run.failed("reservoir holds " + std::to_string(reservoirMl_) + " ml, " +
                       std::to_string(volume) + " ml requested");
            return;
        }
        remainingMl_ = volume;
        pump();
    }
    void suspend() override { stopPump(); }
    void resume() override { pump(); }
    void halt() override { stopPump(); }

    [[nodiscard]] double reservoirMl() const { return reservoirMl_; }

private:
    using Clock = std::chrono::steady_clock;

    void pump() {
        startedAt_ = Clock::now();
        const double seconds = remainingMl_ / flowRate_ / speed_;
        timer_.expires_after(
            std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds)));
        timer_.async_wait([this](const std::error_code& ec) {
            if (ec) return;  // suspended or halted: stopPump() accounted for the volume
            reservoirMl_ -= remainingMl_;
            remainingMl_ = 0;
            run_.finished();
        });
    }
    void stopPump() {
        const double seconds = std::chrono::duration<double>(Clock::now() - startedAt_).count();
        const double pumped = std::min(remainingMl_, seconds * speed_ * flowRate_);
        reservoirMl_ -= pumped;
        remainingMl_ -= pumped;
        timer_.cancel();
    }

    asio::steady_timer timer_;
    double reservoirMl_;
    double speed_;
    double flowRate_ = 1;
    double remainingMl_ = 0;
    Clock::time_point startedAt_{};
    skills::SkillRun run_;
};

}  // namespace skillcell::examples
