#include "devices/dh/ag95_gripper.hpp"

#include <array>
#include <cstdio>

namespace skillcell::devices::dh {
namespace {

std::string millimetres(std::uint16_t perMille) {
    std::array<char, 32> buf{};
    std::snprintf(buf.data(), buf.size(), "%.1f mm", widthOf(perMille) * 1000);
    return buf.data();
}

}  // namespace

std::unique_ptr<Ag95Gripper> Ag95Gripper::start(std::unique_ptr<ModbusRtuMaster> line,
                                                Ag95GripperOptions options) {
    return std::make_unique<Ag95Gripper>(Token{}, std::move(line), options);
}

void Ag95Gripper::submit(Goal goal, std::uint16_t target, std::uint16_t force, Done done) {
    worker_.submit([this, goal, target,
                    force](Control& control) { return execute(goal, target, force, control); },
                   std::move(done),
                   [this] {
                       // Halted: the fingers stay where they are.
                       if (const auto state = read()) (void)write(kPosition, state->position);
                   });
}

void Ag95Gripper::grasp(Done done) {
    submit(Goal::Grasp, 0, forcePercentOf(options_.graspForce), std::move(done));
}
void Ag95Gripper::release(Done done) {
    submit(Goal::Release, 1000, forcePercentOf(options_.graspForce), std::move(done));
}
void Ag95Gripper::moveTo(double width, double force, Done done) {
    submit(Goal::Move, perMilleOf(width), forcePercentOf(force), std::move(done));
}

ua::Result<Ag95Gripper::State> Ag95Gripper::read() {
    std::array<std::uint16_t, 3> r{};
    if (const auto s = line_->readHoldingRegisters(kInitialisationState, r); s.isBad()) return s;
    return State{static_cast<InitialisationState>(r[0]), static_cast<GripperState>(r[1]), r[2]};
}

ua::StatusCode Ag95Gripper::write(std::uint16_t address, std::uint16_t value) {
    const std::array<std::uint16_t, 1> one{value};
    return line_->writeRegisters(address, one);
}

std::optional<std::string> Ag95Gripper::initialise(Control& control) {
    auto state = read();
    if (!state) return lineError();
    if (state->initialisation == InitialisationState::Initialised) return std::nullopt;
    if (state->initialisation == InitialisationState::NotInitialised &&
        write(kInitialise, 1).isBad()) {
        return lineError();
    }
    const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        if (!control.pause()) return std::nullopt;
        state = read();
        if (!state) return lineError();
        if (state->initialisation == InitialisationState::Initialised) return std::nullopt;
    }
    return std::string("the gripper did not complete its initialisation");
}

std::optional<std::string> Ag95Gripper::travel(std::uint16_t target, Control& control,
                                               State& stopped) {
    if (write(kPosition, target).isBad()) return lineError();
    bool holding = false;  // suspended: the fingers were asked to stay where they are
    const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
    for (;;) {
        if (!control.pause()) return std::nullopt;
        const auto state = read();
        if (!state) return lineError();
        if (control.suspended() != holding) {
            holding = control.suspended();
            if (write(kPosition, holding ? state->position : target).isBad()) return lineError();
            continue;
        }
        if (holding) continue;  // a suspended operation has no deadline
        if (std::chrono::steady_clock::now() > deadline) {
            return std::string("the fingers did not stop in time");
        }
        if (state->gripper != GripperState::Moving) {
            stopped = *state;
            return std::nullopt;
        }
    }
}

std::optional<std::string> Ag95Gripper::execute(Goal goal, std::uint16_t target,
                                                std::uint16_t force, Control& control) {
    if (auto failure = initialise(control); failure || control.abandoned()) return failure;
    if (write(kForce, force).isBad() || write(kSpeed, speedPercentOf(options_.speed)).isBad()) {
        return lineError();
    }
    State stopped{};
    if (goal == Goal::Grasp) {
        // Fingers that are not open cannot close around anything: open them first.
        const auto state = read();
        if (!state) return lineError();
        if (state->position < kOpenEnough) {
            if (auto failure = travel(1000, control, stopped); failure) return failure;
            if (control.abandoned()) return std::nullopt;
            if (stopped.gripper != GripperState::AtPosition) {
                return "the fingers were blocked while opening at " + millimetres(stopped.position);
            }
        }
    }
    if (auto failure = travel(target, control, stopped); failure) return failure;
    if (control.abandoned()) return std::nullopt;
    const std::string where = millimetres(stopped.position);
    if (stopped.gripper == GripperState::Dropped) return "the object was dropped at " + where;
    const bool caught = stopped.gripper == GripperState::Caught;
    switch (goal) {
        case Goal::Grasp:
            if (caught) return std::nullopt;
            return "no object between the fingers: they closed to " + where;
        case Goal::Release:
            if (!caught) return std::nullopt;
            return "the fingers were blocked while opening at " + where;
        case Goal::Move:
            if (!caught) return std::nullopt;
            return "an object stopped the fingers at " + where + " before " + millimetres(target);
    }
    return std::string("unknown operation");
}

}  // namespace skillcell::devices::dh
