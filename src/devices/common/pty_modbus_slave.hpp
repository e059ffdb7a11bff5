#pragma once
// PtyModbusSlave: a simulated device's serial port. It opens a pseudo-terminal pair, puts
// the slave side in raw mode and answers Modbus RTU requests (libmodbus) on the master side
// from a thread of its own, showing the registers a SimulatedModbusDevice keeps. The adapter
// opens devicePath() like any serial device; nothing else connects the two. What a real
// device on a bus does, this does: a request for another slave id goes unanswered, a
// damaged frame is dropped, an address outside the map gets ILLEGAL DATA ADDRESS.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>

namespace skillcell::devices {

/// Where a device's registers are on the bus.
struct ModbusRegisterMap {
    int slaveId = 1;
    int baudRate = 115200;
    std::uint16_t holdingStart = 0;  // functions 3, 6 and 16
    std::uint16_t holdingCount = 0;
    std::uint16_t inputStart = 0;  // function 4
    std::uint16_t inputCount = 0;
};

/// The simulated device behind the port. Both calls come from the port's thread.
class SimulatedModbusDevice {
public:
    SimulatedModbusDevice() = default;
    virtual ~SimulatedModbusDevice() = default;
    SimulatedModbusDevice(const SimulatedModbusDevice&) = delete;
    SimulatedModbusDevice& operator=(const SimulatedModbusDevice&) = delete;

    /// Before a request is answered: bring the registers up to now (a read returns them).
    virtual void present(std::span<std::uint16_t> holding, std::span<std::uint16_t> input) = 0;
    /// After a write request was answered: the master wrote `count` registers from
    /// `address` on; `holding` is the whole block as it left it.
    virtual void written(std::uint16_t address, std::uint16_t count,
                         std::span<const std::uint16_t> holding) = 0;
};

class PtyModbusSlave {
public:
    /// Opens the pty pair and starts serving `device` (which must outlive the port). On
    /// failure, nullptr and `why`.
    [[nodiscard]] static std::unique_ptr<PtyModbusSlave> open(ModbusRegisterMap map,
                                                              SimulatedModbusDevice& device,
                                                              std::string* why = nullptr);
    ~PtyModbusSlave();
    PtyModbusSlave(const PtyModbusSlave&) = delete;
    PtyModbusSlave& operator=(const PtyModbusSlave&) = delete;

    /// The serial device the adapter opens (the pty's slave side, /dev/pts/N).
    [[nodiscard]] const std::string& devicePath() const { return path_; }
    /// Requests answered so far (tests wait on the protocol, not on time).
    [[nodiscard]] std::uint64_t requests();
    /// Waits until `count` requests have been answered; false after `timeout`.
    bool waitForRequests(std::uint64_t count, std::chrono::milliseconds timeout);

    struct Token {
    private:
        friend class PtyModbusSlave;
        Token() = default;
    };
    PtyModbusSlave(Token, ModbusRegisterMap map, SimulatedModbusDevice& device)
        : map_(map), device_(device) {}

private:
    void serve();

    ModbusRegisterMap map_;
    SimulatedModbusDevice& device_;
    int master_ = -1;
    int slave_ = -1;  // kept open so the master never sees a hang-up between clients
    int stop_[2] = {-1, -1};
    std::string path_;
    std::mutex mutex_;
    std::condition_variable served_;
    std::uint64_t requests_ = 0;
    std::thread thread_;
};

}  // namespace skillcell::devices
