#include "devices/schmalz/ecbpi_process_data.hpp"

namespace skillcell::devices::schmalz {

ProcessDataOut encode(const EcbpiCommand& c) {
    return {static_cast<std::uint8_t>((c.suction ? 1U : 0U) | (c.blowOff ? 2U : 0U)), 0};
}

EcbpiCommand decodeCommand(const ProcessDataOut& d) {
    return EcbpiCommand{(d[0] & 1U) != 0, (d[0] & 2U) != 0};
}

ProcessDataIn encode(const EcbpiStatus& s) {
    const auto bits = static_cast<std::uint8_t>(
        (s.partPresent ? 1U : 0U) | (s.controlReached ? 2U : 0U) | (s.partDetached ? 1U << 5 : 0U) |
        (static_cast<unsigned>(s.device) << 6));
    return {bits, s.supplyVoltage, static_cast<std::uint8_t>(s.vacuum >> 8),
            static_cast<std::uint8_t>(s.vacuum & 0xFF)};
}

EcbpiStatus decodeStatus(const ProcessDataIn& d) {
    EcbpiStatus s;
    s.partPresent = (d[0] & 1U) != 0;
    s.controlReached = (d[0] & 2U) != 0;
    s.partDetached = (d[0] & (1U << 5)) != 0;
    s.device = static_cast<DeviceStatus>(d[0] >> 6);
    s.supplyVoltage = d[1];
    s.vacuum = static_cast<std::uint16_t>((d[2] << 8) | d[3]);
    return s;
}

}  // namespace skillcell::devices::schmalz
