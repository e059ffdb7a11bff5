#pragma once
// ArmController: what the move skills need from a robot arm: its joint positions, and
// executing a planned trajectory that can be paused, resumed and stopped. The simulated
// UR5 (simulated_arm.hpp) is one implementation; a driver for the real controller would
// be another, and the move skills would not change.
//
// Threading: the owner's io_context thread only; `done` runs there too.
#include <functional>
#include <optional>
#include <string>

#include "devices/arm/trajectory.hpp"

namespace skillcell::devices {

class ArmController {
public:
    /// nullopt: the trajectory's end was reached; else the fault that ended it early.
    using Done = std::function<void(std::optional<std::string> fault)>;

    ArmController() = default;
    virtual ~ArmController() = default;
    ArmController(const ArmController&) = delete;
    ArmController& operator=(const ArmController&) = delete;

    [[nodiscard]] virtual Joints joints() const = 0;
    [[nodiscard]] virtual bool busy() const = 0;
    /// Starts `trajectory` (which begins at joints()); false when the arm is busy.
    virtual bool execute(Trajectory trajectory, Done done) = 0;
    /// Holds the motion where it is; resume() continues it.
    virtual void pause() = 0;
    virtual void resume() = 0;
    /// Ends the motion where it is; its `done` is not called.
    virtual void stop() = 0;
};

}  // namespace skillcell::devices
