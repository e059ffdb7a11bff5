#include "devices/robotiq/robotiq_client.hpp"

namespace skillcell::devices::robotiq {

RobotiqClient::RobotiqClient(Token, std::unique_ptr<ModbusRtuMaster> master)
    : master_(std::move(master)) {}

ua::Result<std::unique_ptr<RobotiqClient>> RobotiqClient::open(const std::string& device,
                                                               int slaveId, std::string* why) {
    auto master = ModbusRtuMaster::open(device, kBaudRate, slaveId, why);
    if (!master) return master.status();
    return std::make_unique<RobotiqClient>(Token{}, std::move(*master));
}

ua::StatusCode RobotiqClient::write(const Command& command) {
    const Registers r = encode(command);
    return master_->writeRegisters(kCommandAddress, r);
}

ua::Result<Status> RobotiqClient::read() {
    Registers r{};
    if (const auto s = master_->readInputRegisters(kStatusAddress, r); s.isBad()) return s;
    return decodeStatus(r);
}

}  // namespace skillcell::devices::robotiq
