#include "ua/discovery/service_cache.hpp"

#include <algorithm>
#include <set>

namespace skillcell::ua::mdns {

namespace {

constexpr std::array<int, 4> kRefreshPercent = {80, 85, 90, 95};
// Bounds what a flood of records can make us keep (each map separately).
constexpr std::size_t kMaxEntries = 1024;

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

}  // namespace

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

bool ServiceInstance::hasCapability(std::string_view cap) const {
    const std::string folded = foldCase(cap);
    return std::any_of(capabilities.begin(), capabilities.end(),
                       [&](const std::string& c) { return foldCase(c) == folded; });
}

std::optional<Clock::time_point> ServiceCache::Timed::nextRefresh() const {
    if (refreshesAsked >= static_cast<int>(kRefreshPercent.size())) return std::nullopt;
    const auto ttlMs = std::chrono::duration_cast<std::chrono::milliseconds>(ttl);
    return received + ttlMs * kRefreshPercent[static_cast<std::size_t>(refreshesAsked)] / 100;
}

ServiceCache::ServiceCache(std::string serviceType)
    : serviceType_(std::move(serviceType)), serviceTypeKey_(foldCase(serviceType_)) {}

void ServiceCache::store(const DnsRecord& rr, const Ipv4& source, Clock::time_point now,
                         std::vector<std::string>& goodbyes) {
    const std::string key = foldCase(rr.name);
    const Timed timed{now, std::chrono::seconds(rr.ttl), 0};
    const bool goodbye = rr.ttl == 0;
    switch (static_cast<DnsType>(rr.type)) {
        case DnsType::Ptr: {
            if (key != serviceTypeKey_) return;
            const std::string instance = foldCase(rr.target);
            if (!endsWith(instance, "." + serviceTypeKey_)) return;
            if (goodbye) {
                pointers_.erase(instance);
                goodbyes.push_back(instance);
            } else if (roomFor(pointers_, instance)) {
                pointers_[instance] = Pointer{timed, rr.target};
            }
            return;
        }
        case DnsType::Srv:
            if (!endsWith(key, "." + serviceTypeKey_)) return;
            if (goodbye) {
                srvs_.erase(key);
                goodbyes.push_back(key);
            } else if (roomFor(srvs_, key)) {
                srvs_[key] = Srv{timed, foldCase(rr.target), rr.port, source};
            }
            return;
        case DnsType::Txt:
            if (!endsWith(key, "." + serviceTypeKey_)) return;
            if (goodbye) {
                txts_.erase(key);
                goodbyes.push_back(key);
            } else if (roomFor(txts_, key)) {
                txts_[key] = Txt{timed, rr.txt};
            }
            return;
        case DnsType::A: {
            if (!roomFor(addresses_, key)) return;
            auto& list = addresses_[key];
            if (rr.cacheFlush() && !goodbye) {
                // RFC 6762 10.2: a cache-flush record replaces those older than a second.
                std::erase_if(list, [&](const Address& a) {
                    return a.ip != rr.ipv4 && now - a.received > std::chrono::seconds(1);
                });
            }
            auto it = std::find_if(list.begin(), list.end(),
                                   [&](const Address& a) { return a.ip == rr.ipv4; });
            if (goodbye) {
                if (it != list.end()) list.erase(it);
                goodbyes.push_back(key);
            } else if (it != list.end()) {
                static_cast<Timed&>(*it) = timed;
            } else if (list.size() < 16) {
                list.push_back(Address{timed, rr.ipv4});
            }
            if (list.empty()) addresses_.erase(key);
            return;
        }
        case DnsType::Aaaa:
        case DnsType::Any:
        default: return;
    }
}

std::vector<ServiceEvent> ServiceCache::ingest(const DnsMessage& message, const Ipv4& source,
                                               Clock::time_point now) {
    std::vector<std::string> goodbyes;
    for (const auto& rr : message.records) {
        if ((rr.rrclass & ~kClassTopBit) != kClassIn) continue;
        store(rr, source, now, goodbyes);
    }
    std::vector<ServiceEvent> events;
    reconcile(events, goodbyes);
    return events;
}

std::vector<ServiceEvent> ServiceCache::expire(Clock::time_point now) {
    auto expired = [now](const Timed& t) { return t.expiry() <= now; };
    std::erase_if(pointers_, [&](const auto& kv) { return expired(kv.second); });
    std::erase_if(srvs_, [&](const auto& kv) { return expired(kv.second); });
    std::erase_if(txts_, [&](const auto& kv) { return expired(kv.second); });
    for (auto it = addresses_.begin(); it != addresses_.end();) {
        std::erase_if(it->second, expired);
        it = it->second.empty() ? addresses_.erase(it) : std::next(it);
    }
    std::vector<ServiceEvent> events;
    reconcile(events, {});
    return events;
}

std::optional<ServiceInstance> ServiceCache::complete(const std::string& key) const {
    const auto ptr = pointers_.find(key);
    const auto srv = srvs_.find(key);
    const auto txt = txts_.find(key);
    if (ptr == pointers_.end() || srv == srvs_.end() || txt == txts_.end()) return std::nullopt;
    const auto addrs = addresses_.find(srv->second.host);
    if (addrs == addresses_.end() || addrs->second.empty()) return std::nullopt;

    ServiceInstance s;
    s.name = firstLabel(ptr->second.instance);
    s.host = srv->second.host;
    s.port = srv->second.port;
    if (auto path = txtValue(txt->second.strings, "path"); path && !path->empty()) {
        s.path = path->front() == '/' ? *path : "/" + *path;
    }
    if (auto caps = txtValue(txt->second.strings, "caps")) s.capabilities = splitCaps(*caps);
    // The address the SRV record came from, when the host claims it: that one routes back.
    const auto& list = addrs->second;
    auto viaSender = std::find_if(list.begin(), list.end(),
                                  [&](const Address& a) { return a.ip == srv->second.sender; });
    s.address = viaSender != list.end() ? viaSender->ip : list.front().ip;
    return s;
}

void ServiceCache::reconcile(std::vector<ServiceEvent>& events,
                             const std::vector<std::string>& goodbyes) {
    std::set<std::string> keys;
    for (const auto& [k, v] : pointers_) keys.insert(k);
    for (const auto& [k, v] : announced_) keys.insert(k);
    for (const auto& key : keys) {
        auto now = complete(key);
        auto was = announced_.find(key);
        if (now) {
            if (was == announced_.end() || was->second != *now) {
                events.push_back({ServiceEvent::Kind::Announced, *now, RemovalReason::Expired});
                announced_[key] = std::move(*now);
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
    std::vector<DnsQuestion> out;
    auto ask = [&](std::string name, DnsType type) {
        const auto t = static_cast<std::uint16_t>(type);
        const bool dup = std::any_of(out.begin(), out.end(), [&](const DnsQuestion& q) {
            return q.type == t && foldCase(q.name) == foldCase(name);
        });
        if (!dup) out.push_back({std::move(name), t, kClassIn});
    };
    auto due = [now](Timed& t) {
        const auto at = t.nextRefresh();
        if (!at || *at > now) return false;
        // Several thresholds may have passed at once (a stalled loop): ask once, skip them.
        while (t.nextRefresh() && *t.nextRefresh() <= now) ++t.refreshesAsked;
        return true;
    };
    for (auto& [key, ptr] : pointers_) {
        if (due(ptr)) ask(serviceType_, DnsType::Ptr);
    }
    for (auto& [key, srv] : srvs_) {
        if (!announced_.contains(key)) continue;
        const std::string& instance = pointers_.contains(key) ? pointers_[key].instance : key;
        if (due(srv)) {
            ask(instance, DnsType::Srv);
            ask(instance, DnsType::Txt);
        }
        if (auto txt = txts_.find(key); txt != txts_.end() && due(txt->second)) {
            ask(instance, DnsType::Txt);
        }
        if (auto addrs = addresses_.find(srv.host); addrs != addresses_.end()) {
            bool any = false;
            for (auto& a : addrs->second) any = due(a) || any;
            if (any) ask(srv.host, DnsType::A);
        }
    }
    return out;
}

std::optional<Clock::time_point> ServiceCache::nextDeadline() const {
    std::optional<Clock::time_point> best;
    // Refresh times count only for what refreshQueries() asks about (else the deadline would
    // stay in the past); expiry counts for every record.
    auto consider = [&](const Timed& t, bool refreshed) {
        auto at = t.expiry();
        if (auto r = t.nextRefresh(); refreshed && r && *r < at) at = *r;
        if (!best || at < *best) best = at;
    };
    std::set<std::string> refreshedHosts;
    for (const auto& [k, v] : pointers_) consider(v, true);
    for (const auto& [k, v] : srvs_) {
        const bool live = announced_.contains(k);
        consider(v, live);
        if (live) refreshedHosts.insert(v.host);
    }
    for (const auto& [k, v] : txts_) consider(v, announced_.contains(k));
    for (const auto& [k, list] : addresses_) {
        for (const auto& a : list) consider(a, refreshedHosts.contains(k));
    }
    return best;
}

std::vector<ServiceInstance> ServiceCache::services() const {
    std::vector<ServiceInstance> out;
    out.reserve(announced_.size());
    for (const auto& [k, v] : announced_) out.push_back(v);
    return out;
}

}  // namespace skillcell::ua::mdns
