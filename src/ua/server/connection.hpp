#pragma once
// Connection: one UA-TCP connection on the server, as coroutines: Hello, then the secure
// channel, then the request loop (OPC 10000-6, 7.1 and 6.7). It owns the socket, the
// SecureChannel state machine and the outgoing queue; services run through the
// ServiceTable. A fatal protocol error sends an ERR frame with the precise status and
// closes this connection only.
#include <asio.hpp>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ua/server/server_description.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/server/service_table.hpp"
#include "ua/server/session_manager.hpp"
#include "ua/transport/secure_channel.hpp"

namespace skillcell::ua {

/// What a connection needs from the server that accepted it.
struct ConnectionEnvironment {
    const ServiceTable& services;
    SessionManager& sessions;
    const ServerLimits& limits;
    const SecureChannelConfig& channelConfig;
    const ServerDescription& description;
    const ServerSecurity& security;
};

class Connection : public std::enable_shared_from_this<Connection> {
public:
    Connection(asio::ip::tcp::socket socket, ConnectionEnvironment env, std::uint32_t channelId);

    /// Serves the connection until the peer leaves, a fatal error, or close().
    asio::awaitable<void> run();
    /// Closes the socket; run() ends soon after.
    void close();
    [[nodiscard]] std::uint32_t channelId() const { return channelId_; }

private:
    asio::awaitable<StatusCode> serve();
    /// The next whole frame (header included), valid until the next call.
    asio::awaitable<Result<std::span<const std::uint8_t>>> readFrame(std::uint32_t maxSize);
    StatusCode handleHello(std::span<const std::uint8_t> frame);
    StatusCode handleOpen(const ChannelMessage& message, SteadyTime now);
    StatusCode handleMessage(const ChannelMessage& message, SteadyTime now);
    /// Encodes a service body into frames and queues them; a response too large for the
    /// client becomes a ServiceFault.
    StatusCode sendMessage(MessageType type, std::uint32_t requestId, std::uint32_t requestHandle,
                           std::vector<std::uint8_t> body);
    /// Sends the response of a deferred service; nothing once the connection is closing.
    void sendDeferred(std::uint32_t requestId, std::uint32_t requestHandle,
                      std::vector<std::uint8_t> body);
    void send(std::vector<std::uint8_t> frame);
    void fail(StatusCode status, std::string_view reason);
    void setDeadline(SteadyTime deadline);
    /// A None channel on a server that does not offer None: discovery services only.
    [[nodiscard]] bool discoveryOnly() const;

    /// Writes what is queued unless a write is in flight; closes once drained if closing.
    void writeQueued();
    asio::awaitable<void> watchdog();

    asio::ip::tcp::socket socket_;
    ConnectionEnvironment env_;
    std::uint32_t channelId_;
    std::optional<SecureChannel> channel_;
    TransportLimits limits_;
    std::string endpointUrl_;
    std::string peer_ = "?";  // "address:port", for logs

    std::vector<std::uint8_t> in_;
    std::size_t inBegin_ = 0;
    std::size_t inEnd_ = 0;

    std::deque<std::vector<std::uint8_t>> out_;
    std::vector<asio::const_buffer> writeBuffers_;
    bool writing_ = false;
    bool closing_ = false;  // flush what is queued, then close

    asio::steady_timer deadlineTimer_;
    SteadyTime deadline_;
};

}  // namespace skillcell::ua
