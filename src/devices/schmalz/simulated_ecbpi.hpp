#pragma once
// SimulatedEcbpi: a Schmalz ECBPi electric vacuum generator behind its IO-Link process
// data, as a plain value fed commands and simulated time (seconds). With suction on, the
// system vacuum approaches 750 mbar when a part seals the cup and the free-flow vacuum
// (60 mbar) when none does, exponentially (evacuation time constant 80 ms); blow-off
// drops it to 0 within tens of ms (30 ms constant), and with both off it leaks away (500 ms).
// The switching points have hysteresis: SP1 (control vacuum) on at 600, off below 550
// mbar; SP2 (part present) on at 400, off below 300 mbar. SP3 (part detached) is set when
// the vacuum falls below 50 mbar after a part was present, until the next suction. The
// part under the cup comes from a probe asked when suction starts.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "devices/schmalz/ecbpi_process_data.hpp"

namespace skillcell::devices::schmalz {

/// What the cup did to a part (for the world model).
struct CupEvent {
    enum class Kind : std::uint8_t { Grasped, Released };
    Kind kind;
    std::string partId;
};

struct VacuumLevels {
    double sealed = 750;   // mbar with a part sealing the cup
    double freeFlow = 60;  // mbar with the cup open
    double sp1 = 600, rp1 = 550;
    double sp2 = 400, rp2 = 300;
    double detached = 50;
    double evacuationTau = 0.08;  // s
    double blowOffTau = 0.03;
    double leakTau = 0.5;
};

class SimulatedEcbpi {
public:
    /// The id of the part under the cup, if any.
    using Probe = std::function<std::optional<std::string>()>;

    explicit SimulatedEcbpi(Probe probe = {}, VacuumLevels levels = {})
        : probe_(std::move(probe)), levels_(levels) {}

    /// Sucking, with `part` sealing the cup: the generator as its adapter finds it when the
    /// adapter restarts while the cup holds a part (the world model says it does).
    void startHolding(std::string part);
    /// The master wrote the process data out at time `now`.
    void write(const EcbpiCommand& command, double now);
    /// The process data in at time `now` (time only moves forward).
    [[nodiscard]] EcbpiStatus status(double now);
    [[nodiscard]] std::vector<CupEvent> takeEvents();
    [[nodiscard]] double vacuum() const { return vacuum_; }
    [[nodiscard]] const EcbpiCommand& command() const { return command_; }

private:
    void advance(double now);
    [[nodiscard]] double target() const;
    [[nodiscard]] double tau() const;

    Probe probe_;
    VacuumLevels levels_;
    EcbpiCommand command_;
    std::optional<std::string> part_;  // under the cup during this suction
    double vacuum_ = 0;
    double now_ = 0;
    bool sp1_ = false, sp2_ = false, sp3_ = false;
    bool holding_ = false;
    std::vector<CupEvent> events_;
};

}  // namespace skillcell::devices::schmalz
