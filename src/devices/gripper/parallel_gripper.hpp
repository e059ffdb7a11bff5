#pragma once
// Gripper and ParallelGripper: what the gripper skills (gripper_skills.hpp) need from a
// gripper. The Robotiq 2F-85 adapter is a ParallelGripper, the Schmalz ECBPi adapter a
// Gripper; another model offering the same skills implements one of these and nothing
// else changes.
//
// Each operation reports once through `done`, from any thread: nullopt on success, else
// the reason it failed. After halt() the current operation reports nothing.
#include <functional>
#include <optional>
#include <string>

namespace skillcell::devices {

/// What a gripper can hold, from its maker's ratings: what its skills publish (MaxPayload,
/// MaxGripWidth) for the MES to choose a gripper that suits an object.
struct GripperRating {
    double maxPayload = 0;    // kg
    double maxGripWidth = 0;  // m across the fingers; 0: width does not limit it (vacuum)
};

class Gripper {
public:
    using Done = std::function<void(std::optional<std::string> failure)>;

    Gripper() = default;
    virtual ~Gripper() = default;
    Gripper(const Gripper&) = delete;
    Gripper& operator=(const Gripper&) = delete;

    /// Takes hold of the object at the grip point; fails when there is none.
    virtual void grasp(Done done) = 0;
    /// Lets go.
    virtual void release(Done done) = 0;
    virtual void suspend() = 0;
    virtual void resume() = 0;
    virtual void halt() = 0;
    [[nodiscard]] virtual GripperRating rating() const = 0;
};

class ParallelGripper : public Gripper {
public:
    /// Moves the fingers to `width` (m) with at most `force` (N); fails when an object
    /// stops them first.
    virtual void moveTo(double width, double force, Done done) = 0;
};

}  // namespace skillcell::devices
