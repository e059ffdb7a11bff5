#pragma once
// SimulatedArm: a robot arm's hardware in simulation: joint positions that follow the trajectory
// being executed in simulated time. A steady timer ticks on the io_context; each tick
// advances simulated time by the real time elapsed since the last one (read from an
// injectable clock) times the speed factor, and reports the joints to an observer (the
// published variables, the world model). Pausing freezes simulated time for the motion;
// stopping ends it in place (the simulation stops at once; a real arm decelerates). A
// force-limited motion is sampled finely, as a real arm's force control loop runs: its
// simulated time advances at most kForceSamplePeriod per tick, ticks come every
// kForceTick, it waits while more than kForceSamplesInFlight samples await their force,
// and it ends only when the force at its last pose is within the limit.
#include <asio/any_io_executor.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "devices/arm/arm_controller.hpp"

namespace skillcell::devices {

/// A force-limited motion's sampling: at an insertion's 20 mm/s, 0.04 mm per sample.
inline constexpr double kForceSamplePeriod = 0.002;  // s of simulated time
inline constexpr std::chrono::milliseconds kForceTick{1};
/// How many reported samples may await their force measurement while the motion goes on.
inline constexpr std::uint64_t kForceSamplesInFlight = 1;

struct SimulatedArmOptions {
    using Clock = std::function<std::chrono::steady_clock::time_point()>;
    SimulatedArmOptions() = default;
    double speed = 1.0;  // simulated seconds per real second
    std::chrono::milliseconds tick{10};
    Clock clock;     // empty: std::chrono::steady_clock::now
    Joints initial;  // where the arm starts; empty: the arm model's home (ArmComponent)
    /// Called when a motion reaches its end, before the move is reported: it calls its
    /// argument (from any thread) when the end may be reported, e.g. once the world model
    /// has the final flange pose. Empty: report at once.
    std::function<void(std::function<void()> report)> beforeDone;
    /// The force the tool meets (N), as the arm's torque sensing measures it; empty: the arm
    /// senses none (a force-limited motion then never stops for force).
    std::function<double()> contactForce;
    /// How many poses reported to the observer still await their force measurement; empty:
    /// none ever do (the force is measured at once).
    std::function<std::uint64_t()> unmeasuredSamples;
};

class SimulatedArm final : public ArmController {
public:
    using Observer = std::function<void(const Joints&)>;
    SimulatedArm(const asio::any_io_executor& executor, SimulatedArmOptions options,
                 Observer observer = {});
    ~SimulatedArm() override;

    [[nodiscard]] Joints joints() const override { return joints_; }
    [[nodiscard]] bool busy() const override { return trajectory_.has_value(); }
    bool execute(Trajectory trajectory, Done done) override;
    void pause() override;
    void resume() override;
    void stop() override;

    [[nodiscard]] bool paused() const { return paused_; }
    /// The force the tool meets now (N; 0 when the arm senses none).
    [[nodiscard]] double contactForce() const {
        return options_.contactForce ? options_.contactForce() : 0.0;
    }
    /// Simulated seconds the current motion has run (0 when idle).
    [[nodiscard]] double elapsed() const { return elapsed_; }

private:
    void arm();
    void tick();
    /// The current motion's force limit (N); 0 when it has none or the arm senses no force.
    [[nodiscard]] double forceLimit() const;
    /// Simulated seconds from the last step to `t`: one sample at most in a force-limited motion.
    [[nodiscard]] double simulatedSince(std::chrono::steady_clock::time_point t) const;
    [[nodiscard]] static std::string forceFault(double force, double limit);
    /// Ends the motion where it is (stop()), then tells its owner why.
    void abort(const std::string& fault);
    [[nodiscard]] std::chrono::steady_clock::time_point now() const;

    asio::steady_timer timer_;
    SimulatedArmOptions options_;
    Observer observer_;
    Joints joints_;
    std::optional<Trajectory> trajectory_;
    Done done_;
    double elapsed_ = 0;
    bool paused_ = false;
    std::chrono::steady_clock::time_point last_{};
    std::uint64_t generation_ = 0;  // bumps on stop, so a pending tick of an old motion idles
    std::shared_ptr<int> alive_ = std::make_shared<int>(0);  // for reports posted late
};

}  // namespace skillcell::devices
