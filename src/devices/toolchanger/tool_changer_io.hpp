#pragma once
// ToolChangerIo: the I/O of a Kelvin tool changer as its controller sees it: the coupling's
// lock valve (a digital output), the locked sensor (a digital input) and the tool
// identification pin (a 12-bit ADC channel, 0-10 V). Calls block for an I/O round trip, so
// the adapter makes them from its own I/O thread, never from a server's thread.
#include <cstdint>

#include "ua/types/result.hpp"

namespace skillcell::devices::toolchanger {

inline constexpr double kAdcFullScaleVolts = 10.0;
inline constexpr std::uint16_t kAdcMaxCount = 4095;

[[nodiscard]] constexpr double adcVolts(std::uint16_t counts) {
    return kAdcFullScaleVolts * counts / kAdcMaxCount;
}

class ToolChangerIo {
public:
    ToolChangerIo() = default;
    virtual ~ToolChangerIo() = default;
    ToolChangerIo(const ToolChangerIo&) = delete;
    ToolChangerIo& operator=(const ToolChangerIo&) = delete;

    /// Drives the lock valve; the coupling locks (or opens) if it can. Bad: the output
    /// could not be written.
    virtual ua::StatusCode setLockValve(bool lock) = 0;
    /// The locked sensor.
    [[nodiscard]] virtual ua::Result<bool> locked() = 0;
    /// One conversion of the identification pin.
    [[nodiscard]] virtual ua::Result<std::uint16_t> identificationCounts() = 0;
};

}  // namespace skillcell::devices::toolchanger
