#pragma once
// RobotiqClient: the adapter's side of the 2F-85's serial line: a Modbus RTU master
// (libmodbus) on a serial device, writing the command registers and reading the status
// registers (robotiq_registers.hpp). It knows a device path and a slave id, nothing of
// what is behind them. Blocking calls, for one thread at a time.
#include <memory>
#include <string>

#include "devices/common/modbus_rtu_master.hpp"
#include "devices/robotiq/robotiq_registers.hpp"
#include "ua/types/result.hpp"

namespace skillcell::devices::robotiq {

class RobotiqClient {
public:
    /// Opens `device` (115200 8N1). BadCommunicationError with `why` when it cannot.
    [[nodiscard]] static ua::Result<std::unique_ptr<RobotiqClient>> open(
        const std::string& device, int slaveId = kSlaveId, std::string* why = nullptr);

    /// Writes the three command registers (function 16). BadCommunicationError on a
    /// timeout or a damaged reply; `lastError()` says more.
    ua::StatusCode write(const Command& command);
    /// Reads the three status registers (function 4).
    [[nodiscard]] ua::Result<Status> read();
    [[nodiscard]] const std::string& lastError() const { return master_->lastError(); }

    struct Token {
    private:
        friend class RobotiqClient;
        Token() = default;
    };
    RobotiqClient(Token, std::unique_ptr<ModbusRtuMaster> master);

private:
    std::unique_ptr<ModbusRtuMaster> master_;
};

}  // namespace skillcell::devices::robotiq
