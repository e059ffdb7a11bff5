#pragma once
// Simulated2F85: the behaviour of a Robotiq 2F-85 behind its registers, as a plain value
// fed commands and simulated time (seconds): activation takes kActivationTime and leaves
// the fingers open; a motion runs at the requested speed towards the requested position;
// closing on an object whose width lies within the stroke stops the fingers at that
// width with gOBJ = 2 (object detected while closing), reaching the requested position
// gives gOBJ = 3. rGTO without rACT is fault 0x07; an action requested while activating
// waits for the activation (fault 0x05 meanwhile). The object between the fingers comes
// from a probe asked when a motion starts (the world model, in the cell).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "devices/gripper/fingers.hpp"
#include "devices/robotiq/robotiq_registers.hpp"

namespace skillcell::devices::robotiq {

using devices::FingerEvent;
using devices::ObjectBetweenFingers;
using devices::Probed;

class Simulated2F85 {
public:
    using Probe = std::function<Probed()>;
    static constexpr double kActivationTime = 1.0;  // s

    explicit Simulated2F85(Probe probe = {}) : probe_(std::move(probe)) {}

    /// Powered, activated and closed on `object`: the gripper as its adapter finds it when the
    /// adapter restarts while the fingers hold a part (the world model says they do). A real
    /// 2F-85 keeps its activation and its grip while its controller's client restarts.
    void startHolding(const ObjectBetweenFingers& object);
    /// The robot wrote the command registers at time `now`.
    void write(const Command& command, double now);
    /// The status registers at time `now` (time only moves forward).
    [[nodiscard]] Status status(double now);
    /// Grasps and releases since the last call, oldest first.
    [[nodiscard]] std::vector<FingerEvent> takeEvents();
    /// The finger position (0 open .. 255 closed, fractional while moving).
    [[nodiscard]] double position() const { return position_; }
    [[nodiscard]] const Command& command() const { return command_; }

private:
    void advance(double now);
    void startMotion(double now);
    /// Where the closing fingers stop, from what the probe found.
    void meet(const std::optional<ObjectBetweenFingers>& object, double target);

    Probe probe_;
    Command command_;
    ActivationStatus activation_ = ActivationStatus::Reset;
    double activatedAt_ = 0;
    Fault fault_ = Fault::None;
    double position_ = 0;
    // The motion in progress.
    bool moving_ = false;
    double from_ = 0;
    double stopAt_ = 0;  // the requested position, or where the object stops the fingers
    double startedAt_ = 0;
    double unitsPerSecond_ = 1;
    std::optional<std::string> contactWith_;  // the object the motion will meet
    bool waitingForWorld_ = false;            // the probe could not say yet: not moving
    ObjectStatus object_ = ObjectStatus::Moving;
    bool motionPending_ = false;  // requested while activating
    std::string holding_;
    std::vector<FingerEvent> events_;
    double now_ = 0;
};

}  // namespace skillcell::devices::robotiq
