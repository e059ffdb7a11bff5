#pragma once
// MdnsResponder: one process's mDNS presence (RFC 6762 / DNS-SD, as OPC 10000-12 uses it),
// on Asio UDP multicast 224.0.0.251:5353 and [ff02::fb]:5353.
//
// - Publishing is libmdnsd's job: it holds our records (PTR, SRV, TXT, A), announces them,
//   re-announces them before their TTL runs out, sends the goodbyes (TTL 0) on withdraw() and
//   shutdown(), and answers legacy unicast queries.
// - Multicast queries are answered as RFC 6762 asks (ResponsePlanner): after a random delay,
//   aggregated, without what the querier knows or another responder just sent. libmdnsd's
//   own answering cannot (its delay is 20-120 us, known answers count whatever their TTL,
//   nothing limits repeats), so it does not see those queries.
// - Only a process with a subscriber browses (BrowseSchedule: after 20-120 ms, then backing
//   off up to `queryPeriod`), with its known answers in the query; and only it keeps the
//   records it hears fresh with refresh queries. A server that only announces never queries.
// - A browser that looks for LDSes alone (BrowseScope::DiscoveryServers: a server that
//   registers) asks for the LDS subtype (RFC 6763, 7.1), which our LDSes announce beside the
//   service type: only LDSes answer, its known answers list only LDSes, and it refreshes
//   only their records. On a segment of N servers that is what keeps their queries from
//   carrying N known answers each. An LDS of another vendor, which announces no subtype, is
//   found by its TXT caps, from its own announcements and from the answers to other
//   browsers; a query for every server at each one's start cost 18 datagrams per server on a
//   segment of 200 starting together, against 5 without it (skillcell_bench_cell_scale).
// - What others announce goes into our ServiceCache (TTL-honouring, see service_cache.hpp),
//   whose changes reach subscribers as "announced" / "gone" events.
// - When a link we use comes back (carrier again, LinkMonitor), we announce our records again,
//   twice, a second apart, and a browser asks again from its shortest interval (RFC 6762,
//   8.3 and 13): a host cut off for longer than the TTL is found, and finds the others, at
//   once rather than at the next refresh or query.
// - Every datagram is checked by parseDnsMessage() first; a malformed one is counted and
//   dropped, and never reaches libmdnsd.
// - IPv4 (224.0.0.251) always, and IPv6 (ff02::fb) on the interfaces that have it: every
//   datagram goes out on both, and both are listened to.
//
// Threading: everything runs on the executor given to create(), which must not run handlers
// concurrently. Listeners are called on it. The responder lives while its loops run
// (they hold a shared_ptr); shutdown() ends them.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/ip/udp.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "ua/discovery/browse_schedule.hpp"
#include "ua/discovery/dns_message.hpp"
#include "ua/discovery/link_monitor.hpp"
#include "ua/discovery/network_interfaces.hpp"
#include "ua/discovery/response_planner.hpp"
#include "ua/discovery/service_cache.hpp"
#include "ua/types/result.hpp"

struct mdns_adapter;
struct mdns_adapter_record;

namespace skillcell::ua::mdns {

struct MdnsConfig {
    MdnsConfig() = default;  // not an aggregate: see ClientConfig
    /// TTL of the records we publish; peers drop us this long after our last word.
    std::chrono::seconds recordTtl{120};
    /// The longest interval between a browser's queries for every OPC UA server: they go out
    /// at once, then after 1 s, 2 s, 4 s ... up to this (RFC 6762, 5.2). Records about to
    /// expire are asked for on their own schedule, at 80-95 % of their TTL.
    std::chrono::milliseconds queryPeriod{std::chrono::minutes(60)};
    /// Interface names; empty: see chooseMdnsInterfaces().
    std::vector<std::string> interfaces;
    /// Our host name, without ".local"; empty: gethostname().
    std::string hostName;
    std::uint16_t port = 5353;
    /// Which IP versions carry mDNS: IPv4 (224.0.0.251) and, where an interface has IPv6,
    /// IPv6 (ff02::fb). The records are the same on both; discovery URLs use IPv4 addresses.
    bool ipv4 = true;
    bool ipv6 = true;
};

/// What a subscriber looks for: every OPC UA server (a detector, an LDS), or the Local
/// Discovery Servers alone (a server that registers with them).
enum class BrowseScope : std::uint8_t { AllServers, DiscoveryServers };

/// A server to announce.
struct ServiceAnnouncement {
    std::string name;  // the mDNS server name: one DNS label (1..63 bytes, no dots)
    std::uint16_t port = 0;
    std::string path;  // the discovery URL's path, e.g. "/" or ""
    std::vector<std::string> capabilities;
    /// For a server announced on its behalf by an LDS: its address. Empty: this host.
    std::optional<Ipv4> address;
};

/// Checks an mDNS server name: BadInvalidArgument unless it is one DNS label.
[[nodiscard]] StatusCode validateServerName(std::string_view name);

class MdnsResponder : public std::enable_shared_from_this<MdnsResponder> {
public:
    using Listener = std::function<void(const ServiceEvent&)>;

    struct Stats {
        std::uint64_t received = 0;
        std::uint64_t malformed = 0;
        std::uint64_t sent = 0;
        std::uint64_t sendErrors = 0;
        std::uint64_t queriesSent = 0;    // datagrams of our queries
        std::uint64_t answersSent = 0;    // datagrams of our answers to queries
        std::uint64_t queriesHeard = 0;   // others' queries
        std::uint64_t queriesSpared = 0;  // ours that another's same question stood for (7.3)
    };

    /// Opens and binds the socket and joins the group on the chosen interfaces.
    /// BadResourceUnavailable (with `error` saying why) when that is not possible.
    [[nodiscard]] static Result<std::shared_ptr<MdnsResponder>> create(
        asio::any_io_executor executor, MdnsConfig config, std::string* error = nullptr);
    ~MdnsResponder();
    MdnsResponder(const MdnsResponder&) = delete;
    MdnsResponder& operator=(const MdnsResponder&) = delete;

    /// Starts receiving; a subscriber's browsing starts with it (see subscribe()).
    void start();
    /// Publishes (or republishes) a server. BadInvalidArgument for a bad name or port.
    StatusCode announce(const ServiceAnnouncement& announcement);
    /// Withdraws one server with a goodbye.
    void withdraw(std::string_view name);
    /// Goodbyes for everything published, then closes the socket. Idempotent.
    void shutdown();
    /// Asks the network for every OPC UA server now, and backs off again from 1 s.
    void queryNow();

    /// Calls `listener` with an Announced event for every server known now, then with every
    /// change (of every server heard, whatever the scope). Returns the id for unsubscribe().
    /// The first subscriber starts browsing: the first query goes out within 20-120 ms (RFC
    /// 6762, 5.2), so that servers started earlier are found now, unless another host asked
    /// the same meanwhile (its answers reach us); the first AllServers subscriber after
    /// DiscoveryServers ones starts it again for every server.
    std::size_t subscribe(Listener listener, BrowseScope scope = BrowseScope::AllServers);
    void unsubscribe(std::size_t id);

    [[nodiscard]] std::vector<ServiceInstance> services() const { return cache_.services(); }
    [[nodiscard]] const std::vector<NetworkInterface>& interfaces() const { return nics_; }
    [[nodiscard]] const std::string& hostName() const { return hostName_; }
    [[nodiscard]] const MdnsConfig& config() const { return config_; }
    [[nodiscard]] Stats stats() const { return stats_; }
    /// Records of ours waiting for their random delay to send them (see ResponsePlanner).
    [[nodiscard]] std::size_t pendingAnswers() const { return planner_.pendingCount(); }

    /// Handles one received datagram (public for tests and the fuzzer).
    void handleDatagram(std::span<const std::uint8_t> bytes, const Ipv4& source,
                        std::uint16_t sourcePort);

private:
    struct AdapterDeleter {
        void operator()(mdns_adapter* a) const;
    };
    struct Published {
        ServiceAnnouncement announcement;
        std::vector<mdns_adapter_record*> records;  // PTR, SRV, TXT (and A when on behalf)
        std::string hostFqdn;
    };

    MdnsResponder(asio::any_io_executor executor, MdnsConfig config);
    asio::awaitable<void> receiveLoop(asio::ip::udp::socket& socket);
    /// Opens the IPv6 socket and joins ff02::fb where interfaces have IPv6; why not, if not.
    bool openIpv6(std::string& why);
    asio::awaitable<void> timerLoop();
    void wake();
    /// wake(), only when what a received datagram changed is due before the timer's time:
    /// a round of the timer loop per datagram is most of a datagram's cost in a large cell.
    void wakeIfSooner();
    void feedLibmdnsd(std::span<const std::uint8_t> bytes, const Ipv4& source,
                      std::uint16_t sourcePort);
    void answerWithAdditionals(const DnsMessage& query, const Ipv4& source);
    void handleQuery(const DnsMessage& query, std::span<const std::uint8_t> bytes,
                     const Ipv4& source, std::uint16_t sourcePort);
    [[nodiscard]] bool isOwnQuery(const DnsMessage& query,
                                  std::span<const std::uint8_t> bytes) const;
    /// Browsing from the shortest interval; the first query after `firstDelay`.
    void startBrowsing(Clock::duration firstDelay);
    /// What our browse queries ask for: the service type, or the LDS subtype.
    [[nodiscard]] std::string browseName() const { return cache_.browseName(); }
    void rebuildOwnRecords();
    void flushOutput();
    void sendMulticast(std::span<const std::uint8_t> bytes);
    void sendQuestions(std::vector<DnsQuestion> questions, Clock::time_point now);
    void sendAnswers(std::vector<DnsRecord> records);
    void dispatch(const std::vector<ServiceEvent>& events);
    void ensureHostRecords();
    void withdrawRecords(Published& p);
    /// A link of ours came up again: announce again, ask again.
    void linkCameUp(unsigned index);

    asio::any_io_executor executor_;
    MdnsConfig config_;
    asio::ip::udp::socket socket_;   // IPv4
    asio::ip::udp::socket socket6_;  // IPv6, when available
    asio::steady_timer timer_;
    std::vector<NetworkInterface> nics_;
    std::vector<unsigned> v6Interfaces_;  // interface indices that joined ff02::fb
    std::string hostName_;
    std::unique_ptr<mdns_adapter, AdapterDeleter> mdnsd_;  // libmdnsd
    std::vector<mdns_adapter_record*> hostRecords_;        // our A records
    std::map<std::string, Published> published_;           // folded name -> records
    ServiceCache cache_;
    BrowseSchedule browse_;
    ResponsePlanner planner_;
    std::minstd_rand random_;  // the first query's delay
    // Our queries carry this id, and we keep a digest of the last ones we sent, so that the
    // copy the loopback brings back is not taken for another host's query.
    std::uint16_t queryId_ = 0;
    std::vector<std::size_t> recentQueries_;
    std::map<std::size_t, Listener> listeners_;
    std::size_t nextListener_ = 1;
    BrowseScope scope_ = BrowseScope::DiscoveryServers;  // the widest of the subscribers'
    Stats stats_;
    std::shared_ptr<LinkMonitor> links_;
    /// When our records go out once more after a link came up (the second announcement).
    std::optional<Clock::time_point> announceAgainAt_;
    bool started_ = false;
    bool closed_ = false;
};

}  // namespace skillcell::ua::mdns
