#pragma once
// PeriodicTask: a function called on a thread of its own, again and again, with a pause
// that the function chooses, or at once when woken; for what the dashboard reads with
// blocking calls (the MES's journal, the KB's processes). The destructor stops it and waits
// for the call in progress, which a blocking call bounds by its own timeout.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace skillcell::dashboard {

class PeriodicTask {
public:
    /// Calls `tick` at once, then again each time the pause it returned has passed.
    explicit PeriodicTask(std::function<std::chrono::milliseconds()> tick)
        : tick_(std::move(tick)), thread_([this] { run(); }) {}
    ~PeriodicTask() {
        {
            const std::lock_guard lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        thread_.join();
    }
    /// Ends the current pause at once (any thread); a wake during a call makes the next
    /// call follow it without a pause.
    void wake() {
        {
            const std::lock_guard lock(mutex_);
            woken_ = true;
        }
        wake_.notify_all();
    }
    PeriodicTask(const PeriodicTask&) = delete;
    PeriodicTask& operator=(const PeriodicTask&) = delete;

private:
    void run() {
        for (;;) {
            const auto pause = tick_();
            std::unique_lock lock(mutex_);
            wake_.wait_for(lock, pause, [this] { return stop_ || woken_; });
            if (stop_) return;
            woken_ = false;
        }
    }

    std::function<std::chrono::milliseconds()> tick_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    bool woken_ = false;
    std::thread thread_;  // last: it starts once the rest is there
};

}  // namespace skillcell::dashboard
