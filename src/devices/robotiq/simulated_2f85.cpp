#include "devices/robotiq/simulated_2f85.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices::robotiq {

void Simulated2F85::write(const Command& command, double now) {
    advance(now);
    const Command previous = command_;
    command_ = command;
    if (!command.activate) {
        // rACT = 0 resets the gripper: it stops and forgets its activation.
        activation_ = ActivationStatus::Reset;
        moving_ = false;
        motionPending_ = false;
        fault_ = command.go ? Fault::ActivationBitNotSet : Fault::None;
        return;
    }
    if (!previous.activate) {
        activation_ = ActivationStatus::Activating;
        activatedAt_ = now_ + kActivationTime;
        fault_ = Fault::None;
    }
    if (!command.go) {
        moving_ = false;  // rGTO = 0 stops the fingers where they are
        motionPending_ = false;
        return;
    }
    const bool newRequest = !previous.go || previous.position != command.position ||
                            previous.speed != command.speed || previous.force != command.force;
    if (!newRequest) return;
    if (activation_ != ActivationStatus::Active) {
        fault_ = Fault::ActionDelayed;
        motionPending_ = true;
        return;
    }
    startMotion(now_);
}

void Simulated2F85::startHolding(const ObjectBetweenFingers& object) {
    const double width = std::clamp(object.width, 0.0, kStroke);
    command_ = Command{.activate = true, .go = true, .position = 255, .speed = 255, .force = 255};
    activation_ = ActivationStatus::Active;
    fault_ = Fault::None;
    position_ = 255.0 * (1.0 - width / kStroke);
    from_ = stopAt_ = position_;
    moving_ = false;
    object_ = ObjectStatus::ContactClosing;
    holding_ = object.id;
}

void Simulated2F85::startMotion(double now) {
    motionPending_ = false;
    fault_ = Fault::None;
    from_ = position_;
    const double target = command_.position;
    unitsPerSecond_ = speedOf(command_.speed) / kStroke * 255.0;
    startedAt_ = now;
    stopAt_ = target;
    contactWith_.reset();
    if (target < position_ && !holding_.empty()) {
        // Opening lets go of what the fingers held.
        events_.push_back({FingerEvent::Kind::Released, holding_});
        holding_.clear();
    }
    waitingForWorld_ = false;
    if (target > position_) {
        const Probed probed = probe_ ? probe_() : Probed();
        waitingForWorld_ = !probed.known;
        meet(probed.object, target);
    }
    moving_ = true;
    object_ = ObjectStatus::Moving;
    advance(now);
}

void Simulated2F85::meet(const std::optional<ObjectBetweenFingers>& object, double target) {
    // Only an object narrower than the stroke fits between the fingers.
    if (object && object->width > 0 && object->width <= kStroke) {
        const double contact = 255.0 * (1.0 - object->width / kStroke);
        if (contact < target) {
            stopAt_ = std::max(contact, position_);
            contactWith_ = object->id;
        }
    }
}

void Simulated2F85::advance(double now) {
    now_ = std::max(now_, now);
    if (activation_ == ActivationStatus::Activating && now_ >= activatedAt_) {
        activation_ = ActivationStatus::Active;
        position_ = 0;  // activation ends with the fingers open
        if (!holding_.empty()) {
            events_.push_back({FingerEvent::Kind::Released, holding_});
            holding_.clear();
        }
        if (motionPending_) startMotion(activatedAt_);
    }
    if (!moving_) return;
    if (waitingForWorld_) return;  // status() asks again
    const double travelled = unitsPerSecond_ * (now_ - startedAt_);
    const double direction = stopAt_ >= from_ ? 1.0 : -1.0;
    if (travelled >= std::abs(stopAt_ - from_)) {
        position_ = stopAt_;
        moving_ = false;
        if (contactWith_) {
            object_ = ObjectStatus::ContactClosing;
            holding_ = *contactWith_;
            events_.push_back({FingerEvent::Kind::Grasped, holding_});
        } else {
            object_ = ObjectStatus::AtRequestedPosition;
        }
        return;
    }
    position_ = from_ + direction * travelled;
}

Status Simulated2F85::status(double now) {
    if (moving_ && waitingForWorld_) {
        // The fingers start once the world says what lies between them.
        const Probed probed = probe_();
        if (probed.known) {
            waitingForWorld_ = false;
            now_ = std::max(now_, now);
            startedAt_ = now_;
            meet(probed.object, stopAt_);
        }
    }
    advance(now);
    Status s;
    s.activated = command_.activate;
    s.going = command_.go;
    s.activation = activation_;
    s.object =
        command_.go && activation_ == ActivationStatus::Active ? object_ : ObjectStatus::Moving;
    s.fault = fault_;
    s.requestEcho = command_.position;
    s.position = static_cast<std::uint8_t>(std::clamp(std::lround(position_), 0L, 255L));
    // Motor current: a holding grip draws current in proportion to the force.
    s.current = !holding_.empty() ? static_cast<std::uint8_t>(10 + command_.force / 4)
                                  : static_cast<std::uint8_t>(moving_ ? 5 : 0);
    return s;
}

std::vector<FingerEvent> Simulated2F85::takeEvents() {
    std::vector<FingerEvent> out;
    out.swap(events_);
    return out;
}

}  // namespace skillcell::devices::robotiq
