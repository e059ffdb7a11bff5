#pragma once
// ServerRegistrar: a server's registration life cycle with the Local Discovery Servers it
// discovers (OPC 10000-12, 4.3.3). Every server announced by mDNS with the "LDS" capability
// gets a RegisterServer2 (RegisterServer for an LDS without it) at once, again every
// `period` (the standard's 10 minutes by default), and an offline registration
// (isOnline = false) on stop(). An LDS that goes away and comes back (a cable pulled and
// plugged in again) is registered with again as soon as it is seen.
//
// Threading: on the responder's executor.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "ua/client/client.hpp"
#include "ua/discovery/mdns_responder.hpp"
#include "ua/messages/discovery.hpp"

namespace skillcell::ua::lds {

struct RegistrarConfig {
    RegistrarConfig() = default;
    std::chrono::seconds period{600};
    /// For connecting and for each request.
    std::chrono::milliseconds timeout{2000};
    /// The channel RegisterServer2 goes over (no session is opened): a secured LDS takes
    /// registrations only over a secured channel from a server whose certificate it trusts.
    ClientSecurity security;
};

class ServerRegistrar : public std::enable_shared_from_this<ServerRegistrar> {
public:
    /// `self` describes this server; `mdns` is how it is announced (its mdnsServerName is
    /// also how the registrar recognises, and skips, its own announcement).
    [[nodiscard]] static std::shared_ptr<ServerRegistrar> create(
        asio::any_io_executor executor, std::shared_ptr<mdns::MdnsResponder> responder,
        RegisteredServer self, MdnsDiscoveryConfiguration mdns, RegistrarConfig config = {});
    ~ServerRegistrar();
    ServerRegistrar(const ServerRegistrar&) = delete;
    ServerRegistrar& operator=(const ServerRegistrar&) = delete;

    void start();
    /// Ends the registrations in flight (their connections dropped, their coroutines waited
    /// for, bounded by the timeout), then unregisters from every LDS it registered with
    /// (each bounded by the timeout). After it, nothing of the registrar is left suspended on
    /// the executor: a process may stop its io_context at once without leaving coroutine
    /// frames behind.
    asio::awaitable<void> stop();

    /// Discovery URLs of the LDSs it is registered with now.
    [[nodiscard]] std::vector<std::string> registeredWith() const;

private:
    struct Target {
        std::string url;
        std::shared_ptr<asio::steady_timer> timer;
        bool registered = false;
        std::uint64_t generation = 0;
    };

    ServerRegistrar(asio::any_io_executor executor, std::shared_ptr<mdns::MdnsResponder> responder,
                    RegisteredServer self, MdnsDiscoveryConfiguration mdns, RegistrarConfig config);
    void onMdnsEvent(const mdns::ServiceEvent& event);
    asio::awaitable<void> registrationLoop(std::string key, std::uint64_t generation);
    asio::awaitable<StatusCode> sendRegistration(std::string url, bool online);

    asio::any_io_executor executor_;
    std::shared_ptr<mdns::MdnsResponder> responder_;
    RegisteredServer self_;
    MdnsDiscoveryConfiguration mdns_;
    RegistrarConfig config_;
    std::map<std::string, Target> targets_;  // folded LDS mDNS name
    std::size_t subscription_ = 0;
    std::uint64_t nextGeneration_ = 1;
    bool stopped_ = false;
    // The periodic registrations' clients while they run, so that stop() can drop their
    // connections; `registrationsEnded_` is cancelled when the last one ends.
    std::set<Client*> registering_;
    std::shared_ptr<asio::steady_timer> registrationsEnded_;
};

}  // namespace skillcell::ua::lds
