#include "devices/dh/simulated_ag95.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices::dh {

SimulatedAg95::SimulatedAg95(Token, SimulatedAg95Options options) : options_(std::move(options)) {
    epoch_ = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
    if (const auto& held = options_.holding) {
        initialisation_ = InitialisationState::Initialised;
        perMille_ = std::clamp(held->width / kStroke * 1000, 0.0, 1000.0);
        state_ = GripperState::Caught;
        holding_ = held->id;
    }
}

std::unique_ptr<SimulatedAg95> SimulatedAg95::open(SimulatedAg95Options options, std::string* why) {
    auto gripper = std::make_unique<SimulatedAg95>(Token{}, std::move(options));
    ModbusRegisterMap map;
    map.slaveId = kSlaveId;
    map.baudRate = kBaudRate;
    map.holdingStart = kFirstRegister;
    map.holdingCount = kRegisterCount;
    gripper->port_ = PtyModbusSlave::open(map, *gripper, why);
    if (!gripper->port_) return nullptr;
    return gripper;
}

SimulatedAg95::~SimulatedAg95() {
    port_.reset();  // no request reaches the gripper from here on
}

double SimulatedAg95::now() const {
    const auto t = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
    return std::chrono::duration<double>(t - epoch_).count() * options_.speed;
}

double SimulatedAg95::width() {
    std::lock_guard lock(mutex_);
    advance(now());
    return widthOf(perMille_);
}

void SimulatedAg95::advance(double t) {
    now_ = std::max(now_, t);
    if (initialisation_ == InitialisationState::Initialising && now_ >= initialisedAt_) {
        initialisation_ = InitialisationState::Initialised;
        perMille_ = 1000;  // it found its zero fully open
        state_ = GripperState::AtPosition;
    }
    if (!moving_ || waitingForWorld_) return;  // present() asks the world again
    const double rate = speed_ / 100.0 * kMaximumSpeed / kStroke * 1000;  // per mille / s
    const double travelled = (now_ - startedAt_) * rate;
    const double distance = std::abs(stopAt_ - from_);
    if (travelled < distance) {
        perMille_ = from_ + std::copysign(travelled, stopAt_ - from_);
        return;
    }
    perMille_ = stopAt_;
    moving_ = false;
    if (contactWith_) {
        state_ = GripperState::Caught;
        holding_ = *contactWith_;
        events_.push_back({FingerEvent::Kind::Grasped, holding_});
    } else {
        state_ = GripperState::AtPosition;
    }
}

void SimulatedAg95::startMotion(double target, double t) {
    advance(t);
    if (!holding_.empty() && target > perMille_) {
        events_.push_back({FingerEvent::Kind::Released, holding_});
        holding_.clear();
    }
    contactWith_.reset();
    stopAt_ = target;
    waitingForWorld_ = false;
    if (target < perMille_ && options_.probe) {
        const Probed probed = options_.probe();
        waitingForWorld_ = !probed.known;
        meet(probed.object, target);
    }
    from_ = perMille_;
    startedAt_ = now_;
    moving_ = true;
    state_ = GripperState::Moving;
    advance(t);  // a motion to where the fingers are ends at once
}

void SimulatedAg95::meet(const std::optional<ObjectBetweenFingers>& object, double target) {
    // Closing: an object narrower than the gap stops the fingers at its width.
    if (!object) return;
    const double at = object->width / kStroke * 1000;
    if (at < perMille_ && at > target) {
        stopAt_ = at;
        contactWith_ = object->id;
    }
}

void SimulatedAg95::report(const std::vector<FingerEvent>& events) const {
    for (const auto& e : events) {
        if (options_.onEvent) options_.onEvent(e);
    }
}

void SimulatedAg95::present(std::span<std::uint16_t> holding, std::span<std::uint16_t>) {
    // Grasps and releases reach the world before the reply that shows them; while the world
    // has not heard one yet (it restarts), the fingers show as still moving.
    std::vector<FingerEvent> events;
    {
        std::lock_guard lock(mutex_);
        const double t = now();
        if (moving_ && waitingForWorld_) {
            // The fingers start once the world says what lies between them.
            const Probed probed = options_.probe();
            if (probed.known) {
                waitingForWorld_ = false;
                now_ = std::max(now_, t);
                startedAt_ = now_;
                meet(probed.object, stopAt_);
            }
        }
        advance(t);
        holding[kInitialisationState - kFirstRegister] =
            static_cast<std::uint16_t>(initialisation_);
        holding[kGripperState - kFirstRegister] = static_cast<std::uint16_t>(state_);
        holding[kPositionNow - kFirstRegister] = static_cast<std::uint16_t>(std::lround(perMille_));
        events.swap(events_);
    }
    report(events);
    if (options_.worldBehind && options_.worldBehind()) {
        holding[kGripperState - kFirstRegister] = static_cast<std::uint16_t>(GripperState::Moving);
    }
}

void SimulatedAg95::written(std::uint16_t address, std::uint16_t count,
                            std::span<const std::uint16_t> holding) {
    auto wrote = [&](std::uint16_t reg) { return reg >= address && reg < address + count; };
    auto value = [&](std::uint16_t reg) { return holding[reg - kFirstRegister]; };
    std::vector<FingerEvent> events;
    {
        std::lock_guard lock(mutex_);
        const double t = now();
        advance(t);
        if (wrote(kSpeed)) speed_ = std::clamp<std::uint16_t>(value(kSpeed), 1, 100);
        if (wrote(kInitialise) && value(kInitialise) == 1 &&
            initialisation_ != InitialisationState::Initialising) {
            initialisation_ = InitialisationState::Initialising;
            initialisedAt_ = now_ + kInitialisationTime;
            moving_ = false;
            holding_.clear();
        }
        // Ignored until initialised, as the gripper does.
        if (wrote(kPosition) && initialisation_ == InitialisationState::Initialised) {
            startMotion(std::min<std::uint16_t>(value(kPosition), 1000), t);
        }
        events.swap(events_);
    }
    report(events);
}

}  // namespace skillcell::devices::dh
