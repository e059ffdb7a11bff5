#pragma once
// ParallelGripper: what the gripper skills (gripper_skills.hpp) need from a parallel
// gripper. The Robotiq 2F-85 adapter is one implementation; another model offering the
// same skills implements this interface and nothing else changes.
//
// Each operation reports once through `done`, from any thread: nullopt on success, else
// the reason it failed. After halt() the current operation reports nothing.
#include <functional>
#include <optional>
#include <string>

namespace skillcell::devices {

class ParallelGripper {
public:
    using Done = std::function<void(std::optional<std::string> failure)>;

    ParallelGripper() = default;
    virtual ~ParallelGripper() = default;
    ParallelGripper(const ParallelGripper&) = delete;
    ParallelGripper& operator=(const ParallelGripper&) = delete;

    /// Closes until an object stops the fingers; fails when they close on nothing.
    virtual void grasp(Done done) = 0;
    /// Opens fully.
    virtual void release(Done done) = 0;
    /// Moves the fingers to `width` (m) with at most `force` (N); fails when an object
    /// stops them first.
    virtual void moveTo(double width, double force, Done done) = 0;
    virtual void suspend() = 0;
    virtual void resume() = 0;
    virtual void halt() = 0;
};

}  // namespace skillcell::devices
