#include "ua/discovery/service_cache.hpp"

#include <algorithm>
#include <set>

namespace skillcell::ua::mdns {

namespace {

constexpr std::array<int, 4> kRefreshPercent = {80, 85, 90, 95};
// Bounds what a flood of records can make us keep (each map separately).
constexpr std::size_t kMaxEntries = 1024;
// Queue entries beyond one per record come from records whose time moved earlier (a shorter
// TTL); a sender that keeps shortening them would grow the queue without end: past this
// many, it is made again from the records, one entry each.
constexpr std::size_t kMaxQueued = 64 * kMaxEntries;

bool endsWith(std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

std::string firstLabel(std::string_view name) {
    return std::string(name.substr(0, name.find('.')));
}

/// The value of `key=` in a TXT record (keys compare case-insensitively, RFC 6763 6.4).
std::optional<std::string> txtValue(const std::vector<std::string>& strings, std::string_view key) {
    for (const auto& s : strings) {
        const auto eq = s.find('=');
        if (eq == std::string::npos) continue;
        if (foldCase(std::string_view(s).substr(0, eq)) == key) return s.substr(eq + 1);
    }
    return std::nullopt;
}

std::vector<std::string> splitCaps(std::string_view caps) {
    std::vector<std::string> out;
    while (!caps.empty()) {
        const auto comma = caps.find(',');
        std::string_view cap = caps.substr(0, comma);
        if (!cap.empty()) out.emplace_back(cap);
        caps = comma == std::string_view::npos ? std::string_view{} : caps.substr(comma + 1);
    }
    return out;
}

template <class Map>
bool roomFor(const Map& map, const std::string& key) {
    return map.size() < kMaxEntries || map.contains(key);
}

/// Adds `q` to `questions` unless the same question (name folded) is there already.
void addQuestion(std::vector<DnsQuestion>& questions, DnsQuestion q) {
    const bool dup = std::any_of(questions.begin(), questions.end(), [&](const DnsQuestion& o) {
        return o.type == q.type && foldCase(o.name) == foldCase(q.name);
    });
    if (!dup) questions.push_back(std::move(q));
}

/// Takes `key` out of the instances `index` holds for `host`, and the host once it has none.
void unindex(std::map<std::string, std::set<std::string>>& index, const std::string& host,
             const std::string& key) {
    if (auto on = index.find(host); on != index.end()) {
        on->second.erase(key);
        if (on->second.empty()) index.erase(on);
    }
}

}  // namespace

std::optional<Ipv4> parseIpv4Literal(std::string_view name) {
    Ipv4 out{};
    for (std::size_t i = 0; i < 4; ++i) {
        const auto dot = name.find('.');
        if ((dot == std::string_view::npos) != (i == 3)) return std::nullopt;
        const std::string_view part = name.substr(0, dot);
        if (part.empty() || part.size() > 3) return std::nullopt;
        unsigned value = 0;
        for (char c : part) {
            if (c < '0' || c > '9') return std::nullopt;
            value = value * 10 + static_cast<unsigned>(c - '0');
        }
        if (value > 255) return std::nullopt;
        out[i] = static_cast<std::uint8_t>(value);
        name = dot == std::string_view::npos ? std::string_view{} : name.substr(dot + 1);
    }
    return out;
}

std::string subtypeName(std::string_view capability, std::string_view serviceType) {
    return "_" + foldCase(capability) + "._sub." + std::string(serviceType);
}

std::string toString(const Ipv4& a) {
    return std::to_string(a[0]) + "." + std::to_string(a[1]) + "." + std::to_string(a[2]) + "." +
           std::to_string(a[3]);
}

std::string_view toString(RemovalReason reason) {
    return reason == RemovalReason::Goodbye ? "goodbye" : "expired";
}

std::string ServiceInstance::discoveryUrl() const {
    return "opc.tcp://" + toString(address) + ":" + std::to_string(port) + path;
}

bool hasCapability(const std::vector<std::string>& capabilities, std::string_view cap) {
    const std::string folded = foldCase(cap);
    return std::any_of(capabilities.begin(), capabilities.end(),
                       [&](const std::string& c) { return foldCase(c) == folded; });
}

bool ServiceInstance::hasCapability(std::string_view cap) const {
    return mdns::hasCapability(capabilities, cap);
}

std::optional<Clock::time_point> ServiceCache::Timed::nextRefresh() const {
    if (refreshesAsked >= static_cast<int>(kRefreshPercent.size())) return std::nullopt;
    const auto ttlMs = std::chrono::duration_cast<std::chrono::milliseconds>(ttl);
    const int permille =
        kRefreshPercent[static_cast<std::size_t>(refreshesAsked)] * 10 + jitterPermille;
    return received + ttlMs * permille / 1000;
}

ServiceCache::ServiceCache(std::string serviceType, std::optional<std::uint32_t> jitterSeed)
    : serviceType_(std::move(serviceType)), serviceTypeKey_(foldCase(serviceType_)) {
    if (jitterSeed) jitter_.emplace(*jitterSeed);
}

bool ServiceCache::store(const DnsRecord& rr, const Ipv4& source, Clock::time_point now,
                         std::vector<std::string>& goodbyes) {
    const std::string key = foldCase(rr.name);
    const int jitter = jitter_ ? static_cast<int>((*jitter_)() % 21) : 0;
    const Timed timed{now, std::chrono::seconds(rr.ttl), 0, jitter, std::nullopt};
    const bool goodbye = rr.ttl == 0;
    switch (static_cast<DnsType>(rr.type)) {
        case DnsType::Ptr: {
            // The type's PTR, or a subtype's (RFC 6763, 7.1): either names the instance.
            if (key != serviceTypeKey_ && !subtypeCapability(key)) return false;
            const std::string instance = foldCase(rr.target);
            if (!endsWith(instance, "." + serviceTypeKey_)) return false;
            if (goodbye) {
                pointers_.erase(instance);
                goodbyes.push_back(instance);
            } else if (roomFor(pointers_, instance)) {
                renew(pointers_[instance], Pointer{timed, rr.target}, RecordKind::Ptr, instance);
            }
            return false;
        }
        case DnsType::Srv:
            if (!endsWith(key, "." + serviceTypeKey_)) return false;
            if (goodbye) {
                eraseSrv(key);
                goodbyes.push_back(key);
            } else if (roomFor(srvs_, key)) {
                std::string host = foldCase(rr.target);
                const auto old = srvs_.find(key);
                const bool known = old != srvs_.end() && old->second.host == host;
                // A copy that came over IPv6 has no IPv4 sender: keep the one we know.
                const Ipv4 sender = (source == Ipv4{} && known) ? old->second.sender : source;
                const bool literal = parseIpv4Literal(host).has_value();
                putSrv(key, Srv{timed, std::move(host), rr.port, sender});
                // A target without an address (yet): ask for it, once per new target. The
                // A record often comes in the same message; asking then costs one datagram.
                if (!known && !literal && pending_.size() < 64) {
                    pending_.push_back(
                        {rr.target, static_cast<std::uint16_t>(DnsType::A), kClassIn});
                }
            }
            return false;
        case DnsType::Txt:
            if (!endsWith(key, "." + serviceTypeKey_)) return false;
            if (goodbye) {
                txts_.erase(key);
                goodbyes.push_back(key);
            } else if (roomFor(txts_, key)) {
                renew(txts_[key], Txt{timed, rr.txt}, RecordKind::Txt, key);
            }
            return false;
        case DnsType::A: {
            if (!roomFor(addresses_, key)) return false;
            auto& list = addresses_[key];
            const std::size_t before = list.size();
            bool changed = false;
            if (rr.cacheFlush() && !goodbye) {
                // RFC 6762 10.2: a cache-flush record replaces those older than a second.
                std::erase_if(list, [&](const Address& a) {
                    return a.ip != rr.ipv4 && now - a.received > std::chrono::seconds(1);
                });
                changed = list.size() != before;
            }
            auto it = std::find_if(list.begin(), list.end(),
                                   [&](const Address& a) { return a.ip == rr.ipv4; });
            if (goodbye) {
                if (it != list.end()) {
                    list.erase(it);
                    changed = true;
                }
                goodbyes.push_back(key);
            } else if (it != list.end()) {
                renew(*it, Address{timed, rr.ipv4}, RecordKind::Address, key, rr.ipv4);
            } else if (list.size() < 16) {
                list.push_back(Address{timed, rr.ipv4});
                schedule(list.back(), RecordKind::Address, key, rr.ipv4);
                changed = true;
            }
            if (list.empty()) addresses_.erase(key);
            return changed;
        }
        case DnsType::Aaaa:
        case DnsType::Any:
        default:
            return false;
    }
}

std::vector<ServiceEvent> ServiceCache::ingest(const DnsMessage& message, const Ipv4& source,
                                               Clock::time_point now) {
    std::vector<std::string> goodbyes;
    // Only the instances this message touched are looked at again: a flood of records
    // costs in proportion to its size, not to the size of the cache.
    std::set<std::string> touched;
    std::set<std::string> hosts;
    const auto isA = [](const DnsRecord& rr) {
        return rr.type == static_cast<std::uint16_t>(DnsType::A);
    };
    const std::set<std::string> others = withoutInterest(message);
    for (const auto& key : others) {
        if (forget(key)) touched.insert(key);
    }
    const auto instanceOf = [](const DnsRecord& rr) {
        return foldCase(rr.type == static_cast<std::uint16_t>(DnsType::Ptr) ? rr.target : rr.name);
    };
    for (const auto& rr : message.records) {
        if (!isClassIn(rr.rrclass) || isA(rr)) continue;
        std::string key = instanceOf(rr);
        if (others.contains(key)) continue;
        store(rr, source, now, goodbyes);
        if (interest_ && rr.type == static_cast<std::uint16_t>(DnsType::Txt) && rr.ttl > 0 &&
            (!pointers_.contains(key) || !srvs_.contains(key)) && pending_.size() < 64) {
            // An LDS we know only the TXT of (its capability came later): ask for the rest.
            addQuestion(pending_,
                        {browseName(), static_cast<std::uint16_t>(DnsType::Ptr), kClassIn});
        }
        touched.insert(std::move(key));
    }
    // Addresses after the SRVs that name their hosts, wherever they stand in the message.
    for (const auto& rr : message.records) {
        if (!isClassIn(rr.rrclass) || !isA(rr)) continue;
        std::string host = foldCase(rr.name);
        if (interest_ && !instancesOnHost_.contains(host)) continue;  // no instance of interest
        if (store(rr, source, now, goodbyes)) hosts.insert(std::move(host));
    }
    addInstancesOn(hosts, touched);
    std::vector<ServiceEvent> events;
    reconcile(events, goodbyes, touched);
    return events;
}

std::vector<ServiceEvent> ServiceCache::expire(Clock::time_point now) {
    processDue(now);
    std::set<std::string> keys;
    keys.swap(expiredKeys_);
    addInstancesOn(expiredHosts_, keys);
    expiredHosts_.clear();
    std::vector<ServiceEvent> events;
    if (!keys.empty()) reconcile(events, {}, keys);
    return events;
}

void ServiceCache::addInstancesOn(const std::set<std::string>& hosts,
                                  std::set<std::string>& keys) const {
    for (const auto& host : hosts) {
        if (auto it = instancesOnHost_.find(host); it != instancesOnHost_.end()) {
            keys.insert(it->second.begin(), it->second.end());
        }
    }
}

std::set<std::string> ServiceCache::withoutInterest(const DnsMessage& message) const {
    std::set<std::string> out;
    if (!interest_) return out;
    for (const auto& rr : message.records) {
        if (rr.type != static_cast<std::uint16_t>(DnsType::Txt) || rr.ttl == 0 ||
            !isClassIn(rr.rrclass)) {
            continue;
        }
        const auto caps = txtValue(rr.txt, "caps");
        if (!caps || !hasCapability(splitCaps(*caps), *interest_)) out.insert(foldCase(rr.name));
    }
    return out;
}

bool ServiceCache::forget(const std::string& key) {
    const bool had = pointers_.erase(key) + txts_.erase(key) > 0 || srvs_.contains(key);
    eraseSrv(key);
    return had;
}

void ServiceCache::putSrv(const std::string& key, Srv srv) {
    auto it = srvs_.find(key);
    if (it == srvs_.end()) {
        instancesOnHost_[srv.host].insert(key);
        it = srvs_.emplace(key, Srv{}).first;
    } else if (it->second.host != srv.host) {
        instancesOnHost_[srv.host].insert(key);
        unindex(instancesOnHost_, it->second.host, key);
    }
    renew(it->second, std::move(srv), RecordKind::Srv, key);
}

void ServiceCache::eraseSrv(const std::string& key) {
    const auto it = srvs_.find(key);
    if (it == srvs_.end()) return;
    unindex(instancesOnHost_, it->second.host, key);
    srvs_.erase(it);
}

ServiceCache::Timed* ServiceCache::recordOf(const Due& due) {
    switch (due.kind) {
        case RecordKind::Ptr: {
            auto it = pointers_.find(due.key);
            return it == pointers_.end() ? nullptr : &it->second;
        }
        case RecordKind::Srv: {
            auto it = srvs_.find(due.key);
            return it == srvs_.end() ? nullptr : &it->second;
        }
        case RecordKind::Txt: {
            auto it = txts_.find(due.key);
            return it == txts_.end() ? nullptr : &it->second;
        }
        case RecordKind::Address: {
            auto it = addresses_.find(due.key);
            if (it == addresses_.end()) return nullptr;
            auto a = std::find_if(it->second.begin(), it->second.end(),
                                  [&](const Address& x) { return x.ip == due.ip; });
            return a == it->second.end() ? nullptr : &*a;
        }
    }
    return nullptr;
}

bool ServiceCache::refreshed(const Due& due) const {
    switch (due.kind) {
        case RecordKind::Ptr:
            return interesting(due.key);
        case RecordKind::Srv:
        case RecordKind::Txt:
            return announced_.contains(due.key) && interesting(due.key);
        case RecordKind::Address: {  // the host of a live instance that counts
            const auto on = instancesOnHost_.find(due.key);
            return on != instancesOnHost_.end() &&
                   std::any_of(on->second.begin(), on->second.end(), [&](const auto& key) {
                       return announced_.contains(key) && interesting(key);
                   });
        }
    }
    return false;
}

void ServiceCache::schedule(Timed& t, RecordKind kind, const std::string& key, const Ipv4& ip) {
    // The refresh times count for every record here; refreshed() decides when they come.
    auto at = t.expiry();
    if (auto r = t.nextRefresh(); r && *r < at) at = *r;
    if (t.scheduledAt && *t.scheduledAt <= at) return;  // due as early already
    t.scheduledAt = at;
    queue_.push(Due{at, kind, key, ip});
    if (queue_.size() > kMaxQueued) requeueAll();
}

void ServiceCache::requeueAll() {
    queue_ = {};
    const auto again = [&](Timed& t, RecordKind kind, const std::string& key, const Ipv4& ip) {
        t.scheduledAt.reset();
        schedule(t, kind, key, ip);
    };
    for (auto& [key, p] : pointers_) again(p, RecordKind::Ptr, key, {});
    for (auto& [key, srv] : srvs_) again(srv, RecordKind::Srv, key, {});
    for (auto& [key, txt] : txts_) again(txt, RecordKind::Txt, key, {});
    for (auto& [host, list] : addresses_) {
        for (auto& a : list) again(a, RecordKind::Address, host, a.ip);
    }
}

void ServiceCache::scheduleInstance(const std::string& key) {
    if (auto it = pointers_.find(key); it != pointers_.end()) {
        schedule(it->second, RecordKind::Ptr, key);
    }
    if (auto it = txts_.find(key); it != txts_.end()) schedule(it->second, RecordKind::Txt, key);
    if (auto it = srvs_.find(key); it != srvs_.end()) {
        schedule(it->second, RecordKind::Srv, key);
        if (auto a = addresses_.find(it->second.host); a != addresses_.end()) {
            for (auto& address : a->second) {
                schedule(address, RecordKind::Address, it->second.host, address.ip);
            }
        }
    }
}

void ServiceCache::processDue(Clock::time_point now) {
    auto ask = [&](std::string name, DnsType type) {
        addQuestion(refreshQuestions_,
                    {std::move(name), static_cast<std::uint16_t>(type), kClassIn});
    };
    while (!queue_.empty() && queue_.top().at <= now) {
        const Due due = queue_.top();
        queue_.pop();
        Timed* t = recordOf(due);
        if (t == nullptr || t->scheduledAt != due.at) continue;  // gone, or queued again
        t->scheduledAt.reset();
        if (t->expiry() <= now) {
            switch (due.kind) {
                case RecordKind::Ptr:
                    pointers_.erase(due.key);
                    expiredKeys_.insert(due.key);
                    break;
                case RecordKind::Srv:
                    eraseSrv(due.key);
                    expiredKeys_.insert(due.key);
                    break;
                case RecordKind::Txt:
                    txts_.erase(due.key);
                    expiredKeys_.insert(due.key);
                    break;
                case RecordKind::Address: {
                    auto& list = addresses_[due.key];
                    std::erase_if(list, [&](const Address& a) { return a.ip == due.ip; });
                    if (list.empty()) addresses_.erase(due.key);
                    expiredHosts_.insert(due.key);
                    break;
                }
            }
            continue;
        }
        if (auto r = t->nextRefresh(); r && *r <= now) {
            if (!refreshed(due)) {
                // Not ours to ask now; queued at its expiry. Should it come to count (its
                // instance announced with the capability of interest), it is queued again.
                t->scheduledAt = t->expiry();
                queue_.push(Due{t->expiry(), due.kind, due.key, due.ip});
                continue;
            }
            // Several thresholds may have passed at once (a stalled loop): ask once, skip them.
            while (t->nextRefresh() && *t->nextRefresh() <= now) ++t->refreshesAsked;
            switch (due.kind) {
                case RecordKind::Ptr:
                    ask(browseName(), DnsType::Ptr);
                    break;
                case RecordKind::Srv: {
                    const auto p = pointers_.find(due.key);
                    const std::string instance =
                        p != pointers_.end() ? p->second.instance : due.key;
                    ask(instance, DnsType::Srv);
                    ask(instance, DnsType::Txt);
                    break;
                }
                case RecordKind::Txt: {
                    const auto p = pointers_.find(due.key);
                    ask(p != pointers_.end() ? p->second.instance : due.key, DnsType::Txt);
                    break;
                }
                case RecordKind::Address:
                    ask(due.key, DnsType::A);
                    break;
            }
        }
        schedule(*t, due.kind, due.key, due.ip);  // its next time (early entries: put back)
    }
}

std::optional<ServiceInstance> ServiceCache::complete(const std::string& key) const {
    const auto ptr = pointers_.find(key);
    const auto srv = srvs_.find(key);
    const auto txt = txts_.find(key);
    if (ptr == pointers_.end() || srv == srvs_.end() || txt == txts_.end()) return std::nullopt;
    const auto addrs = addresses_.find(srv->second.host);
    const auto literal = parseIpv4Literal(srv->second.host);
    if ((addrs == addresses_.end() || addrs->second.empty()) && !literal) return std::nullopt;

    ServiceInstance s;
    s.name = firstLabel(ptr->second.instance);
    s.host = srv->second.host;
    s.port = srv->second.port;
    if (auto path = txtValue(txt->second.strings, "path"); path && !path->empty()) {
        s.path = path->front() == '/' ? *path : "/" + *path;
    }
    if (auto caps = txtValue(txt->second.strings, "caps")) s.capabilities = splitCaps(*caps);
    if (literal) {
        s.address = *literal;
        return s;
    }
    // The address the SRV record came from, when the host claims it: that one routes back.
    const auto& list = addrs->second;
    auto viaSender = std::find_if(list.begin(), list.end(),
                                  [&](const Address& a) { return a.ip == srv->second.sender; });
    s.address = viaSender != list.end() ? viaSender->ip : list.front().ip;
    return s;
}

void ServiceCache::reconcile(std::vector<ServiceEvent>& events,
                             const std::vector<std::string>& goodbyes,
                             const std::set<std::string>& keys) {
    for (const auto& key : keys) {
        auto now = complete(key);
        auto was = announced_.find(key);
        if (now) {
            if (was == announced_.end() || was->second != *now) {
                events.push_back({ServiceEvent::Kind::Announced, *now, RemovalReason::Expired});
                announced_[key] = std::move(*now);
                scheduleInstance(key);  // its refreshes may count now
            }
        } else if (was != announced_.end()) {
            const bool bye = std::any_of(goodbyes.begin(), goodbyes.end(), [&](const auto& g) {
                return g == key || g == was->second.host;
            });
            events.push_back({ServiceEvent::Kind::Gone, was->second,
                              bye ? RemovalReason::Goodbye : RemovalReason::Expired});
            announced_.erase(was);
        }
    }
}

std::vector<DnsQuestion> ServiceCache::refreshQueries(Clock::time_point now) {
    processDue(now);
    std::vector<DnsQuestion> out;
    for (auto& q : pending_) {
        const auto addrs = addresses_.find(foldCase(q.name));
        if (addrs == addresses_.end() || addrs->second.empty()) out.push_back(std::move(q));
    }
    pending_.clear();
    for (auto& q : refreshQuestions_) addQuestion(out, std::move(q));
    refreshQuestions_.clear();
    return out;
}

std::optional<Clock::time_point> ServiceCache::nextDeadline() const {
    // Something to ask or report at once: a refresh or an expiry taken off the queue, or the
    // address of an SRV target that did not come with it (at most 64 of those).
    const bool unanswered = std::any_of(pending_.begin(), pending_.end(), [&](const auto& q) {
        const auto a = addresses_.find(foldCase(q.name));
        return a == addresses_.end() || a->second.empty();
    });
    if (unanswered || !refreshQuestions_.empty() || !expiredKeys_.empty() ||
        !expiredHosts_.empty()) {
        return Clock::time_point::min();
    }
    if (queue_.empty()) return std::nullopt;
    return queue_.top().at;  // perhaps early (a record renewed since), never late
}

std::vector<DnsRecord> ServiceCache::knownAnswers(Clock::time_point now,
                                                  std::string_view browseName) const {
    std::vector<DnsRecord> out;
    const std::string name = foldCase(browseName);
    const auto capability = subtypeCapability(name);
    if (name != serviceTypeKey_ && !capability) return out;
    for (const auto& [key, p] : pointers_) {
        const auto left = std::chrono::duration_cast<std::chrono::seconds>(p.expiry() - now);
        if (left * 2 <= p.ttl) continue;
        if (capability && !announcedWith(key, *capability)) continue;
        DnsRecord r;
        r.name = std::string(browseName);
        r.type = static_cast<std::uint16_t>(DnsType::Ptr);
        r.ttl = static_cast<std::uint32_t>(left.count());
        r.target = p.instance;
        out.push_back(std::move(r));
    }
    return out;
}

bool ServiceCache::knowsAll(const std::set<std::string>& targets, Clock::time_point now) const {
    return std::all_of(targets.begin(), targets.end(), [&](const std::string& t) {
        const auto it = pointers_.find(t);
        return it != pointers_.end() && (it->second.expiry() - now) * 2 > it->second.ttl;
    });
}

void ServiceCache::questionSeen(const DnsQuestion& question,
                                const std::set<std::string>& knownByAsker, Clock::time_point now) {
    // A refresh due within the next 5 % of the record's TTL is what "planning to ask" means
    // here; the answers to the other host's question renew the record as ours would.
    auto counts = [now](Timed& t) {
        const auto window = std::chrono::duration_cast<Clock::duration>(t.ttl) / 20;
        while (t.nextRefresh() && *t.nextRefresh() <= now + window) ++t.refreshesAsked;
    };
    if (!isClassIn(question.qclass)) return;
    const std::string name = foldCase(question.name);
    const auto type = static_cast<DnsType>(question.type);
    const bool any = type == DnsType::Any;
    const auto capability = subtypeCapability(name);
    if ((name == serviceTypeKey_ || capability) && (any || type == DnsType::Ptr)) {
        for (auto& [key, p] : pointers_) {
            if (knownByAsker.contains(key)) continue;
            if (capability && !announcedWith(key, *capability)) continue;
            counts(p);
        }
        return;
    }
    if (auto it = srvs_.find(name); it != srvs_.end() && (any || type == DnsType::Srv)) {
        counts(it->second);
    }
    if (auto it = txts_.find(name); it != txts_.end() && (any || type == DnsType::Txt)) {
        counts(it->second);
    }
    if (auto it = addresses_.find(name); it != addresses_.end() && (any || type == DnsType::A)) {
        for (auto& a : it->second) counts(a);
    }
}

void ServiceCache::setInterest(std::optional<std::string> capability) {
    interest_ = std::move(capability);
    // What counts changed: every record at its next time again (rare: a browse widening).
    for (auto& [key, p] : pointers_) scheduleInstance(key);
}

std::string ServiceCache::browseName() const {
    return interest_ ? subtypeName(*interest_, serviceType_) : serviceType_;
}

bool ServiceCache::interesting(const std::string& key) const {
    return !interest_ || announcedWith(key, *interest_);
}

bool ServiceCache::announcedWith(const std::string& key, std::string_view capability) const {
    const auto it = announced_.find(key);
    return it != announced_.end() && it->second.hasCapability(capability);
}

std::optional<std::string> ServiceCache::subtypeCapability(const std::string& foldedName) const {
    // "_<capability>._sub.<service type>"
    const std::string suffix = "._sub." + serviceTypeKey_;
    if (foldedName.size() <= suffix.size() + 1 || foldedName.front() != '_' ||
        !endsWith(foldedName, suffix)) {
        return std::nullopt;
    }
    std::string capability = foldedName.substr(1, foldedName.size() - suffix.size() - 1);
    if (capability.find('.') != std::string::npos) return std::nullopt;
    return capability;
}

std::vector<ServiceInstance> ServiceCache::services() const {
    std::vector<ServiceInstance> out;
    out.reserve(announced_.size());
    for (const auto& [k, v] : announced_) out.push_back(v);
    return out;
}

}  // namespace skillcell::ua::mdns
