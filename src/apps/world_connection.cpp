#include "world_connection.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include "ua/types/connection_loss.hpp"

namespace skillcell::apps {

namespace {

ua::Result<std::unique_ptr<devices::WorldLink>> connectWorld(const std::string& url,
                                                             const ua::ClientConfig& config,
                                                             const std::string& robot) {
    constexpr auto kPatience = std::chrono::seconds(15);
    constexpr auto kPause = std::chrono::milliseconds(200);
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    for (bool told = false;;) {
        auto link = devices::WorldLink::connect(url, config, robot);
        if (link || !ua::isConnectionLoss(link.status()) ||
            std::chrono::steady_clock::now() + kPause >= deadline) {
            if (!link) spdlog::critical("--world {}: {}", url, ua::statusName(link.status()));
            return link;
        }
        if (!told) {
            spdlog::warn("--world {}: {}; waiting up to {} s for the world model", url,
                         ua::statusName(link.status()), kPatience.count());
            told = true;
        }
        std::this_thread::sleep_for(kPause);  // nothing to wait on but a server that restarts
    }
}

}  // namespace

WorldConnection::WorldConnection(std::string url, std::string robot, Then then)
    : url_(std::move(url)), robot_(std::move(robot)), then_(std::move(then)) {}

WorldConnection::~WorldConnection() {
    if (link_.valid()) link_.wait();
}

void WorldConnection::start(const ua::ClientSecurity& security, const std::string& applicationUri) {
    if (link_.valid()) return;
    ua::ClientConfig config;
    config.applicationUri = applicationUri;
    config.sessionName = "world link";
    config.security = security;
    link_ = std::async(std::launch::async,
                       [url = url_, robot = robot_, then = then_, config = std::move(config)] {
                           auto link = connectWorld(url, config, robot);
                           if (link && then) then(**link);
                           return link;
                       });
}

ua::Result<std::unique_ptr<devices::WorldLink>> WorldConnection::take() {
    if (!link_.valid()) return ua::status::BadInvalidState;
    return link_.get();
}

}  // namespace skillcell::apps
