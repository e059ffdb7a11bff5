#include "devices/robotiq/robotiq_gripper.hpp"

#include <cstdio>
#include <variant>

namespace skillcell::devices::robotiq {
namespace {

std::string millimetres(std::uint8_t position) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f mm", widthOf(position) * 1000);
    return buf;
}

}  // namespace

std::unique_ptr<RobotiqGripper> RobotiqGripper::start(std::unique_ptr<RobotiqClient> client,
                                                      RobotiqGripperOptions options) {
    return std::make_unique<RobotiqGripper>(Token{}, std::move(client), options);
}

void RobotiqGripper::submit(Goal goal, std::uint8_t position, std::uint8_t force, Done done) {
    Command c;
    c.activate = true;
    c.go = true;
    c.position = position;
    c.speed = speedFor(options_.speed);
    c.force = force;
    worker_.submit([this, goal, c](Control& control) { return execute(goal, c, control); },
                   std::move(done),
                   [this, c] {
                       // Halted: stop the fingers where they are.
                       Command stop = c;
                       stop.go = false;
                       (void)client_->write(stop);
                   });
}

void RobotiqGripper::grasp(Done done) {
    submit(Goal::Grasp, 255, forceFor(options_.graspForce), std::move(done));
}
void RobotiqGripper::release(Done done) {
    submit(Goal::Release, 0, forceFor(options_.graspForce), std::move(done));
}
void RobotiqGripper::moveTo(double width, double force, Done done) {
    submit(Goal::Move, positionFor(width), forceFor(force), std::move(done));
}

std::optional<std::string> RobotiqGripper::activate(Control& control) {
    auto status = client_->read();
    if (!status) return "serial line: " + client_->lastError();
    if (status->activation == ActivationStatus::Active && status->activated) return std::nullopt;
    // The manual's activation sequence: clear rACT, then set it.
    if (client_->write(Command{}).isBad() || client_->write(Command{.activate = true}).isBad()) {
        return "serial line: " + client_->lastError();
    }
    const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        if (!control.pause()) return std::nullopt;
        status = client_->read();
        if (!status) return "serial line: " + client_->lastError();
        if (status->activation == ActivationStatus::Active) return std::nullopt;
    }
    return std::string("the gripper did not complete its activation");
}

std::variant<Status, std::string> RobotiqGripper::travel(const Command& command, Control& control) {
    if (client_->write(command).isBad()) return "serial line: " + client_->lastError();
    bool holding = false;  // suspended: rGTO = 0 written
    const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
    for (;;) {
        if (!control.pause()) return Status{};
        const bool suspended = control.suspended();
        if (suspended != holding) {
            Command c = command;
            c.go = !suspended;
            if (client_->write(c).isBad()) return "serial line: " + client_->lastError();
            holding = suspended;
        }
        if (holding) continue;  // a suspended operation has no deadline
        if (std::chrono::steady_clock::now() > deadline) {
            return std::string("the fingers did not stop in time");
        }
        const auto status = client_->read();
        if (!status) return "serial line: " + client_->lastError();
        if (status->fault != Fault::None && status->fault != Fault::ActionDelayed) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "gripper fault 0x%02X",
                          static_cast<unsigned>(status->fault));
            return std::string(buf);
        }
        if (status->going && status->requestEcho == command.position &&
            status->object != ObjectStatus::Moving) {
            return *status;
        }
    }
}

std::optional<std::string> RobotiqGripper::execute(Goal goal, const Command& command,
                                                   Control& control) {
    if (auto failure = activate(control); failure || control.abandoned()) return failure;
    if (goal == Goal::Grasp) {
        // Fingers that are not open cannot close around anything: open them first.
        const auto status = client_->read();
        if (!status) return "serial line: " + client_->lastError();
        if (status->position > kOpenEnough) {
            Command open = command;
            open.position = 0;
            auto opened = travel(open, control);
            if (auto* why = std::get_if<std::string>(&opened)) return *why;
            if (control.abandoned()) return std::nullopt;
            if (std::get<Status>(opened).object != ObjectStatus::AtRequestedPosition) {
                return "the fingers were blocked while opening at " +
                       millimetres(std::get<Status>(opened).position);
            }
        }
    }
    auto stopped = travel(command, control);
    if (auto* why = std::get_if<std::string>(&stopped)) return *why;
    if (control.abandoned()) return std::nullopt;
    const Status& status = std::get<Status>(stopped);
    const std::string where = millimetres(status.position);
    switch (goal) {
        case Goal::Grasp:
            if (status.object == ObjectStatus::ContactClosing) return std::nullopt;
            return "no object between the fingers: they closed to " + where;
        case Goal::Release:
            if (status.object == ObjectStatus::AtRequestedPosition) return std::nullopt;
            return "the fingers were blocked while opening at " + where;
        case Goal::Move:
            if (status.object == ObjectStatus::AtRequestedPosition) return std::nullopt;
            return "an object stopped the fingers at " + where + " before " +
                   millimetres(command.position);
    }
    return std::string("unknown operation");
}

}  // namespace skillcell::devices::robotiq
