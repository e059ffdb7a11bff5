#pragma once
// LocalDiscoveryServer: turns a Server into a Local Discovery Server with the multicast
// extension (LDS-ME, OPC 10000-12, 4.3): RegisterServer, RegisterServer2, FindServers
// (this server and the registered ones) and FindServersOnNetwork (what mDNS sees).
//
// Servers that register with RegisterServer2 and an MdnsDiscoveryConfiguration are
// announced by mDNS on their behalf, unless they already announce themselves (every
// skillcell server does): then the LDS leaves their announcement to them, and their
// registration ends with their mDNS presence (a goodbye or an expiry), so FindServers never
// lists a server that the network has seen go.
//
// Threading: on the server's io_context thread, like the Server.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <functional>
#include <memory>
#include <set>

#include "ua/discovery/mdns_responder.hpp"
#include "ua/discovery/registered_server_table.hpp"
#include "ua/discovery/server_on_network_directory.hpp"
#include "ua/server/server.hpp"

namespace skillcell::ua::lds {

struct LdsConfig {
    LdsConfig() = default;
    /// A registration not renewed for this long ends (the standard's re-registration period
    /// is 10 minutes; a minute of grace).
    std::chrono::seconds registrationTimeout{660};
    RegistrationLimits limits;
    /// After a registration with mDNS, how long the LDS waits for the server to announce
    /// itself (asking the network meanwhile) before it announces the server on its behalf. A
    /// registration can arrive before the server's own announcement; two responders naming
    /// one instance with different SRV targets would make every cache flip between them.
    std::chrono::milliseconds selfAnnouncementGrace{1000};
};

/// What happened to a registration, for the observer (a skill detector in the component that
/// hosts the LDS learns of servers that register without announcing themselves).
enum class RegistrationChange : std::uint8_t {
    Registered,    // added, or updated with new content (not a plain renewal)
    Unregistered,  // isOnline = false, or its mDNS presence ended with a goodbye
    Expired,       // not renewed in time, semaphore file gone, or its mDNS records expired
};

class LocalDiscoveryServer : public std::enable_shared_from_this<LocalDiscoveryServer> {
public:
    /// Called on the server's thread after each change; `server` is the registration as it
    /// was last registered.
    using RegistrationObserver =
        std::function<void(RegistrationChange change, const RegisteredServer& server)>;

    /// `responder` may be null: an LDS without the multicast extension (FindServersOnNetwork
    /// then answers BadServiceUnsupported).
    [[nodiscard]] static std::shared_ptr<LocalDiscoveryServer> create(
        Server& server, std::shared_ptr<mdns::MdnsResponder> responder, LdsConfig config = {});
    ~LocalDiscoveryServer();
    LocalDiscoveryServer(const LocalDiscoveryServer&) = delete;
    LocalDiscoveryServer& operator=(const LocalDiscoveryServer&) = delete;

    /// Installs the services and starts expiring registrations.
    void start(asio::any_io_executor executor);
    /// Withdraws what it announced for others and stops its timer.
    void stop();

    /// One observer (a later call replaces it; an empty function removes it). The servers
    /// registered already are in registrations().describe({}, {}).
    void setRegistrationObserver(RegistrationObserver observer) { observer_ = std::move(observer); }

    [[nodiscard]] const RegisteredServerTable& registrations() const { return table_; }
    /// Whether the LDS announces the server by mDNS on its behalf now.
    [[nodiscard]] bool announcesOnBehalfOf(const std::string& serverUri) const {
        return announcedFor_.contains(serverUri);
    }
    /// Whether the LDS is still waiting to see if the server announces itself.
    [[nodiscard]] bool awaitsSelfAnnouncement(const std::string& serverUri) const {
        return graceTimers_.contains(serverUri);
    }
    [[nodiscard]] const ServerOnNetworkDirectory& directory() const { return directory_; }

private:
    LocalDiscoveryServer(Server& server, std::shared_ptr<mdns::MdnsResponder> responder,
                         LdsConfig config);
    StatusCode registerServer(const RegisteredServer& server,
                              std::optional<MdnsDiscoveryConfiguration> mdns);
    void onMdnsEvent(const mdns::ServiceEvent& event);
    /// Announces for `r` now, or after the grace when it does not announce itself yet.
    void scheduleAnnounceFor(const Registration& r);
    asio::awaitable<void> announceAfterGrace(std::string serverUri,
                                             std::shared_ptr<asio::steady_timer> timer);
    [[nodiscard]] bool announcesItself(const std::string& mdnsName) const;
    void announceFor(const Registration& r);
    void withdrawFor(const std::string& serverUri);
    void notify(RegistrationChange change, const RegisteredServer& server) const;
    asio::awaitable<void> expiryLoop();

    Server& server_;
    std::shared_ptr<mdns::MdnsResponder> responder_;
    LdsConfig config_;
    RegisteredServerTable table_;
    ServerOnNetworkDirectory directory_;
    std::map<std::string, std::string> announcedFor_;  // serverUri -> mDNS name we announce
    std::size_t subscription_ = 0;
    std::unique_ptr<asio::steady_timer> timer_;
    std::optional<asio::any_io_executor> executor_;
    std::map<std::string, std::shared_ptr<asio::steady_timer>> graceTimers_;  // serverUri ->
    RegistrationObserver observer_;
    bool stopped_ = false;
};

}  // namespace skillcell::ua::lds
