#pragma once
// ServerWatcher: the callback API of discovery. "Announced" fires once a server that mDNS
// announced has also told us who it is (its ApplicationDescription, from GetEndpoints on
// the announced discovery URL); "gone" fires when its announcement is withdrawn or expires.
// The skill detector builds on this.
//
// Threading: on the responder's executor; the callbacks are called there.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>

#include "ua/discovery/mdns_responder.hpp"
#include "ua/messages/discovery.hpp"

namespace skillcell::ua::lds {

struct AnnouncedServer {
    mdns::ServiceInstance instance;
    std::string discoveryUrl;  // instance.discoveryUrl()
    ApplicationDescription application;
    /// What the server answered to GetEndpoints at discoveryUrl when it was described: a
    /// client connecting next can choose among these instead of asking again.
    std::vector<EndpointDescription> endpoints;
};

class ServerWatcher : public std::enable_shared_from_this<ServerWatcher> {
public:
    struct Callbacks {
        std::function<void(const AnnouncedServer&)> announced;
        std::function<void(const AnnouncedServer&, mdns::RemovalReason)> gone;
    };

    [[nodiscard]] static std::shared_ptr<ServerWatcher> create(
        asio::any_io_executor executor, std::shared_ptr<mdns::MdnsResponder> responder,
        Callbacks callbacks, std::chrono::milliseconds timeout = std::chrono::seconds(2));
    ~ServerWatcher();
    ServerWatcher(const ServerWatcher&) = delete;
    ServerWatcher& operator=(const ServerWatcher&) = delete;

    /// Reports what the responder already knows, then every change.
    void start();
    void stop();

    /// The servers announced and described so far.
    [[nodiscard]] std::vector<AnnouncedServer> servers() const;
    /// How many times a server was asked who it is (GetEndpoints), for tests and diagnosis.
    [[nodiscard]] std::uint64_t describesStarted() const { return describesStarted_; }

private:
    struct Entry {
        std::uint64_t generation = 0;
        bool described = false;
        bool describing = false;  // a describe() of this generation runs
        AnnouncedServer server;
    };

    ServerWatcher(asio::any_io_executor executor, std::shared_ptr<mdns::MdnsResponder> responder,
                  Callbacks callbacks, std::chrono::milliseconds timeout);
    void onMdnsEvent(const mdns::ServiceEvent& event);
    asio::awaitable<void> describe(std::string key, std::uint64_t generation);

    asio::any_io_executor executor_;
    std::shared_ptr<mdns::MdnsResponder> responder_;
    Callbacks callbacks_;
    std::chrono::milliseconds timeout_;
    std::map<std::string, Entry> entries_;  // folded mDNS name
    std::size_t subscription_ = 0;
    std::uint64_t nextGeneration_ = 1;
    std::uint64_t describesStarted_ = 0;
    bool stopped_ = false;
};

}  // namespace skillcell::ua::lds
