#pragma once
// ServiceCache: what mDNS says about the `_opcua-tcp._tcp` services on the network, with
// the TTL of every record honoured. Pure logic with the time passed in: the responder feeds
// it the messages it receives and asks it what expired and which refresh queries are due;
// tests drive it with a fake clock.
//
// A service instance is "announced" once its PTR, SRV, TXT and at least one A record are all
// known, and "gone" when one of them is withdrawn (a goodbye: TTL 0) or expires. Before a
// record expires the cache asks for it again at 80, 85, 90 and 95 % of its TTL, plus a random
// 0-2 % of its own (RFC 6762, 5.2), so a live server is kept and a vanished one is dropped when
// its TTL runs out. When another host asks the same question first, that counts as our refresh
// (7.3): on a segment of many browsers each record is asked for about once, not once by each.
//
// Its cost per message is in proportion to the message, not to the cache: every process of a
// cell browses (a registrar looks for its LDS) and hears every answer on the segment, so a
// scan of the whole cache per datagram made a cell's start-up cost grow as N^3. Records' times
// are kept in a queue (one entry per record, moved later lazily: an entry that comes due
// early is put back at the record's current time), and expire() and refreshQueries() look
// only at what is due.
#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <queue>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "ua/discovery/dns_message.hpp"

namespace skillcell::ua::mdns {

inline constexpr std::string_view kOpcUaServiceType = "_opcua-tcp._tcp.local";
/// The capability of a Local Discovery Server (OPC 10000-12, Annex D).
inline constexpr std::string_view kLdsCapability = "LDS";

/// The DNS-SD subtype (RFC 6763, 7.1) under which a server with `capability` is announced
/// besides its service type, so that who looks for those servers alone asks only them:
/// "_lds._sub._opcua-tcp._tcp.local" for "LDS". OPC 10000-12 defines no subtypes; an LDS of
/// ours announces this one, and other vendors' LDSes are found by their TXT caps.
[[nodiscard]] std::string subtypeName(std::string_view capability,
                                      std::string_view serviceType = kOpcUaServiceType);

using Clock = std::chrono::steady_clock;
using Ipv4 = std::array<std::uint8_t, 4>;

[[nodiscard]] std::string toString(const Ipv4& address);

/// The address a host name spells when it is an IPv4 literal ("127.0.0.1"): some
/// responders (node-opcua's) put one into the SRV target and send no A record.
[[nodiscard]] std::optional<Ipv4> parseIpv4Literal(std::string_view name);

/// One OPC UA server as mDNS describes it (OPC 10000-12, 4.3.4).
struct ServiceInstance {
    std::string name;  // the instance label: the server's mDNS name
    std::string host;  // the SRV target
    std::uint16_t port = 0;
    std::string path;                       // TXT path=, with its leading '/' (or empty)
    std::vector<std::string> capabilities;  // TXT caps=
    /// The address to reach it by: the A record that matches the sender of the records when
    /// there is one (so a peer on another host gets an address it can route to).
    Ipv4 address{};

    /// "opc.tcp://a.b.c.d:port/path": an address, never a host name that the peer might not
    /// be able to resolve.
    [[nodiscard]] std::string discoveryUrl() const;
    [[nodiscard]] bool hasCapability(std::string_view cap) const;
    bool operator==(const ServiceInstance&) const = default;
};

/// Whether `capabilities` (a TXT caps= list, ours or another server's) holds `cap`, in any case.
[[nodiscard]] bool hasCapability(const std::vector<std::string>& capabilities,
                                 std::string_view cap);

enum class RemovalReason : std::uint8_t { Goodbye, Expired };
[[nodiscard]] std::string_view toString(RemovalReason reason);

struct ServiceEvent {
    enum class Kind : std::uint8_t { Announced, Gone };
    Kind kind = Kind::Announced;
    ServiceInstance instance;  // for Gone: as it was last announced
    RemovalReason reason = RemovalReason::Expired;
};

class ServiceCache {
public:
    /// `jitterSeed`: the seed of the random part of refresh times; none: no random part
    /// (tests that expect exact times).
    explicit ServiceCache(std::string serviceType = std::string(kOpcUaServiceType),
                          std::optional<std::uint32_t> jitterSeed = std::nullopt);

    /// Takes in every record of a received message (answers and additional records alike).
    /// `source` is the sender's address. Returns what changed.
    std::vector<ServiceEvent> ingest(const DnsMessage& message, const Ipv4& source,
                                     Clock::time_point now);
    /// Drops what expired by `now`.
    std::vector<ServiceEvent> expire(Clock::time_point now);
    /// The questions due by `now`: refreshes of records before they expire (each asked once
    /// per threshold), and the address of an SRV target that came without one.
    std::vector<DnsQuestion> refreshQueries(Clock::time_point now);
    /// The next time expire() or refreshQueries() has something to do (perhaps earlier: a
    /// record renewed since; never later). The distant past when a question is waiting.
    [[nodiscard]] std::optional<Clock::time_point> nextDeadline() const;
    /// The known answers for a browse query (RFC 6762, 7.1) for `browseName` (the service
    /// type, or a subtype of it): the PTR records with more than half of their TTL left, with
    /// the TTL they have left; for a subtype, those of the instances with its capability.
    [[nodiscard]] std::vector<DnsRecord> knownAnswers(Clock::time_point now,
                                                      std::string_view browseName) const;
    [[nodiscard]] std::vector<DnsRecord> knownAnswers(Clock::time_point now) const {
        return knownAnswers(now, serviceType_);
    }
    /// What this cache's owner wants: every server (none), or only the servers with a
    /// capability (a server looking for its LDS). With a capability, an instance whose TXT
    /// says it lacks it is not kept (nor the addresses of hosts that only such instances
    /// name): a new detector's browse brings every server's answer to every process of the
    /// segment, and a registrar stored and indexed them all. Instances whose TXT is not known
    /// yet are kept, but not asked for again. The refresh of a PTR asks for the subtype.
    void setInterest(std::optional<std::string> capability);
    /// The name a browse query of this cache's owner asks for: the service type, or the
    /// subtype of the capability of interest.
    [[nodiscard]] std::string browseName() const;
    /// Another host asked `question`, and holds `knownByAsker` (the PTR targets, folded, of its
    /// known answers): a refresh of ours that is due soon and that the answers will renew
    /// counts as asked (RFC 6762, 7.3).
    void questionSeen(const DnsQuestion& question, const std::set<std::string>& knownByAsker,
                      Clock::time_point now);
    /// Whether every PTR target in `targets` (folded) is in our known answers now: then a
    /// browse query of another host with those known answers brings us everything ours would.
    [[nodiscard]] bool knowsAll(const std::set<std::string>& targets, Clock::time_point now) const;

    [[nodiscard]] std::vector<ServiceInstance> services() const;
    [[nodiscard]] std::size_t size() const { return announced_.size(); }
    [[nodiscard]] const std::string& serviceType() const { return serviceType_; }
    /// Entries in the queue of record times (for tests: it stays bounded).
    [[nodiscard]] std::size_t queued() const { return queue_.size(); }

private:
    struct Timed {
        Clock::time_point received;
        std::chrono::seconds ttl{0};
        int refreshesAsked = 0;
        int jitterPermille = 0;  // 0..20: the random part of the refresh times
        /// When this record's entry in the queue comes due (none: not queued). Never later
        /// than the record's expiry or its next refresh, when that one counts.
        std::optional<Clock::time_point> scheduledAt;
        [[nodiscard]] Clock::time_point expiry() const { return received + ttl; }
        [[nodiscard]] std::optional<Clock::time_point> nextRefresh() const;
    };
    struct Pointer : Timed {
        std::string instance;  // full instance name, case kept
    };
    struct Srv : Timed {
        std::string host;  // folded
        std::uint16_t port = 0;
        Ipv4 sender{};  // who sent it
    };
    struct Txt : Timed {
        std::vector<std::string> strings;
    };
    struct Address : Timed {
        Ipv4 ip{};
    };

    enum class RecordKind : std::uint8_t { Ptr, Srv, Txt, Address };
    /// A record's time in the queue: its kind, its key (an instance, or a host for an
    /// address) and, for an address, which one.
    struct Due {
        Clock::time_point at;
        RecordKind kind = RecordKind::Ptr;
        std::string key;
        Ipv4 ip{};
        friend bool operator>(const Due& a, const Due& b) { return a.at > b.at; }
    };

    /// The record a queue entry names, or null when it is gone.
    Timed* recordOf(const Due& due);
    /// Whether the refreshes of this record are asked for (setInterest).
    [[nodiscard]] bool refreshed(const Due& due) const;
    /// Replaces `record` by `fresh` (a new copy heard), keeping its place in the queue, and
    /// queues it earlier if the copy is due sooner.
    template <class Record>
    void renew(Record& record, Record fresh, RecordKind kind, const std::string& key,
               const Ipv4& ip = {}) {
        fresh.scheduledAt = record.scheduledAt;
        record = std::move(fresh);
        schedule(record, kind, key, ip);
    }
    /// Adds to `keys` the instances whose SRV names one of `hosts` (an announced instance's
    /// host is its SRV's: reconcile() keeps them so).
    void addInstancesOn(const std::set<std::string>& hosts, std::set<std::string>& keys) const;
    /// With an interest (setInterest): the instances (folded) whose TXT in `message` shows
    /// they lack the capability. None without an interest.
    [[nodiscard]] std::set<std::string> withoutInterest(const DnsMessage& message) const;
    /// Drops the PTR, SRV and TXT of instance `key`; whether there was any.
    bool forget(const std::string& key);
    /// Stores or replaces the SRV of instance `key`, keeping instancesOnHost_ in step.
    void putSrv(const std::string& key, Srv srv);
    /// Erases the SRV of instance `key`, if any, keeping instancesOnHost_ in step.
    void eraseSrv(const std::string& key);
    /// Queues `t` (of kind/key/ip) at its next time, unless it is queued as early already.
    void schedule(Timed& t, RecordKind kind, const std::string& key, const Ipv4& ip = {});
    /// Makes the queue again from the records, one entry each (kMaxQueued reached).
    void requeueAll();
    /// Queues the records of instance `key` again (it became interesting: its refreshes count).
    void scheduleInstance(const std::string& key);
    /// Takes what is due by `now` off the queue: expired records are erased (their instances
    /// go to expiredKeys_), due refreshes become questions (refreshQuestions_).
    void processDue(Clock::time_point now);

    /// Returns whether an address record was added or removed (else a refresh, or another type).
    bool store(const DnsRecord& rr, const Ipv4& source, Clock::time_point now,
               std::vector<std::string>& goodbyes);
    /// Compares what is complete now with what was announced, for the instances `keys`;
    /// emits the differences.
    void reconcile(std::vector<ServiceEvent>& events, const std::vector<std::string>& goodbyes,
                   const std::set<std::string>& keys);
    [[nodiscard]] std::optional<ServiceInstance> complete(const std::string& key) const;
    /// Whether the instance `key` (folded) is one whose records are refreshed (setInterest).
    [[nodiscard]] bool interesting(const std::string& key) const;
    /// Whether the instance `key` (folded) is announced with `capability`.
    [[nodiscard]] bool announcedWith(const std::string& key, std::string_view capability) const;
    /// The capability (folded) a PTR name is the subtype of, e.g. "lds"; none for another name.
    [[nodiscard]] std::optional<std::string> subtypeCapability(const std::string& foldedName) const;

    std::string serviceType_;
    std::string serviceTypeKey_;
    std::map<std::string, Pointer> pointers_;  // folded instance name -> PTR
    std::map<std::string, Srv> srvs_;
    // Folded host -> the instances whose SRV names it. An address heard for a host touches
    // those instances only: looking them up in srvs_ instead cost a scan of the whole cache
    // per datagram, which a cold detection in a cell of 500 made every component pay 500 times.
    std::map<std::string, std::set<std::string>> instancesOnHost_;
    std::map<std::string, Txt> txts_;
    std::map<std::string, std::vector<Address>> addresses_;  // folded host -> A records
    std::map<std::string, ServiceInstance> announced_;       // folded instance name
    std::vector<DnsQuestion> pending_;  // A questions for SRV targets we have no address for
    std::priority_queue<Due, std::vector<Due>, std::greater<>> queue_;
    std::vector<DnsQuestion> refreshQuestions_;  // due, not yet returned by refreshQueries()
    std::set<std::string> expiredKeys_;   // instances touched by expiries, not yet reconciled
    std::set<std::string> expiredHosts_;  // hosts whose addresses expired, likewise
    std::optional<std::minstd_rand> jitter_;
    std::optional<std::string> interest_;  // the capability, as given
};

}  // namespace skillcell::ua::mdns
