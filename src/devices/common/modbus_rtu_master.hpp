#pragma once
// ModbusRtuMaster: an adapter's side of a device's serial line: a Modbus RTU master
// (libmodbus) on a serial device, reading and writing registers of one slave. It knows a
// device path and a slave id, nothing of what is behind them. Blocking calls, for one thread
// at a time; a failed call flushes the line and leaves the reason in lastError().
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "ua/types/result.hpp"

namespace skillcell::devices {

class ModbusRtuMaster {
public:
    /// Opens `device` (8N1 at `baudRate`). BadCommunicationError with `why` when it cannot.
    [[nodiscard]] static ua::Result<std::unique_ptr<ModbusRtuMaster>> open(
        const std::string& device, int baudRate, int slaveId, std::string* why = nullptr);
    ~ModbusRtuMaster();
    ModbusRtuMaster(const ModbusRtuMaster&) = delete;
    ModbusRtuMaster& operator=(const ModbusRtuMaster&) = delete;

    /// Function 16 (write multiple registers).
    ua::StatusCode writeRegisters(std::uint16_t address, std::span<const std::uint16_t> values);
    /// Function 3 (read holding registers) into `out`.
    ua::StatusCode readHoldingRegisters(std::uint16_t address, std::span<std::uint16_t> out);
    /// Function 4 (read input registers) into `out`.
    ua::StatusCode readInputRegisters(std::uint16_t address, std::span<std::uint16_t> out);
    [[nodiscard]] const std::string& lastError() const { return lastError_; }

    struct Context;  // the libmodbus context, defined where libmodbus is included
    struct Token {
    private:
        friend class ModbusRtuMaster;
        Token() = default;
    };
    ModbusRtuMaster(Token, std::unique_ptr<Context> ctx);

private:
    ua::StatusCode failed(const char* what);

    std::unique_ptr<Context> ctx_;
    std::string lastError_;
};

}  // namespace skillcell::devices
