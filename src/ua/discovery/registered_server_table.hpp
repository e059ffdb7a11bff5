#pragma once
// RegisteredServerTable: the servers registered with a Local Discovery Server through
// RegisterServer / RegisterServer2 (OPC 10000-4, 5.4.5 and 5.4.6; OPC 10000-12, 4.3). Pure
// logic with the time passed in.
//
// A registration ends when the server says it is offline (isOnline = false), when it has
// not renewed itself within the timeout (servers re-register every 10 minutes by default),
// or when its semaphore file disappears.
#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ua/discovery/service_cache.hpp"
#include "ua/messages/discovery.hpp"

namespace skillcell::ua::lds {

using Clock = std::chrono::steady_clock;

struct Registration {
    RegisteredServer server;
    std::optional<MdnsDiscoveryConfiguration> mdns;  // from RegisterServer2
    Clock::time_point renewed;
};

struct RegistrationLimits {
    std::size_t maxServers = 1000;
    std::size_t maxUrls = 32;
    std::size_t maxNames = 32;
    std::size_t maxStringBytes = 4096;
};

class RegisteredServerTable {
public:
    explicit RegisteredServerTable(std::chrono::seconds timeout, RegistrationLimits limits = {});

    /// Checks a registration as the standard asks: BadServerUriInvalid (no or an oversized
    /// serverUri), BadServerNameMissing, BadDiscoveryUrlMissing (none, or none usable),
    /// BadSemaphoreFileMissing (a path to a file that does not exist), BadInvalidArgument
    /// (a Client registering itself, an unknown ApplicationType, a malformed URL, too
    /// many entries). An offline registration only needs its serverUri.
    [[nodiscard]] StatusCode validate(const RegisteredServer& server) const;

    enum class Change : std::uint8_t { Added, Renewed, Updated, Removed, NotFound };
    /// Adds, renews, updates or (isOnline = false) removes. Call validate() first.
    /// BadResourceUnavailable when the table is full.
    Result<Change> apply(const RegisteredServer& server,
                         std::optional<MdnsDiscoveryConfiguration> mdns, Clock::time_point now);
    /// Removes one registration; false if there was none.
    bool remove(const std::string& serverUri);
    /// Removes the registrations that timed out or whose semaphore file is gone.
    std::vector<Registration> expire(Clock::time_point now);

    /// FindServers: the registered servers as ApplicationDescriptions, filtered by
    /// serverUris (empty: all), the name in the first of `localeIds` that has one.
    [[nodiscard]] std::vector<ApplicationDescription> describe(
        const std::vector<String>& serverUris, const std::vector<String>& localeIds) const;

    [[nodiscard]] const Registration* find(const std::string& serverUri) const;
    /// The registration whose mDNS server name is `name` (case-insensitive), if any.
    [[nodiscard]] const Registration* findByMdnsName(std::string_view name) const;
    [[nodiscard]] std::size_t size() const { return servers_.size(); }

private:
    std::chrono::seconds timeout_;
    RegistrationLimits limits_;
    std::map<std::string, Registration> servers_;  // by serverUri
};

/// The mDNS server name a registration is announced under: mdnsServerName, or derived from
/// the first server name.
[[nodiscard]] std::string mdnsNameOf(const Registration& r);

}  // namespace skillcell::ua::lds
