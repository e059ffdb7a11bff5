#pragma once
// LaggingWorld: the world model as a simulated gripper sees it while the world restarts: each
// event the gripper tells it is heard only after the gripper's registers have been read a
// number of times more (WorldLink::behind, as the simulations ask it on every read).
#include <mutex>

namespace skillcell::test {

class LaggingWorld {
public:
    /// From now on each event is heard only after `reads` more reads.
    void lagBehind(int reads) {
        const std::lock_guard lock(mutex_);
        lagging_ = reads;
    }
    /// The gripper told an event.
    void told() {
        const std::lock_guard lock(mutex_);
        behindFor_ = lagging_;
    }
    /// Asked on each read: whether an event told is not heard yet.
    [[nodiscard]] bool behind() {
        const std::lock_guard lock(mutex_);
        if (behindFor_ == 0) return false;
        --behindFor_;
        return true;
    }
    /// How many reads it still lags behind: 0 once it has heard everything told.
    [[nodiscard]] int behindFor() {
        const std::lock_guard lock(mutex_);
        return behindFor_;
    }

private:
    std::mutex mutex_;
    int lagging_ = 0;
    int behindFor_ = 0;
};

}  // namespace skillcell::test
