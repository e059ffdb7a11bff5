#include "world_connection.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <optional>
#include <thread>

#include "ua/crypto/primitives.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/pki/file_util.hpp"
#include "ua/types/connection_loss.hpp"

namespace skillcell::apps {

namespace {

/// The link's security with the world's certificate given: the strongest policy we have for
/// its key, SignAndEncrypt, and the certificate as the server's. Nothing when the file is not
/// a certificate we could use (the link then asks the world for its endpoints).
std::optional<ua::ClientConfig> pinnedTo(const std::string& file, ua::ClientConfig config) {
    std::vector<std::uint8_t> der = ua::pki::readWholeFile(file);
    if (der.empty()) {
        spdlog::warn("--world-certificate {}: cannot read it; asking the world for its endpoints",
                     file);
        return std::nullopt;
    }
    auto key = ua::crypto::AsymmetricKey::fromCertificate(der);
    if (!key) {
        spdlog::warn(
            "--world-certificate {}: not a DER certificate ({}); asking the world for "
            "its endpoints",
            file, ua::statusName(key.status()));
        return std::nullopt;
    }
    // Strongest last (securityPolicyProfiles()): the last one for this kind of key.
    const ua::crypto::SecurityPolicyProfile* chosen = nullptr;
    for (const auto& profile : ua::crypto::securityPolicyProfiles()) {
        if (profile.keyKind == key->kind()) chosen = &profile;
    }
    if (chosen == nullptr) return std::nullopt;
    config.security.policyUri = std::string(chosen->uri);
    config.security.mode = ua::MessageSecurityMode::SignAndEncrypt;
    config.serverCertificate = ua::ByteString(std::move(der));
    return config;
}

ua::Result<std::unique_ptr<devices::WorldLink>> connectWorld(const WorldAddress& address,
                                                             const ua::ClientConfig& config,
                                                             const std::string& robot) {
    constexpr auto kPatience = std::chrono::seconds(15);
    constexpr auto kPause = std::chrono::milliseconds(200);
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    const std::string& url = address.url;
    if (!address.certificateFile.empty() && config.security.choosesEndpoint()) {
        if (const auto pinned = pinnedTo(address.certificateFile, config)) {
            auto link = devices::WorldLink::connect(url, *pinned, robot);
            if (link) return link;
            // The world has another certificate, no such endpoint, or is not up yet: what
            // follows asks it (and waits for it) as a link without the certificate does.
            spdlog::info(
                "--world {}: with the certificate of {}: {}; asking the world for its "
                "endpoints",
                url, address.certificateFile, ua::statusName(link.status()));
        }
    }
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

void addWorldCertificateOption(CLI::App* cmd, WorldAddress& address) {
    cmd->add_option("--world-certificate", address.certificateFile,
                    "the world model's application certificate (DER), as the cell issued it: "
                    "the link opens its secure channel with it at once instead of asking the "
                    "world for its endpoints first (and asks when the world refuses it)")
        ->check(CLI::ExistingFile);
}

WorldConnection::WorldConnection(WorldAddress address, std::string robot, Then then)
    : address_(std::move(address)), robot_(std::move(robot)), then_(std::move(then)) {}

WorldConnection::~WorldConnection() {
    if (link_.valid()) link_.wait();
}

void WorldConnection::start(const ua::ClientSecurity& security, const std::string& applicationUri) {
    if (link_.valid()) return;
    ua::ClientConfig config;
    config.applicationUri = applicationUri;
    config.sessionName = "world link";
    config.security = security;
    link_ = std::async(std::launch::async, [address = address_, robot = robot_, then = then_,
                                            config = std::move(config)] {
        auto link = connectWorld(address, config, robot);
        if (link && then) then(**link);
        return link;
    });
}

ua::Result<std::unique_ptr<devices::WorldLink>> WorldConnection::take() {
    if (!link_.valid()) return ua::status::BadInvalidState;
    return link_.get();
}

}  // namespace skillcell::apps
