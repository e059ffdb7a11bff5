#pragma once
// Server: an OPC UA server on one Asio io_context. It is composed of owned parts, each with
// one job: the AddressSpace (nodes), the SessionManager (sessions), the ServiceTable
// (service sets), and one Connection per socket (transport + secure channel). The server
// only wires them together and runs the accept loop and the session reaper.
//
// Threading: everything runs on the io_context's thread. Application code on other threads
// changes the address space through asio::post(io, ...).
#include <asio.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>

#include "ua/address_space/address_space.hpp"
#include "ua/address_space/server_object.hpp"
#include "ua/server/connection.hpp"
#include "ua/server/server_description.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/server/service_table.hpp"
#include "ua/server/session_manager.hpp"
#include "ua/server/subscriptions/subscription_engine.hpp"
#include "ua/transport/secure_channel.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

struct ServerConfig {
    ServerDescription description;
    /// Address to listen on; the port is description.port (0: any free port).
    std::string bindAddress = "0.0.0.0";
    ServerLimits limits;
    SecureChannelConfig channel;
    /// Private key and certificate validation behind description.securityEndpoints.
    ServerSecurity security;
    std::string softwareVersion = "0.1.0";
};

class Server {
public:
    /// Builds the address space (namespace 0 from the embedded NodeSet2 model, the Server
    /// object) and the service table. No socket is opened yet. On failure, `error` (if
    /// given) receives a message naming the cause.
    [[nodiscard]] static std::unique_ptr<Server> create(asio::io_context& io, ServerConfig config,
                                                        std::string* error = nullptr);
    /// The same with namespace 0 loaded already (loadBaseNodeSet into `namespace0`), for a
    /// caller that loaded it on another thread while it did something else; namespace 1
    /// becomes the configured application URI.
    [[nodiscard]] static std::unique_ptr<Server> create(asio::io_context& io, ServerConfig config,
                                                        AddressSpace namespace0,
                                                        std::string* error = nullptr);
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;
    ~Server();

    /// Binds and starts accepting. Returns the port actually bound (useful with port 0);
    /// BadResourceUnavailable if the address cannot be bound.
    [[nodiscard]] Result<std::uint16_t> listen();
    /// Stops accepting, closes every connection; the io_context then runs out of work.
    void stop();

    [[nodiscard]] AddressSpace& addressSpace() { return addressSpace_; }
    /// The executor of the io_context the server runs on (for timers of application code).
    [[nodiscard]] asio::any_io_executor executor() { return io_.get_executor(); }
    [[nodiscard]] ServiceTable& services() { return services_; }
    [[nodiscard]] const ServerConfig& config() const { return config_; }
    [[nodiscard]] std::size_t connectionCount() const { return connections_.size(); }
    /// What a connection serves requests with (dispatchRequest): the service table, the
    /// sessions, the limits, the description and the security. Also what the stateful fuzzer
    /// drives without a socket.
    [[nodiscard]] ConnectionEnvironment environment() {
        return {services_,       sessions_,           config_.limits,
                config_.channel, config_.description, config_.security};
    }
    [[nodiscard]] std::size_t sessionCount() const { return sessions_.size(); }
    /// True while the session with this SessionId exists (not closed, not timed out).
    [[nodiscard]] bool hasSession(const NodeId& sessionId) const {
        return sessions_.contains(sessionId);
    }
    [[nodiscard]] ServerSubscriptionEngine& subscriptions() { return subscriptions_; }

    /// Fires an event from application code (on the io_context thread): delivered to the
    /// event monitored items on its source, the notifiers above it and the Server object.
    /// Returns its EventId.
    ByteString fireEvent(Event event) { return subscriptions_.fireEvent(std::move(event)); }

private:
    Server(asio::io_context& io, ServerConfig config, std::optional<AddressSpace> namespace0);
    [[nodiscard]] static std::unique_ptr<Server> finish(std::unique_ptr<Server> server,
                                                        std::string* error);
    asio::awaitable<void> acceptLoop();
    asio::awaitable<void> reapSessions();
    /// Runs the subscription engine: publishing cycles, sampling, Publish timeouts.
    asio::awaitable<void> driveSubscriptions();

    asio::io_context& io_;
    ServerConfig config_;
    AddressSpace addressSpace_;
    SessionManager sessions_;
    ServerSubscriptionEngine subscriptions_;  // after the address space and sessions it observes
    ServiceTable services_;
    ServerState state_ = ServerState::Running;
    asio::ip::tcp::acceptor acceptor_;
    asio::steady_timer reaper_;
    asio::steady_timer subscriptionTimer_;
    std::unordered_map<std::uint32_t, std::weak_ptr<Connection>> connections_;
    std::uint32_t nextChannelId_ = 1;
    bool stopped_ = false;
};

}  // namespace skillcell::ua
