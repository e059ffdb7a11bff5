#pragma once
// LaggingWorld: the world model as a simulated gripper sees it while the world restarts: each
// event the gripper tells it is heard only after the gripper's registers have been read a
// number of times more (WorldLink::behind, as the simulations ask it on every read), or, while
// it is down (goDown() to comeBack()), only once it is back (WorldLink::waitUntilHeard).
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>

#include "client_thread.hpp"

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
        toldWhileDown_ = toldWhileDown_ || down_;
    }
    /// Asked on each read: whether an event told is not heard yet.
    [[nodiscard]] bool behind() {
        const std::lock_guard lock(mutex_);
        if (toldWhileDown_) return true;
        if (behindFor_ == 0) return false;
        --behindFor_;
        return true;
    }
    /// The world goes down; what is told from now on is heard once it comes back.
    void goDown() {
        const std::lock_guard lock(mutex_);
        down_ = true;
    }
    void comeBack() {
        {
            const std::lock_guard lock(mutex_);
            down_ = false;
            toldWhileDown_ = false;
        }
        back_.notify_all();
    }
    /// Waits until what was told while the world was down is heard, at most `patience`;
    /// whether everything told is heard (as WorldLink::waitUntilHeard: a lag of reads still
    /// to come is not heard yet).
    bool await(std::chrono::milliseconds patience) {
        std::unique_lock lock(mutex_);
        return back_.wait_for(lock, patience, [this] { return !toldWhileDown_; }) &&
               behindFor_ == 0;
    }
    /// How many reads it still lags behind: 0 once it has heard everything told.
    [[nodiscard]] int behindFor() {
        const std::lock_guard lock(mutex_);
        return behindFor_;
    }

private:
    std::mutex mutex_;
    std::condition_variable back_;
    int lagging_ = 0;
    int behindFor_ = 0;
    bool down_ = false;
    bool toldWhileDown_ = false;
};

/// Grasps, then releases, through `grasp` and `release` (on `client`), with `world` lagging
/// `reads` reads behind each event: each skill must end, and end only once the world has
/// heard what it did.
inline void expectEachEndsOnlyOnceHeard(ClientThread& client,
                                        const std::shared_ptr<skills::SkillClient>& grasp,
                                        const std::shared_ptr<skills::SkillClient>& release,
                                        LaggingWorld& world, int reads) {
    using namespace std::chrono_literals;
    world.lagBehind(reads);
    auto outcome = client.invoke(grasp, {}, 20s);
    EXPECT_EQ(outcome.kind, skills::SkillOutcome::Kind::Finished) << outcome.reason;
    EXPECT_EQ(world.behindFor(), 0) << "the grasp ended before the world heard it";
    outcome = client.invoke(release, {}, 20s);
    EXPECT_EQ(outcome.kind, skills::SkillOutcome::Kind::Finished) << outcome.reason;
    EXPECT_EQ(world.behindFor(), 0) << "the release ended before the world heard it";
}

}  // namespace skillcell::test
