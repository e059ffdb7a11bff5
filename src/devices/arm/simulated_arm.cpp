#include "devices/arm/simulated_arm.hpp"

#include <algorithm>
#include <asio/post.hpp>

#include <fmt/format.h>

namespace skillcell::devices {

SimulatedArm::SimulatedArm(const asio::any_io_executor& executor, SimulatedArmOptions options,
                           Observer observer)
    : timer_(executor),
      options_(std::move(options)),
      observer_(std::move(observer)),
      joints_(options_.initial) {}

SimulatedArm::~SimulatedArm() {
    timer_.cancel();
}

std::chrono::steady_clock::time_point SimulatedArm::now() const {
    return options_.clock ? options_.clock() : std::chrono::steady_clock::now();
}

bool SimulatedArm::execute(Trajectory trajectory, Done done) {
    if (trajectory_) return false;
    trajectory_ = std::move(trajectory);
    done_ = std::move(done);
    elapsed_ = 0;
    paused_ = false;
    last_ = now();
    arm();
    return true;
}

void SimulatedArm::arm() {
    const bool sensing = trajectory_ && trajectory_->forceLimit() > 0;
    timer_.expires_after(sensing ? std::min(options_.tick, kForceTick) : options_.tick);
    timer_.async_wait([this, generation = generation_](const std::error_code& ec) {
        if (ec || generation != generation_) return;
        tick();
    });
}

double SimulatedArm::forceLimit() const {
    return options_.contactForce && trajectory_ ? trajectory_->forceLimit() : 0;
}

double SimulatedArm::simulatedSince(std::chrono::steady_clock::time_point t) const {
    const double dt = std::chrono::duration<double>(t - last_).count() * options_.speed;
    // A force-limited motion advances one sample at most per step, as its control loop runs.
    return forceLimit() > 0 ? std::min(dt, kForceSamplePeriod) : dt;
}

void SimulatedArm::tick() {
    if (!trajectory_) return;
    const auto t = now();
    const double limit = forceLimit();
    const double dt = simulatedSince(t);
    last_ = t;
    // A force sensor's latency is fixed; the simulated one is a round trip to the world
    // model, which a loaded machine stretches. So the motion waits, in simulated time,
    // while more than the newest sample is unmeasured: it never runs deeper into contact
    // than the sampling allows, however slow the round trip.
    const bool waitForSensing = limit > 0 && options_.unmeasuredSamples &&
                                options_.unmeasuredSamples() > kForceSamplesInFlight;
    if (!paused_ && !waitForSensing) {
        elapsed_ += dt;
        joints_ = trajectory_->at(elapsed_);
    }
    if (observer_ && !waitForSensing) observer_(joints_);
    // A force-limited motion stops where its tool meets more than its limit (the measured
    // force lags the motion by the sensing's round trip, as a real arm's filter does).
    if (limit > 0) {
        if (const double force = options_.contactForce(); force > limit) {
            abort(forceFault(force, limit));
            return;
        }
    }
    if (!paused_ && !waitForSensing && elapsed_ >= trajectory_->duration()) {
        joints_ = trajectory_->end();
        trajectory_.reset();
        elapsed_ = 0;
        Done done = std::move(done_);
        done_ = {};
        if (!done) return;
        if (!options_.beforeDone) {
            done(std::nullopt);
            return;
        }
        // Report on this thread once the hook allows it, unless the arm is gone by then; a
        // force-limited motion by the force measured at its end.
        options_.beforeDone([this, limit, executor = timer_.get_executor(),
                             alive = std::weak_ptr<int>(alive_), done = std::move(done)]() mutable {
            asio::post(executor, [this, limit, alive, done = std::move(done)] {
                if (!alive.lock()) return;
                const double force = limit > 0 ? options_.contactForce() : 0;
                done(force > limit && limit > 0 ? std::optional(forceFault(force, limit))
                                                : std::nullopt);
            });
        });
        return;
    }
    arm();
}

std::string SimulatedArm::forceFault(double force, double limit) {
    return fmt::format("the contact force {:.1f} N exceeded the limit of {:.1f} N; the arm stopped",
                       force, limit);
}

void SimulatedArm::abort(const std::string& fault) {
    Done done = std::move(done_);
    stop();
    if (done) done(fault);
}

void SimulatedArm::pause() {
    if (!trajectory_ || paused_) return;
    tick();  // account for the time up to now before freezing (it may end the motion)
    if (trajectory_) paused_ = true;
}

void SimulatedArm::resume() {
    if (!trajectory_ || !paused_) return;
    paused_ = false;
    last_ = now();  // the pause does not count as motion time
}

void SimulatedArm::stop() {
    if (!trajectory_) return;
    if (!paused_) {
        elapsed_ += simulatedSince(now());
        joints_ = trajectory_->at(elapsed_);
    }
    ++generation_;
    timer_.cancel();
    trajectory_.reset();
    done_ = {};
    elapsed_ = 0;
    paused_ = false;
    if (observer_) observer_(joints_);
}

}  // namespace skillcell::devices
