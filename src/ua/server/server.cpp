#include "ua/server/server.hpp"

#include <spdlog/spdlog.h>

#include <asio/experimental/as_tuple.hpp>

#include "ua/nodeset/embedded_models.hpp"
#include "ua/server/services/monitored_item_service.hpp"
#include "ua/server/services/register_services.hpp"
#include "ua/server/services/session_service.hpp"
#include "ua/server/services/subscription_service.hpp"

namespace skillcell::ua {

Server::Server(asio::io_context& io, ServerConfig config, std::optional<AddressSpace> namespace0)
    : io_(io),
      config_(std::move(config)),
      addressSpace_(namespace0 ? std::move(*namespace0)
                               : AddressSpace(config_.description.applicationUri)),
      sessions_(config_.limits),
      subscriptions_(addressSpace_, config_.limits),
      acceptor_(io),
      reaper_(io),
      subscriptionTimer_(io) {
    sessions_.setOnClose([this](const Session& s) { subscriptions_.closeSession(s.sessionId()); });
    subscriptions_.setWakeup([this] { subscriptionTimer_.cancel(); });
    sessions_.setWakeup([this] { reaper_.cancel(); });
}

Server::~Server() {
    stop();
}

std::unique_ptr<Server> Server::create(asio::io_context& io, ServerConfig config,
                                       std::string* error) {
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): the constructor is private
    std::unique_ptr<Server> server(new Server(io, std::move(config), std::nullopt));
    const auto loaded = loadBaseNodeSet(server->addressSpace_);
    if (!loaded.ok()) {
        if (error != nullptr) *error = "namespace 0: " + loaded.error;
        return nullptr;
    }
    return finish(std::move(server), error);
}

std::unique_ptr<Server> Server::create(asio::io_context& io, ServerConfig config,
                                       AddressSpace namespace0, std::string* error) {
    if (namespace0.find(NodeId(84)) == nullptr) {  // no RootFolder: nothing was loaded
        if (error != nullptr) *error = "namespace 0: not loaded";
        return nullptr;
    }
    namespace0.setApplicationUri(config.description.applicationUri);
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): the constructor is private
    std::unique_ptr<Server> server(new Server(io, std::move(config), std::move(namespace0)));
    return finish(std::move(server), error);
}

std::unique_ptr<Server> Server::finish(std::unique_ptr<Server> server, std::string* error) {
    ServerInfo info;
    info.applicationUri = server->config_.description.applicationUri;
    info.productUri = server->config_.description.productUri;
    info.productName = server->config_.description.applicationName;
    info.softwareVersion = server->config_.softwareVersion;
    info.startTime = DateTime::now();
    info.maxBrowseContinuationPoints =
        static_cast<std::uint16_t>(server->config_.limits.maxBrowseContinuationPoints);
    if (const StatusCode s = installServerObject(server->addressSpace_, info, &server->state_);
        s.isBad()) {
        if (error != nullptr) *error = "server object: " + std::string(statusName(s));
        return nullptr;
    }
    auto& table = server->services_;
    registerDiscoveryServices(table, server->config_.description);
    registerSessionServices(table, server->sessions_, server->config_.description,
                            server->config_.security);
    registerViewServices(table, server->addressSpace_);
    registerAttributeServices(table, server->addressSpace_);
    registerMethodServices(table, server->addressSpace_);
    registerSubscriptionServices(table, server->subscriptions_);
    registerMonitoredItemServices(table, server->subscriptions_);
    return server;
}

Result<std::uint16_t> Server::listen() {
    asio::error_code ec;
    const auto address = asio::ip::make_address(config_.bindAddress, ec);
    if (ec) {
        spdlog::error("invalid bind address '{}': {}", config_.bindAddress, ec.message());
        return status::BadInvalidArgument;
    }
    const asio::ip::tcp::endpoint endpoint(address, config_.description.port);
    acceptor_.open(endpoint.protocol(), ec);
    if (!ec) acceptor_.set_option(asio::ip::tcp::acceptor::reuse_address(true), ec);
    if (!ec) acceptor_.bind(endpoint, ec);
    if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) {
        spdlog::error("cannot listen on {}:{}: {}", config_.bindAddress, config_.description.port,
                      ec.message());
        return status::BadResourceUnavailable;
    }
    config_.description.port = acceptor_.local_endpoint().port();
    asio::co_spawn(io_, acceptLoop(), asio::detached);
    asio::co_spawn(io_, reapSessions(), asio::detached);
    asio::co_spawn(io_, driveSubscriptions(), asio::detached);
    spdlog::info("listening on {}:{} as {}", config_.bindAddress, config_.description.port,
                 config_.description.applicationUri);
    return config_.description.port;
}

void Server::stop() {
    if (stopped_) return;
    stopped_ = true;
    state_ = ServerState::Shutdown;
    asio::error_code ignored;
    acceptor_.close(ignored);
    reaper_.cancel();
    subscriptionTimer_.cancel();
    for (auto& [id, weak] : connections_) {
        if (auto c = weak.lock()) c->close();
    }
}

asio::awaitable<void> Server::acceptLoop() {
    for (;;) {
        auto [ec, socket] =
            co_await acceptor_.async_accept(asio::experimental::as_tuple(asio::use_awaitable));
        if (ec == asio::error::operation_aborted || stopped_) co_return;
        if (ec) {
            spdlog::warn("accept failed: {}", ec.message());
            continue;
        }
        std::erase_if(connections_, [](const auto& kv) { return kv.second.expired(); });
        if (connections_.size() >= config_.limits.maxChannels) {
            // Tell the client why before closing, so it does not retry blindly.
            spdlog::warn("refusing connection: {} channels open (limit)", connections_.size());
            auto frame = encodeError(status::BadTcpNotEnoughResources, "too many connections");
            asio::error_code ignored;
            asio::write(socket, asio::buffer(frame), ignored);
            socket.close(ignored);
            continue;
        }
        const std::uint32_t channelId = nextChannelId_++;
        auto connection = std::make_shared<Connection>(std::move(socket), environment(), channelId);
        connections_.emplace(channelId, connection);
        asio::co_spawn(io_, connection->run(), asio::detached);
    }
}

asio::awaitable<void> Server::reapSessions() {
    // Armed for the first session's timeout, not on a period: a component without sessions
    // sleeps, and one whose clients keep their sessions alive wakes once per timeout, not
    // once a second. A new session (perhaps the first to time out) cancels the wait.
    while (!stopped_) {
        const auto first = sessions_.nextExpiry();
        reaper_.expires_at(first ? *first + std::chrono::milliseconds(1)
                                 : asio::steady_timer::time_point::max());
        co_await reaper_.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        if (stopped_) co_return;
        if (const auto n = sessions_.expire(std::chrono::steady_clock::now()); n > 0) {
            spdlog::info("closed {} timed-out session(s)", n);
        }
    }
}

asio::awaitable<void> Server::driveSubscriptions() {
    // One timer for the whole engine, armed for its earliest deadline; the engine cancels
    // it (wakeup) when a new subscription or item needs an earlier one.
    while (!stopped_) {
        subscriptionTimer_.expires_at(subscriptions_.nextDeadline());
        co_await subscriptionTimer_.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        if (stopped_) co_return;
        subscriptions_.tick(std::chrono::steady_clock::now());
    }
}

}  // namespace skillcell::ua
