#include "devices/common/modbus_rtu_master.hpp"

#include <modbus.h>

#include <cerrno>

namespace skillcell::devices {
namespace {

constexpr int kAttempts = 3;

/// Runs a request again when its reply was lost (a timeout), as masters on real lines do:
/// writing registers and reading them are idempotent. Other errors are not retried; errno
/// is the failed attempt's.
template <class Request>
bool withRetries(modbus_t* ctx, Request request) {
    for (int attempt = 1;; ++attempt) {
        if (request()) return true;
        if (errno != ETIMEDOUT || attempt == kAttempts) return false;
        modbus_flush(ctx);  // a late reply must not answer the next request
    }
}

}  // namespace

struct ModbusRtuMaster::Context {
    explicit Context(modbus_t* c) : ctx(c) {}
    ~Context() {
        modbus_close(ctx);
        modbus_free(ctx);
    }
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    modbus_t* ctx;
};

ModbusRtuMaster::ModbusRtuMaster(Token, std::unique_ptr<Context> ctx) : ctx_(std::move(ctx)) {}
ModbusRtuMaster::~ModbusRtuMaster() = default;

ua::Result<std::unique_ptr<ModbusRtuMaster>> ModbusRtuMaster::open(const std::string& device,
                                                                   int baudRate, int slaveId,
                                                                   std::string* why) {
    modbus_t* ctx = modbus_new_rtu(device.c_str(), baudRate, 'N', 8, 1);
    if (ctx == nullptr) {
        if (why != nullptr) *why = std::string("libmodbus: ") + modbus_strerror(errno);
        return ua::status::BadCommunicationError;
    }
    auto master = std::make_unique<ModbusRtuMaster>(Token{}, std::make_unique<Context>(ctx));
    if (modbus_set_slave(ctx, slaveId) != 0 || modbus_connect(ctx) != 0) {
        if (why != nullptr) *why = device + ": " + modbus_strerror(errno);
        return ua::status::BadCommunicationError;
    }
    // A reply that does not come within 1 s is lost; the request is then sent again, up to
    // kAttempts in all. The grippers answer in ~1 ms, but a simulated one shares a loaded
    // host with a whole cell: CI run 24 saw three 200 ms waits in a row run out.
    modbus_set_response_timeout(ctx, 1, 0);
    return master;
}

ua::StatusCode ModbusRtuMaster::failed(const char* what) {
    lastError_ = std::string(what) + ": " + modbus_strerror(errno);
    modbus_flush(ctx_->ctx);
    return ua::status::BadCommunicationError;
}

ua::StatusCode ModbusRtuMaster::writeRegisters(std::uint16_t address,
                                               std::span<const std::uint16_t> values) {
    const int n = static_cast<int>(values.size());
    modbus_t* ctx = ctx_->ctx;
    if (!withRetries(ctx,
                     [&] { return modbus_write_registers(ctx, address, n, values.data()) == n; })) {
        return failed("write");
    }
    return ua::status::Good;
}

ua::StatusCode ModbusRtuMaster::readHoldingRegisters(std::uint16_t address,
                                                     std::span<std::uint16_t> out) {
    const int n = static_cast<int>(out.size());
    modbus_t* ctx = ctx_->ctx;
    if (!withRetries(ctx,
                     [&] { return modbus_read_registers(ctx, address, n, out.data()) == n; })) {
        return failed("read");
    }
    return ua::status::Good;
}

ua::StatusCode ModbusRtuMaster::readInputRegisters(std::uint16_t address,
                                                   std::span<std::uint16_t> out) {
    const int n = static_cast<int>(out.size());
    modbus_t* ctx = ctx_->ctx;
    if (!withRetries(
            ctx, [&] { return modbus_read_input_registers(ctx, address, n, out.data()) == n; })) {
        return failed("read");
    }
    return ua::status::Good;
}

}  // namespace skillcell::devices
