#include "devices/robotiq/robotiq_client.hpp"

#include <modbus.h>

#include <cerrno>

namespace skillcell::devices::robotiq {

struct RobotiqClient::Context {
    explicit Context(modbus_t* c) : ctx(c) {}
    ~Context() {
        modbus_close(ctx);
        modbus_free(ctx);
    }
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    modbus_t* ctx;
};

RobotiqClient::RobotiqClient(Token, std::unique_ptr<Context> ctx) : ctx_(std::move(ctx)) {}

ua::Result<std::unique_ptr<RobotiqClient>> RobotiqClient::open(const std::string& device,
                                                               int slaveId, std::string* why) {
    modbus_t* ctx = modbus_new_rtu(device.c_str(), kBaudRate, 'N', 8, 1);
    if (ctx == nullptr) {
        if (why != nullptr) *why = std::string("libmodbus: ") + modbus_strerror(errno);
        return ua::status::BadCommunicationError;
    }
    auto client = std::make_unique<RobotiqClient>(Token{}, std::make_unique<Context>(ctx));
    if (modbus_set_slave(ctx, slaveId) != 0 || modbus_connect(ctx) != 0) {
        if (why != nullptr) *why = device + ": " + modbus_strerror(errno);
        return ua::status::BadCommunicationError;
    }
    // A reply that does not come within 200 ms is lost (the gripper answers in ~1 ms).
    modbus_set_response_timeout(ctx, 0, 200'000);
    return client;
}

RobotiqClient::~RobotiqClient() = default;

ua::StatusCode RobotiqClient::write(const Command& command) {
    const Registers r = encode(command);
    if (modbus_write_registers(ctx_->ctx, kCommandAddress, kRegisterCount, r.data()) !=
        kRegisterCount) {
        lastError_ = std::string("write: ") + modbus_strerror(errno);
        modbus_flush(ctx_->ctx);
        return ua::status::BadCommunicationError;
    }
    return ua::status::Good;
}

ua::Result<Status> RobotiqClient::read() {
    Registers r{};
    if (modbus_read_input_registers(ctx_->ctx, kStatusAddress, kRegisterCount, r.data()) !=
        kRegisterCount) {
        lastError_ = std::string("read: ") + modbus_strerror(errno);
        modbus_flush(ctx_->ctx);
        return ua::status::BadCommunicationError;
    }
    return decodeStatus(r);
}

}  // namespace skillcell::devices::robotiq
