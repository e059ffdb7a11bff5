#include "ua/discovery/response_planner.hpp"

#include <algorithm>

namespace skillcell::ua::mdns {

namespace {

constexpr auto kRepeatGap = std::chrono::seconds(1);
// What queries held for their known answers may take (7.2): a flood of them is bounded.
constexpr std::size_t kMaxHeldQueries = 256;
constexpr std::size_t kMaxHeldEntries = 4096;
// Answers due within this much of the first one leave with it.
constexpr auto kAggregationWindow = std::chrono::milliseconds(120);

bool hasType(const DnsRecord& r, DnsType t) {
    return r.type == static_cast<std::uint16_t>(t);
}

/// The TTL a querier has left of each record it lists as known, by identity.
using KnownAnswers = std::map<std::string, std::uint32_t>;

bool knownEnough(const KnownAnswers& known, const std::string& id, std::uint32_t ourTtl) {
    const auto it = known.find(id);
    return it != known.end() && std::uint64_t{it->second} * 2 >= ourTtl;
}

/// How long after it was last on the link a record is sent again unasked.
Clock::duration reannounceAfter(std::uint32_t ttlSeconds) {
    const auto ttl = std::chrono::duration_cast<Clock::duration>(std::chrono::seconds(ttlSeconds));
    // Never sooner than a record may be repeated at all.
    return std::max<Clock::duration>(ttlSeconds >= 4 ? ttl - std::chrono::seconds(2) : ttl / 2,
                                     kRepeatGap);
}

}  // namespace

std::string recordIdentity(const DnsRecord& r) {
    std::string id = foldCase(r.name) + '|' + std::to_string(r.type) + '|';
    switch (static_cast<DnsType>(r.type)) {
        case DnsType::Ptr:
            id += foldCase(r.target);
            break;
        case DnsType::Srv:
            id += std::to_string(r.port) + ' ' + foldCase(r.target);
            break;
        case DnsType::Txt:
            for (const auto& s : r.txt) id += s + '\x01';
            break;
        case DnsType::A:
            id.append(r.ipv4.begin(), r.ipv4.end());
            break;
        case DnsType::Aaaa:
            id.append(r.ipv6.begin(), r.ipv6.end());
            break;
        case DnsType::Any:
        default:
            id.append(r.rdata.begin(), r.rdata.end());
            break;
    }
    return id;
}

std::vector<DnsRecord> ResponsePlanner::own() const {
    std::vector<DnsRecord> out;
    out.reserve(own_.size());
    for (const auto& o : own_) out.push_back(o.record);
    return out;
}

void ResponsePlanner::setOwn(std::vector<DnsRecord> own) {
    own_.clear();
    ownById_.clear();
    for (auto& r : own) {
        std::string id = recordIdentity(r);
        ownById_.emplace(id, own_.size());
        own_.push_back({std::move(r), std::move(id)});
    }
    std::erase_if(pending_, [&](const auto& kv) { return !ownById_.contains(kv.first); });
    std::erase_if(lastSent_, [&](const auto& kv) { return !ownById_.contains(kv.first); });
}

/// Our records that a question asks for and the querier does not know (7.1), with what
/// browsers expect alongside (RFC 6763, 12.1): a known PTR brings nothing along.
std::vector<const ResponsePlanner::Own*> ResponsePlanner::answersTo(
    const DnsQuestion& q, const KnownAnswers& known) const {
    std::vector<const Own*> out;
    auto add = [&](const Own& o) {
        if (knownEnough(known, o.id, o.record.ttl)) return;
        if (std::find(out.begin(), out.end(), &o) == out.end()) out.push_back(&o);
    };
    auto addressesOf = [&](const std::string& host) {
        for (const auto& o : own_) {
            if (hasType(o.record, DnsType::A) && foldCase(o.record.name) == host) add(o);
        }
    };
    const std::string name = foldCase(q.name);
    const bool any = q.type == static_cast<std::uint16_t>(DnsType::Any);
    for (const auto& o : own_) {
        const DnsRecord& r = o.record;
        if (foldCase(r.name) != name || !(any || q.type == r.type)) continue;
        if (knownEnough(known, o.id, r.ttl)) continue;
        add(o);
        if (hasType(r, DnsType::Ptr)) {
            const std::string instance = foldCase(r.target);
            for (const auto& other : own_) {
                if (foldCase(other.record.name) != instance) continue;
                if (hasType(other.record, DnsType::Srv)) {
                    add(other);
                    addressesOf(foldCase(other.record.target));
                } else if (hasType(other.record, DnsType::Txt)) {
                    add(other);
                }
            }
        } else if (hasType(r, DnsType::Srv)) {
            addressesOf(foldCase(r.target));
        }
    }
    return out;
}

void ResponsePlanner::onQuery(const DnsMessage& query, const Ipv4& source, Clock::time_point now) {
    if (query.questions.empty()) {
        // More known answers of a query held for them (7.2: the datagrams after the first
        // carry known answers only): they join it. Known answers of a query we did not hold
        // are nothing to answer.
        if (auto held = held_.find(source); held != held_.end()) {
            auto& q = held->second.query;
            if (q.records.size() < kMaxHeldEntries) {  // a flood is bounded
                q.records.insert(q.records.end(), query.records.begin(), query.records.end());
            }
        }
        return;
    }
    // A datagram with questions is a query of its own, even from the address of a held one:
    // the processes of one host share its address (and port 5353), and another querier's
    // question must not be answered by the held query's known answers. Each cell of ours
    // has that on every host; a browser that was sent nothing waited for its next query.
    if (query.truncated && !held_.contains(source) && held_.size() < kMaxHeldQueries) {
        const auto wait =
            std::chrono::milliseconds(std::uniform_int_distribution<int>(400, 500)(random_));
        held_.emplace(source, Held{query, now + wait});
        return;
    }
    const auto delay =
        std::chrono::milliseconds(std::uniform_int_distribution<int>(20, 120)(random_));
    plan(query, now + delay);
}

void ResponsePlanner::plan(const DnsMessage& query, Clock::time_point due) {
    KnownAnswers known;
    for (const auto& rr : query.records) {
        if (!isClassIn(rr.rrclass)) continue;
        auto& ttl = known[recordIdentity(rr)];
        ttl = std::max(ttl, rr.ttl);
    }
    for (const auto& q : query.questions) {
        if (!isClassIn(q.qclass)) continue;
        for (const Own* o : answersTo(q, known)) schedule(*o, due);
    }
}

void ResponsePlanner::schedule(const Own& own, Clock::time_point due) {
    if (auto last = lastSent_.find(own.id); last != lastSent_.end()) {
        due = std::max(due, last->second + kRepeatGap);
    }
    auto [it, fresh] = pending_.try_emplace(own.id, Pending{own.record, due});
    if (!fresh) it->second.due = std::min(it->second.due, due);
}

void ResponsePlanner::onResponse(const DnsMessage& response, Clock::time_point now) {
    if (own_.empty()) return;
    for (const auto& rr : response.records) {
        if (!isClassIn(rr.rrclass)) continue;
        const std::string id = recordIdentity(rr);
        const auto it = ownById_.find(id);
        if (it == ownById_.end() || std::uint64_t{rr.ttl} * 2 < own_[it->second].record.ttl) {
            continue;
        }
        pending_.erase(id);
        lastSent_[id] = now;
    }
}

std::optional<Clock::time_point> ResponsePlanner::nextDeadline() const {
    std::optional<Clock::time_point> best;
    for (const auto& o : own_) {
        const auto last = lastSent_.find(o.id);
        if (last == lastSent_.end()) continue;
        const auto at = last->second + reannounceAfter(o.record.ttl);
        if (!best || at < *best) best = at;
    }
    for (const auto& [id, p] : pending_) {
        if (!best || p.due < *best) best = p.due;
    }
    for (const auto& [source, h] : held_) {
        if (!best || h.until < *best) best = h.until;
    }
    return best;
}

std::vector<DnsRecord> ResponsePlanner::takeDue(Clock::time_point now) {
    for (auto it = held_.begin(); it != held_.end();) {
        if (it->second.until > now) {
            ++it;
            continue;
        }
        plan(it->second.query, now);  // its random delay has passed already
        it = held_.erase(it);
    }
    // Records about to expire where nobody asked for them lately: sent again now.
    for (const auto& o : own_) {
        const auto last = lastSent_.find(o.id);
        if (last != lastSent_.end() && last->second + reannounceAfter(o.record.ttl) <= now) {
            schedule(o, now);
        }
    }
    if (pending_.empty()) return {};
    const auto firstDue =
        std::min_element(pending_.begin(), pending_.end(), [](const auto& a, const auto& b) {
            return a.second.due < b.second.due;
        })->second.due;
    if (firstDue > now) return {};
    // What falls due within the next random window leaves in the same datagram; a record
    // multicast less than a second ago waits for its own time.
    std::vector<DnsRecord> out;
    for (auto it = pending_.begin(); it != pending_.end();) {
        const auto last = lastSent_.find(it->first);
        const bool repeatTooSoon = last != lastSent_.end() && last->second + kRepeatGap > now;
        if (it->second.due > now + kAggregationWindow || repeatTooSoon) {
            ++it;
            continue;
        }
        lastSent_[it->first] = now;
        out.push_back(std::move(it->second.record));
        it = pending_.erase(it);
    }
    return out;
}

}  // namespace skillcell::ua::mdns
