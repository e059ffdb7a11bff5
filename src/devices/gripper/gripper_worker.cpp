#include "devices/gripper/gripper_worker.hpp"

namespace skillcell::devices {

bool GripperWorker::Control::pause() {
    std::unique_lock lock(worker_.mutex_);
    worker_.cv_.wait_for(lock, worker_.poll_,
                         [this] { return worker_.generation_ != generation_; });
    suspended_ = worker_.suspended_;
    abandoned_ = worker_.generation_ != generation_;
    return !abandoned_;
}

GripperWorker::GripperWorker(std::chrono::milliseconds poll)
    : poll_(poll), thread_([this] { run(); }) {}

GripperWorker::~GripperWorker() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        ++generation_;
    }
    cv_.notify_all();
    thread_.join();
}

void GripperWorker::submit(Body body, Gripper::Done done, std::function<void()> onAbandoned) {
    {
        std::lock_guard lock(mutex_);
        pending_ = Operation{std::move(body), std::move(done), std::move(onAbandoned)};
        suspended_ = false;
    }
    cv_.notify_all();
}

void GripperWorker::suspend() {
    {
        std::lock_guard lock(mutex_);
        suspended_ = true;
    }
    cv_.notify_all();
}

void GripperWorker::resume() {
    {
        std::lock_guard lock(mutex_);
        suspended_ = false;
    }
    cv_.notify_all();
}

void GripperWorker::halt() {
    {
        std::lock_guard lock(mutex_);
        ++generation_;
        pending_.reset();
        suspended_ = false;
    }
    cv_.notify_all();
}

void GripperWorker::run() {
    for (;;) {
        Operation operation;
        std::uint64_t generation = 0;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [this] { return stopping_ || pending_.has_value(); });
            if (stopping_) return;
            operation = std::move(*pending_);
            pending_.reset();
            generation = generation_;
        }
        Control control(*this, generation);
        auto failure = operation.body(control);
        if (control.abandoned()) {
            if (operation.onAbandoned) operation.onAbandoned();
            continue;
        }
        operation.done(std::move(failure));
    }
}

}  // namespace skillcell::devices
