#include "devices/toolchanger/simulated_kelvin_changer.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "ua/types/connection_loss.hpp"

namespace skillcell::devices::toolchanger {

SimulatedKelvinChanger::SimulatedKelvinChanger(WorldLink& world, const ToolTable& tools)
    : world_(world), tools_(tools) {}

ua::StatusCode SimulatedKelvinChanger::setLockValve(bool lock) {
    std::lock_guard guard(mutex_);
    const auto mounted = world_.mountedTool();
    if (!mounted) return mounted.status();
    if (lock == !mounted->empty()) return ua::status::Good;  // already so
    // The coupling meets a tool only at a dock; elsewhere the valve moves the balls in the
    // air and the sensor stays as it was.
    const auto dock = world_.dockAtFlange();
    if (!dock) return dock.status();
    if (dock->empty()) {
        spdlog::info("tool changer: lock valve {}, but the flange is at no dock",
                     lock ? "on" : "off");
        return ua::status::Good;
    }
    const auto s = lock ? world_.mountTool(*dock) : world_.unmountTool(*dock);
    // The physics not there (restarting) is an I/O failure, not a coupling that did not lock.
    if (ua::isTransient(s)) return s;
    if (s.isBad()) {
        spdlog::info("tool changer: the coupling did not {} at dock {}: {}", lock ? "lock" : "open",
                     *dock, ua::statusName(s));
    }
    return ua::status::Good;  // the valve switched; the sensor tells what came of it
}

ua::Result<bool> SimulatedKelvinChanger::locked() {
    std::lock_guard guard(mutex_);
    const auto mounted = world_.mountedTool();
    if (!mounted) return mounted.status();
    return !mounted->empty();
}

ua::Result<std::uint16_t> SimulatedKelvinChanger::identificationCounts() {
    std::lock_guard guard(mutex_);
    const auto mounted = world_.mountedTool();
    if (!mounted) return mounted.status();
    double volts = 0.02;  // an open pin: a few counts of offset
    if (!mounted->empty()) {
        const ToolEntry* tool = tools_.byId(*mounted);
        // A tool the table does not know has a resistor of its own: outside every band.
        volts = tool != nullptr ? tool->nominalVolts() : kAdcFullScaleVolts * 0.97;
        const double spread = tool != nullptr ? (tool->maxVolts - tool->minVolts) / 8 : 0.01;
        std::uniform_real_distribution<double> jitter(-spread, spread);
        volts += jitter(noise_);
    }
    const double counts = std::round(volts / kAdcFullScaleVolts * kAdcMaxCount);
    return static_cast<std::uint16_t>(std::clamp(counts, 0.0, double(kAdcMaxCount)));
}

}  // namespace skillcell::devices::toolchanger
