#pragma once
// The Schmalz ECBPi's cyclic IO-Link process data, as the IO-Link master exchanges it
// (docs/devices.md, "Schmalz ECBPi"). The layout follows Schmalz's IO-Link data
// dictionaries for its vacuum generators: 4 bytes in (device to master), 2 bytes out.
//
//   PD in  byte 0   bit 0 SP2 part present (vacuum above SP2, not yet below rP2)
//                   bit 1 SP1 control vacuum reached (above SP1, not yet below rP1)
//                   bit 5 SP3 part detached (after a suction cycle)
//                   bits 6-7 device status (0 green, 1 yellow, 2 orange, 3 red)
//          byte 1   EPC value 1: supply voltage (V)
//          byte 2-3 EPC value 2: system vacuum (mbar, big-endian)
//   PD out byte 0   bit 0 suction on, bit 1 blow off
//          byte 1   reserved
#include <array>
#include <cstdint>

namespace skillcell::devices::schmalz {

inline constexpr std::size_t kProcessDataInSize = 4;
inline constexpr std::size_t kProcessDataOutSize = 2;
using ProcessDataIn = std::array<std::uint8_t, kProcessDataInSize>;
using ProcessDataOut = std::array<std::uint8_t, kProcessDataOutSize>;

enum class DeviceStatus : std::uint8_t { Green = 0, Yellow = 1, Orange = 2, Red = 3 };

struct EcbpiCommand {
    bool suction = false;
    bool blowOff = false;
    friend bool operator==(const EcbpiCommand&, const EcbpiCommand&) = default;
};

struct EcbpiStatus {
    bool partPresent = false;     // SP2
    bool controlReached = false;  // SP1
    bool partDetached = false;    // SP3
    DeviceStatus device = DeviceStatus::Green;
    std::uint8_t supplyVoltage = 24;  // V
    std::uint16_t vacuum = 0;         // mbar
    friend bool operator==(const EcbpiStatus&, const EcbpiStatus&) = default;
};

[[nodiscard]] ProcessDataOut encode(const EcbpiCommand& command);
[[nodiscard]] EcbpiCommand decodeCommand(const ProcessDataOut& data);
[[nodiscard]] ProcessDataIn encode(const EcbpiStatus& status);
[[nodiscard]] EcbpiStatus decodeStatus(const ProcessDataIn& data);

}  // namespace skillcell::devices::schmalz
