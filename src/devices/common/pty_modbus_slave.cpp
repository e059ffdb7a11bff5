#include "devices/common/pty_modbus_slave.hpp"

#include <fcntl.h>
#include <modbus.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <spdlog/spdlog.h>
#include <cerrno>
#include <cstring>

namespace skillcell::devices {
namespace {

/// libmodbus objects as RAII handles.
struct ModbusDeleter {
    void operator()(modbus_t* ctx) const { modbus_free(ctx); }
};
struct MappingDeleter {
    void operator()(modbus_mapping_t* m) const { modbus_mapping_free(m); }
};

}  // namespace

std::unique_ptr<PtyModbusSlave> PtyModbusSlave::open(ModbusRegisterMap map,
                                                     SimulatedModbusDevice& device,
                                                     std::string* why) {
    auto port = std::make_unique<PtyModbusSlave>(Token{}, map, device);
    std::array<char, 128> name{};
    if (openpty(&port->master_, &port->slave_, name.data(), nullptr, nullptr) != 0) {
        if (why != nullptr) *why = std::string("openpty: ") + std::strerror(errno);
        return nullptr;
    }
    // Raw bytes both ways: no echo, no line editing, no CR/LF translation.
    termios tio{};
    tcgetattr(port->slave_, &tio);
    cfmakeraw(&tio);
    tcsetattr(port->slave_, TCSANOW, &tio);
    if (pipe2(port->stop_, O_CLOEXEC) != 0) {
        if (why != nullptr) *why = std::string("pipe: ") + std::strerror(errno);
        return nullptr;
    }
    port->path_ = name.data();
    port->thread_ = std::thread([p = port.get()] { p->serve(); });
    return port;
}

PtyModbusSlave::~PtyModbusSlave() {
    if (thread_.joinable()) {
        const char stop = 1;
        (void)!write(stop_[1], &stop, 1);
        thread_.join();
    }
    for (int fd : {master_, slave_, stop_[0], stop_[1]}) {
        if (fd >= 0) close(fd);
    }
}

std::uint64_t PtyModbusSlave::requests() {
    std::lock_guard lock(mutex_);
    return requests_;
}

bool PtyModbusSlave::waitForRequests(std::uint64_t count, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return served_.wait_for(lock, timeout, [&] { return requests_ >= count; });
}

void PtyModbusSlave::serve() {
    // The device path only names the pty for the adapter; this side talks through the
    // master descriptor directly (libmodbus reads and writes ctx's socket).
    auto newContext = [this] {
        std::unique_ptr<modbus_t, ModbusDeleter> c(
            modbus_new_rtu(path_.c_str(), map_.baudRate, 'N', 8, 1));
        if (c) {
            modbus_set_slave(c.get(), map_.slaveId);
            modbus_set_socket(c.get(), master_);
        }
        return c;
    };
    auto ctx = newContext();
    std::unique_ptr<modbus_mapping_t, MappingDeleter> mapping(modbus_mapping_new_start_address(
        0, 0, 0, 0, map_.holdingStart, map_.holdingCount, map_.inputStart, map_.inputCount));
    if (!ctx || !mapping) {
        spdlog::error("simulated Modbus device: cannot set up libmodbus");
        return;
    }
    const std::span<std::uint16_t> holding(mapping->tab_registers, map_.holdingCount);
    const std::span<std::uint16_t> input(mapping->tab_input_registers, map_.inputCount);
    const int header = modbus_get_header_length(ctx.get());
    std::array<std::uint8_t, MODBUS_RTU_MAX_ADU_LENGTH> query{};
    for (;;) {
        std::array<pollfd, 2> fds{{{master_, POLLIN, 0}, {stop_[0], POLLIN, 0}}};
        if (::poll(fds.data(), fds.size(), -1) < 0) {
            if (errno == EINTR) continue;
            spdlog::error("simulated Modbus device: poll: {}", std::strerror(errno));
            return;
        }
        if ((fds[1].revents & POLLIN) != 0) return;
        if ((fds[0].revents & POLLIN) == 0) continue;
        const int length = modbus_receive(ctx.get(), query.data());
        if (length == 0) {
            // A request for another slave. libmodbus then expects that slave's reply and
            // would swallow the next frame as it; a device's firmware does not, so a fresh
            // context forgets the expectation.
            ctx = newContext();
            if (!ctx) return;
            continue;
        }
        if (length < 0) {
            // A damaged frame: drop what is buffered, as a device on a bus does.
            modbus_flush(ctx.get());
            continue;
        }
        device_.present(holding, input);
        (void)modbus_reply(ctx.get(), query.data(), length, mapping.get());
        const auto at = static_cast<std::size_t>(header);
        const int function = query[at];
        if (function == MODBUS_FC_WRITE_MULTIPLE_REGISTERS ||
            function == MODBUS_FC_WRITE_SINGLE_REGISTER) {
            const auto address = static_cast<std::uint16_t>((query[at + 1] << 8) | query[at + 2]);
            const auto count =
                function == MODBUS_FC_WRITE_SINGLE_REGISTER
                    ? std::uint16_t{1}
                    : static_cast<std::uint16_t>((query[at + 3] << 8) | query[at + 4]);
            device_.written(address, count, holding);
        }
        {
            std::lock_guard lock(mutex_);
            ++requests_;
        }
        served_.notify_all();
    }
}

}  // namespace skillcell::devices
