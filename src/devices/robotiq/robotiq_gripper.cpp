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
    auto gripper = std::make_unique<RobotiqGripper>(Token{}, std::move(client), options);
    gripper->thread_ = std::thread([g = gripper.get()] { g->run(); });
    return gripper;
}

RobotiqGripper::~RobotiqGripper() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        ++generation_;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void RobotiqGripper::submit(Goal goal, std::uint8_t position, std::uint8_t force, Done done) {
    Command c;
    c.activate = true;
    c.go = true;
    c.position = position;
    c.speed = speedFor(options_.speed);
    c.force = force;
    {
        std::lock_guard lock(mutex_);
        pending_ = Job{goal, c, std::move(done)};
        suspended_ = false;
    }
    cv_.notify_all();
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

void RobotiqGripper::suspend() {
    {
        std::lock_guard lock(mutex_);
        suspended_ = true;
    }
    cv_.notify_all();
}
void RobotiqGripper::resume() {
    {
        std::lock_guard lock(mutex_);
        suspended_ = false;
    }
    cv_.notify_all();
}
void RobotiqGripper::halt() {
    {
        std::lock_guard lock(mutex_);
        ++generation_;
        pending_.reset();
        suspended_ = false;
    }
    cv_.notify_all();
}

bool RobotiqGripper::pause(std::uint64_t generation) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, options_.poll, [&] { return generation_ != generation; });
    return generation_ == generation;
}

void RobotiqGripper::run() {
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [this] { return stopping_ || pending_.has_value(); });
            if (stopping_) return;
            job = std::move(*pending_);
            pending_.reset();
        }
        bool abandoned = false;
        auto failure = execute(job, abandoned);
        if (abandoned) {
            // Halted: stop the fingers where they are; the run reports nothing.
            Command stop = job.command;
            stop.go = false;
            (void)client_->write(stop);
            continue;
        }
        job.done(std::move(failure));
    }
}

std::optional<std::string> RobotiqGripper::activate(bool& abandoned) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mutex_);
        generation = generation_;
    }
    auto status = client_->read();
    if (!status) return "serial line: " + client_->lastError();
    if (status->activation == ActivationStatus::Active && status->activated) return std::nullopt;
    // The manual's activation sequence: clear rACT, then set it.
    if (client_->write(Command{}).isBad() || client_->write(Command{.activate = true}).isBad()) {
        return "serial line: " + client_->lastError();
    }
    const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        if (!pause(generation)) {
            abandoned = true;
            return std::nullopt;
        }
        status = client_->read();
        if (!status) return "serial line: " + client_->lastError();
        if (status->activation == ActivationStatus::Active) return std::nullopt;
    }
    return std::string("the gripper did not complete its activation");
}

std::variant<Status, std::string> RobotiqGripper::travel(const Command& command,
                                                         std::uint64_t generation,
                                                         bool& abandoned) {
    if (client_->write(command).isBad()) return "serial line: " + client_->lastError();
    bool holding = false;  // suspended: rGTO = 0 written
    const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
    for (;;) {
        if (!pause(generation)) {
            abandoned = true;
            return Status{};
        }
        bool suspended = false;
        {
            std::lock_guard lock(mutex_);
            suspended = suspended_;
        }
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

std::optional<std::string> RobotiqGripper::execute(const Job& job, bool& abandoned) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mutex_);
        generation = generation_;
    }
    if (auto failure = activate(abandoned); failure || abandoned) return failure;
    if (job.goal == Goal::Grasp) {
        // Fingers that are not open cannot close around anything: open them first.
        const auto status = client_->read();
        if (!status) return "serial line: " + client_->lastError();
        if (status->position > kOpenEnough) {
            Command open = job.command;
            open.position = 0;
            auto opened = travel(open, generation, abandoned);
            if (auto* why = std::get_if<std::string>(&opened)) return *why;
            if (abandoned) return std::nullopt;
            if (std::get<Status>(opened).object != ObjectStatus::AtRequestedPosition) {
                return "the fingers were blocked while opening at " +
                       millimetres(std::get<Status>(opened).position);
            }
        }
    }
    auto stopped = travel(job.command, generation, abandoned);
    if (auto* why = std::get_if<std::string>(&stopped)) return *why;
    if (abandoned) return std::nullopt;
    const Status& status = std::get<Status>(stopped);
    const std::string where = millimetres(status.position);
    switch (job.goal) {
        case Goal::Grasp:
            if (status.object == ObjectStatus::ContactClosing) return std::nullopt;
            return "no object between the fingers: they closed to " + where;
        case Goal::Release:
            if (status.object == ObjectStatus::AtRequestedPosition) return std::nullopt;
            return "the fingers were blocked while opening at " + where;
        case Goal::Move:
            if (status.object == ObjectStatus::AtRequestedPosition) return std::nullopt;
            return "an object stopped the fingers at " + where + " before " +
                   millimetres(job.command.position);
    }
    return std::string("unknown operation");
}

}  // namespace skillcell::devices::robotiq
