#pragma once
// ResponsePlanner: which of our own mDNS records are sent, and when, in answer to the queries
// of others (RFC 6762). Pure logic with the time passed in; the responder feeds it what
// arrives and sends what it returns.
//
// - Our records are shared (many servers answer a browse), so an answer waits a random
//   20-120 ms (section 6), 400-500 ms when the querier said that more known answers follow
//   (7.2). Whatever is pending when the first answer is due leaves together, in as few
//   datagrams as fit (aggregation).
// - A record the querier lists as a known answer with at least half of its TTL left is not
//   sent (7.1), and a pending record is dropped when another responder sends it meanwhile with
//   at least half of our TTL (7.4).
// - A record is not multicast again within a second of its last multicast (6).
// - Answering a browse (PTR) brings the instance's SRV and TXT and the host's address along,
//   as browsers expect (RFC 6763, 12.1).
// - A record nobody asked for is sent again 2 s before its TTL runs out (half its TTL when
//   that is under 4 s, and never within a second), counted from when it was last on the link.
//   libmdnsd means to do that, but only for the first record of each of its hash buckets, so an SRV
//   whose TXT shares its name lived only as long as browsers asked for it in time.
#include <cstdint>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "ua/discovery/dns_message.hpp"
#include "ua/discovery/service_cache.hpp"

namespace skillcell::ua::mdns {

/// What makes two records the same record: name, type and data (not TTL or class).
[[nodiscard]] std::string recordIdentity(const DnsRecord& record);

class ResponsePlanner {
public:
    explicit ResponsePlanner(std::uint32_t seed) : random_(seed) {}

    /// Our records (full TTL), whenever they change: what queries are answered from. What is
    /// no longer among them is neither pending nor remembered.
    void setOwn(std::vector<DnsRecord> own);
    /// Our records, as setOwn() gave them.
    [[nodiscard]] std::vector<DnsRecord> own() const;
    /// A multicast query arrived from `source`: schedules the records of ours it asks for that
    /// the querier does not know yet.
    void onQuery(const DnsMessage& query, const Ipv4& source, Clock::time_point now);
    /// A response arrived (another responder's, or our own announcement looped back): the
    /// records of ours it carries with at least half of their TTL are on the link now, so
    /// their pending answers are dropped and none repeats them within a second.
    void onResponse(const DnsMessage& response, Clock::time_point now);

    /// When the next answer is due (or a query held for its known answers is complete, or a
    /// record is to be sent again before its TTL runs out); none when nothing is pending.
    [[nodiscard]] std::optional<Clock::time_point> nextDeadline() const;
    /// Once an answer is due: the pending records that leave now, together. Else nothing.
    [[nodiscard]] std::vector<DnsRecord> takeDue(Clock::time_point now);
    [[nodiscard]] std::size_t pendingCount() const { return pending_.size(); }

private:
    struct Own {
        DnsRecord record;
        std::string id;  // recordIdentity(record), computed once
    };
    struct Pending {
        DnsRecord record;
        Clock::time_point due;
    };
    struct Held {  // a query whose known answers continue in further datagrams (7.2)
        DnsMessage query;
        Clock::time_point until;
    };
    void plan(const DnsMessage& query, Clock::time_point due);
    void schedule(const Own& own, Clock::time_point due);
    [[nodiscard]] std::vector<const Own*> answersTo(
        const DnsQuestion& q, const std::map<std::string, std::uint32_t>& known) const;

    std::minstd_rand random_;
    std::vector<Own> own_;
    std::map<std::string, std::size_t> ownById_;  // id -> index in own_
    std::map<std::string, Pending> pending_;      // by recordIdentity()
    // When each of our records was last on the link, by recordIdentity().
    std::map<std::string, Clock::time_point> lastSent_;
    std::map<Ipv4, Held> held_;  // by querier
};

}  // namespace skillcell::ua::mdns
