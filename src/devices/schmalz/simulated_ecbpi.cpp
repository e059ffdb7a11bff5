#include "devices/schmalz/simulated_ecbpi.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices::schmalz {

double SimulatedEcbpi::target() const {
    if (command_.suction && !command_.blowOff) {
        return part_ ? levels_.sealed : levels_.freeFlow;
    }
    return 0;
}

double SimulatedEcbpi::tau() const {
    if (command_.blowOff) return levels_.blowOffTau;
    return command_.suction ? levels_.evacuationTau : levels_.leakTau;
}

void SimulatedEcbpi::advance(double now) {
    if (now <= now_) return;
    // Between writes the vacuum moves monotonically towards its target, so evaluating
    // the switching points only at the end of the interval misses no crossing.
    const double goal = target();
    vacuum_ = goal + (vacuum_ - goal) * std::exp(-(now - now_) / tau());
    now_ = now;
    if (!sp1_ && vacuum_ >= levels_.sp1) sp1_ = true;
    if (sp1_ && vacuum_ < levels_.rp1) sp1_ = false;
    if (!sp2_ && vacuum_ >= levels_.sp2) {
        sp2_ = true;
        if (part_ && !holding_) {
            holding_ = true;
            events_.push_back({CupEvent::Kind::Grasped, *part_});
        }
    }
    if (sp2_ && vacuum_ < levels_.rp2) {
        sp2_ = false;
        if (holding_) {
            holding_ = false;
            events_.push_back({CupEvent::Kind::Released, part_.value_or("")});
        }
    }
    if (!sp3_ && part_ && !command_.suction && vacuum_ < levels_.detached) sp3_ = true;
}

void SimulatedEcbpi::startHolding(std::string part) {
    command_ = EcbpiCommand{};
    command_.suction = true;
    part_ = std::move(part);
    vacuum_ = levels_.sealed;
    sp1_ = sp2_ = true;
    sp3_ = false;
    holding_ = true;
}

void SimulatedEcbpi::write(const EcbpiCommand& command, double now) {
    advance(now);
    const bool suctionStarts = command.suction && !command_.suction;
    command_ = command;
    if (suctionStarts) {
        sp3_ = false;
        if (!holding_) part_ = probe_ ? probe_() : std::nullopt;
    }
}

EcbpiStatus SimulatedEcbpi::status(double now) {
    advance(now);
    EcbpiStatus s;
    s.partPresent = sp2_;
    s.controlReached = sp1_;
    s.partDetached = sp3_;
    s.vacuum = static_cast<std::uint16_t>(std::lround(std::clamp(vacuum_, 0.0, 1000.0)));
    return s;
}

std::vector<CupEvent> SimulatedEcbpi::takeEvents() {
    std::vector<CupEvent> out;
    out.swap(events_);
    return out;
}

}  // namespace skillcell::devices::schmalz
