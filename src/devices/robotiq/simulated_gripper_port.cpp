#include "devices/robotiq/simulated_gripper_port.hpp"

#include <fcntl.h>
#include <modbus.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <spdlog/spdlog.h>
#include <cerrno>
#include <cstring>

namespace skillcell::devices::robotiq {
namespace {

/// libmodbus objects as RAII handles.
struct ModbusDeleter {
    void operator()(modbus_t* ctx) const { modbus_free(ctx); }
};
struct MappingDeleter {
    void operator()(modbus_mapping_t* m) const { modbus_mapping_free(m); }
};

}  // namespace

SimulatedGripperPort::SimulatedGripperPort(Token, SimulatedGripperOptions options)
    : options_(std::move(options)), gripper_(options_.probe) {
    epoch_ = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
}

std::unique_ptr<SimulatedGripperPort> SimulatedGripperPort::open(SimulatedGripperOptions options,
                                                                 std::string* why) {
    auto port = std::make_unique<SimulatedGripperPort>(Token{}, std::move(options));
    char name[128] = {};
    if (openpty(&port->master_, &port->slave_, name, nullptr, nullptr) != 0) {
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
    port->path_ = name;
    port->thread_ = std::thread([p = port.get()] { p->serve(); });
    return port;
}

SimulatedGripperPort::~SimulatedGripperPort() {
    if (thread_.joinable()) {
        const char stop = 1;
        (void)!write(stop_[1], &stop, 1);
        thread_.join();
    }
    for (int fd : {master_, slave_, stop_[0], stop_[1]}) {
        if (fd >= 0) close(fd);
    }
}

double SimulatedGripperPort::now() const {
    const auto t = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
    return std::chrono::duration<double>(t - epoch_).count() * options_.speed;
}

double SimulatedGripperPort::fingerPosition() {
    std::lock_guard lock(mutex_);
    (void)gripper_.status(now());  // where the fingers are now, not at the last request
    return gripper_.position();
}

std::uint64_t SimulatedGripperPort::requests() {
    std::lock_guard lock(mutex_);
    return requests_;
}

bool SimulatedGripperPort::waitForRequests(std::uint64_t count, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return served_.wait_for(lock, timeout, [&] { return requests_ >= count; });
}

bool SimulatedGripperPort::waitForCommand(const std::function<bool(const Command&)>& predicate,
                                          std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return served_.wait_for(lock, timeout, [&] { return predicate(gripper_.command()); });
}

Command SimulatedGripperPort::lastCommand() {
    std::lock_guard lock(mutex_);
    return gripper_.command();
}

void SimulatedGripperPort::serve() {
    // The device path only names the pty for the adapter; this side talks through the
    // master descriptor directly (libmodbus reads and writes ctx's socket).
    auto newContext = [this] {
        std::unique_ptr<modbus_t, ModbusDeleter> c(
            modbus_new_rtu(path_.c_str(), kBaudRate, 'N', 8, 1));
        if (c) {
            modbus_set_slave(c.get(), kSlaveId);
            modbus_set_socket(c.get(), master_);
        }
        return c;
    };
    auto ctx = newContext();
    std::unique_ptr<modbus_mapping_t, MappingDeleter> map(modbus_mapping_new_start_address(
        0, 0, 0, 0, kCommandAddress, kRegisterCount, kStatusAddress, kRegisterCount));
    if (!ctx || !map) {
        spdlog::error("simulated 2F-85: cannot set up libmodbus");
        return;
    }
    const int header = modbus_get_header_length(ctx.get());
    std::uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
    for (;;) {
        pollfd fds[2] = {{master_, POLLIN, 0}, {stop_[0], POLLIN, 0}};
        if (::poll(fds, 2, -1) < 0) {
            if (errno == EINTR) continue;
            spdlog::error("simulated 2F-85: poll: {}", std::strerror(errno));
            return;
        }
        if ((fds[1].revents & POLLIN) != 0) return;
        if ((fds[0].revents & POLLIN) == 0) continue;
        const int length = modbus_receive(ctx.get(), query);
        if (length == 0) {
            // A request for another slave. libmodbus then expects that slave's reply and
            // would swallow the next frame as it; the gripper's firmware does not, so a
            // fresh context forgets the expectation.
            ctx = newContext();
            if (!ctx) return;
            continue;
        }
        if (length < 0) {
            // A damaged frame: drop what is buffered, as a device on a bus does.
            modbus_flush(ctx.get());
            continue;
        }
        // What the fingers did up to now reaches the world before the reply does, so a
        // robot that reads "object detected" finds the world already holding it.
        std::vector<FingerEvent> events;
        {
            std::lock_guard lock(mutex_);
            const Registers status = encode(gripper_.status(now()));
            std::copy(status.begin(), status.end(), map->tab_input_registers);
            events = gripper_.takeEvents();
        }
        for (const auto& e : events) {
            if (options_.onEvent) options_.onEvent(e);
        }
        {
            std::lock_guard lock(mutex_);
            (void)modbus_reply(ctx.get(), query, length, map.get());
            ++requests_;
            const int function = query[header];
            if (function == MODBUS_FC_WRITE_MULTIPLE_REGISTERS ||
                function == MODBUS_FC_WRITE_SINGLE_REGISTER) {
                Registers written{};
                std::copy(map->tab_registers, map->tab_registers + kRegisterCount, written.begin());
                gripper_.write(decodeCommand(written), now());
            }
            events = gripper_.takeEvents();
        }
        served_.notify_all();
        for (const auto& e : events) {
            if (options_.onEvent) options_.onEvent(e);
        }
    }
}

}  // namespace skillcell::devices::robotiq
