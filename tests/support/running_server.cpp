#include "running_server.hpp"

#include <stdexcept>

namespace skillcell::test {

ua::ServerConfig RunningServer::defaultConfig() {
    ua::ServerConfig config;
    config.bindAddress = "127.0.0.1";
    config.description.port = 0;
    config.description.advertisedHost = "127.0.0.1";
    return config;
}

RunningServer::RunningServer(ua::ServerConfig config,
                             const std::function<void(ua::Server&)>& prepare) {
    std::string error;
    server_ = ua::Server::create(io_, std::move(config), &error);
    if (!server_) throw std::runtime_error("server: " + error);
    if (prepare) prepare(*server_);
    auto port = server_->listen();
    if (!port) throw std::runtime_error("listen failed");
    port_ = *port;
    thread_ = std::thread([this] { io_.run(); });
}

RunningServer::~RunningServer() {
    asio::post(io_, [this] { server_->stop(); });
    thread_.join();
}

std::string RunningServer::url() const {
    return "opc.tcp://127.0.0.1:" + std::to_string(port_);
}

}  // namespace skillcell::test
