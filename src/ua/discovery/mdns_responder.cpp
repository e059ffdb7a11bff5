#include "ua/discovery/mdns_responder.hpp"

#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <unistd.h>

#include "libmdnsd_adapter/libmdnsd_adapter.h"

#include <algorithm>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/ip/multicast.hpp>
#include <asio/ip/v6_only.hpp>
#include <asio/use_awaitable.hpp>
#include <cstring>
#include <random>
#include <set>
#include <thread>

namespace skillcell::ua::mdns {

namespace {

constexpr auto kGroup = "224.0.0.251";
constexpr auto kGroup6 = "ff02::fb";
// What we let libmdnsd put into one datagram: an Ethernet MTU less the IP and UDP headers.
constexpr int kFrameBytes = 1472;
// libmdnsd's parser gets only datagrams small enough that its fixed 4 KiB name area cannot
// run out (see libmdnsd_adapter.h).
constexpr std::size_t kLibmdnsdMaxInput = MDNS_ADAPTER_MAX_INPUT;

std::string fqdn(std::string_view name) {
    return std::string(name) + ".";
}

std::string instanceName(std::string_view serverName) {
    return std::string(serverName) + "." + std::string(kOpcUaServiceType);
}

std::uint32_t toNetworkOrder(const Ipv4& ip) {
    std::uint32_t a = 0;
    std::memcpy(&a, ip.data(), 4);
    return a;
}

/// The TXT strings for OPC 10000-12: "path=..." and "caps=a,b".
std::vector<std::string> txtStrings(const ServiceAnnouncement& a) {
    std::string caps;
    for (const auto& c : a.capabilities) caps += (caps.empty() ? "" : ",") + c;
    std::vector<std::string> out{"path=" + a.path, "caps=" + caps};
    for (auto& s : out) s.resize(std::min<std::size_t>(s.size(), 255));  // a string's limit
    return out;
}

/// The same as TXT rdata: each string after its length byte.
std::string txtRdata(const ServiceAnnouncement& a) {
    std::string out;
    for (const auto& s : txtStrings(a)) {
        out.push_back(static_cast<char>(s.size()));
        out += s;
    }
    return out;
}

/// Opens `s` for mDNS on `local` (any address, port 5353): shared with the other processes of
/// the host (an LDS and servers bind the same port), our own datagrams looped back to us,
/// hop limit 255 (RFC 6762, 11). IPv6 sockets carry IPv6 only; IPv4 has its own socket.
asio::error_code openMulticastSocket(asio::ip::udp::socket& s,
                                     const asio::ip::udp::endpoint& local) {
    asio::error_code ec;
    s.open(local.protocol(), ec);
    if (!ec && local.address().is_v6()) s.set_option(asio::ip::v6_only(true), ec);
    if (!ec) s.set_option(asio::ip::udp::socket::reuse_address(true), ec);
    if (!ec) {
        const int one = 1;
        if (setsockopt(s.native_handle(), SOL_SOCKET, SO_REUSEPORT, &one, sizeof one) != 0) {
            ec = asio::error_code(errno, asio::system_category());
        }
    }
    if (!ec) s.bind(local, ec);
    if (!ec) s.set_option(asio::ip::multicast::enable_loopback(true), ec);
    if (!ec) s.set_option(asio::ip::multicast::hops(255), ec);
    if (ec) {
        asio::error_code ignored;
        s.close(ignored);
    }
    return ec;
}

/// A browser of every server hears the answers of a whole cell at once (a new detector's
/// first query: 500 answers within ~120 ms, ~1 MB of socket buffer as the kernel counts it);
/// the default buffer (net.core.rmem_default, 208 KiB) drops most of them, and each lost
/// answer waits for the next query (1 s, 2 s, 4 s ...). Where the process may (CAP_NET_ADMIN)
/// the buffer is set beyond net.core.rmem_max; elsewhere it is what rmem_max allows. Memory
/// is only taken while datagrams wait.
void enlargeReceiveBuffer(asio::ip::udp::socket& s) {
    if (!s.is_open()) return;
    constexpr int kBytes = 4 << 20;
    const int fd = s.native_handle();
    if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &kBytes, sizeof kBytes) != 0) {
        (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &kBytes, sizeof kBytes);
    }
    int got = 0;
    socklen_t len = sizeof got;
    if (getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &got, &len) == 0) {
        spdlog::debug("mDNS: receive buffer {} KiB", got / 1024);
    }
}

/// Splits `records` over datagrams of at most kFrameBytes, the first with `head`'s questions.
/// For a query, every datagram but the last has TC set: more known answers follow (7.2).
std::vector<std::vector<std::uint8_t>> packDatagrams(DnsMessage head,
                                                     std::vector<DnsRecord> records) {
    constexpr std::size_t kHeaderBytes = 12;
    std::vector<std::vector<std::uint8_t>> out;
    auto sizeOf = [](const DnsRecord& r) -> std::size_t {
        DnsMessage one;
        one.records = {r};
        auto bytes = encodeDnsMessage(one);
        return bytes ? bytes->size() - kHeaderBytes : 0;
    };
    DnsMessage current = std::move(head);
    current.records.clear();
    auto base = encodeDnsMessage(current);
    if (!base) return out;
    std::size_t size = base->size();
    auto finish = [&](bool more) {
        current.truncated = more && !current.isResponse;
        if (auto bytes = encodeDnsMessage(current)) out.push_back(std::move(*bytes));
        DnsMessage next;
        next.id = current.id;
        next.isResponse = current.isResponse;
        current = std::move(next);
        size = kHeaderBytes;
    };
    for (auto& r : records) {
        const std::size_t n = sizeOf(r);
        if (n == 0) continue;  // cannot be encoded: left out
        if (size + n > static_cast<std::size_t>(kFrameBytes) && !current.records.empty()) {
            finish(true);
        }
        size += n;
        current.records.push_back(std::move(r));
    }
    if (!current.records.empty() || !current.questions.empty()) finish(false);
    return out;
}

bool isPtrQuestionFor(const DnsQuestion& q, std::string_view name) {
    return foldCase(q.name) == foldCase(name) &&
           (q.type == static_cast<std::uint16_t>(DnsType::Ptr) ||
            q.type == static_cast<std::uint16_t>(DnsType::Any)) &&
           isClassIn(q.qclass);
}

bool announcesLds(const ServiceAnnouncement& a) {
    return hasCapability(a.capabilities, kLdsCapability);
}

std::size_t digestOf(std::span<const std::uint8_t> bytes) {
    return std::hash<std::string_view>{}(
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::string sanitizeLabel(std::string_view s) {
    std::string out;
    for (char c : s) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
        out.push_back(ok ? c : '-');
    }
    if (out.size() > 63) out.resize(63);
    return out.empty() ? std::string("skillcell") : out;
}

}  // namespace

StatusCode validateServerName(std::string_view name) {
    if (name.empty() || name.size() > 63) return status::BadInvalidArgument;
    for (char c : name) {
        if (c == '.' || static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
            return status::BadInvalidArgument;
        }
    }
    return status::Good;
}

void MdnsResponder::AdapterDeleter::operator()(mdns_adapter* a) const {
    mdns_adapter_free(a);
}

MdnsResponder::MdnsResponder(asio::any_io_executor executor, MdnsConfig config)
    : executor_(std::move(executor)),
      config_(std::move(config)),
      socket_(executor_),
      socket6_(executor_),
      timer_(executor_),
      cache_(std::string(kOpcUaServiceType), std::random_device{}()),
      browse_(config_.queryPeriod),
      planner_(std::random_device{}()),
      random_(std::random_device{}()),
      queryId_(static_cast<std::uint16_t>(1 + std::random_device{}() % 0xFFFF)) {}

MdnsResponder::~MdnsResponder() = default;

Result<std::shared_ptr<MdnsResponder>> MdnsResponder::create(asio::any_io_executor executor,
                                                             MdnsConfig config,
                                                             std::string* error) {
    auto fail = [error](std::string why) -> Result<std::shared_ptr<MdnsResponder>> {
        if (error != nullptr) *error = std::move(why);
        return status::BadResourceUnavailable;
    };
    if (config.recordTtl.count() < 1 || config.recordTtl.count() > 86400) {
        return fail("the record TTL must be 1..86400 s");
    }
    if (config.queryPeriod < std::chrono::milliseconds(100)) {
        return fail("the query period must be at least 100 ms");
    }
    std::shared_ptr<MdnsResponder> r(new MdnsResponder(std::move(executor), std::move(config)));
    r->nics_ = chooseMdnsInterfaces(listIpv4Interfaces(), r->config_.interfaces);
    if (r->nics_.empty()) {
        return fail(r->config_.interfaces.empty()
                        ? "no multicast-capable IPv4 interface"
                        : "none of the interfaces " +
                              [&] {
                                  std::string names;
                                  for (const auto& n : r->config_.interfaces)
                                      names += (names.empty() ? "" : ", ") + n;
                                  return names;
                              }() +
                              " has an IPv4 address and multicast");
    }
    if (r->config_.hostName.empty()) {
        char buf[256] = {};
        if (gethostname(buf, sizeof buf - 1) != 0) std::strcpy(buf, "skillcell");
        r->hostName_ = sanitizeLabel(buf);
    } else {
        r->hostName_ = sanitizeLabel(r->config_.hostName);
    }
    r->mdnsd_.reset(mdns_adapter_new(kFrameBytes));
    if (!r->mdnsd_) return fail("out of memory for libmdnsd");

    if (!r->config_.ipv4 && !r->config_.ipv6) return fail("neither IPv4 nor IPv6 enabled");
    if (r->config_.ipv4) {
        auto& s = r->socket_;
        const auto group = asio::ip::make_address_v4(kGroup);
        const asio::error_code ec = openMulticastSocket(
            s, asio::ip::udp::endpoint(asio::ip::address_v4::any(), r->config_.port));
        if (ec) {
            return fail("mDNS socket on port " + std::to_string(r->config_.port) + ": " +
                        ec.message());
        }
        std::size_t joined = 0;
        for (const auto& nic : r->nics_) {
            asio::error_code jec;
            s.set_option(asio::ip::multicast::join_group(group, asio::ip::address_v4(nic.address)),
                         jec);
            if (jec) {
                spdlog::warn("mDNS: cannot join {} on {} ({}): {}", kGroup, nic.name,
                             toString(nic.address), jec.message());
            } else {
                ++joined;
            }
        }
        if (joined == 0) return fail("could not join the mDNS group on any interface");
    }
    if (r->config_.ipv6) {
        std::string why;
        if (!r->openIpv6(why)) {
            if (!r->config_.ipv4) return fail("mDNS over IPv6: " + why);
            spdlog::info("mDNS over IPv4 only: {}", why);
        }
    }
    return r;
}

bool MdnsResponder::openIpv6(std::string& why) {
    auto& s = socket6_;
    asio::error_code ec =
        openMulticastSocket(s, asio::ip::udp::endpoint(asio::ip::address_v6::any(), config_.port));
    if (ec) {
        why = ec.message();
        return false;
    }
    const auto group = asio::ip::make_address_v6(kGroup6);
    std::vector<unsigned> joined;
    for (const auto& nic : nics_) {
        if (!nic.hasIpv6 || nic.index == 0 ||
            std::find(joined.begin(), joined.end(), nic.index) != joined.end()) {
            continue;
        }
        asio::error_code jec;
        s.set_option(asio::ip::multicast::join_group(group, nic.index), jec);
        if (jec) {
            spdlog::debug("mDNS: cannot join {} on {}: {}", kGroup6, nic.name, jec.message());
        } else {
            joined.push_back(nic.index);
        }
    }
    if (joined.empty()) {
        why = "no interface with IPv6 multicast";
        s.close(ec);
        return false;
    }
    v6Interfaces_ = std::move(joined);
    return true;
}

void MdnsResponder::start() {
    if (started_ || closed_) return;
    started_ = true;
    std::string names;
    for (const auto& nic : nics_)
        names += (names.empty() ? "" : ", ") + nic.name + " " + toString(nic.address);
    spdlog::info("mDNS on {} (host {}.local, TTL {} s, longest query interval {} ms)", names,
                 hostName_, config_.recordTtl.count(), config_.queryPeriod.count());
    if (socket_.is_open()) asio::co_spawn(executor_, receiveLoop(socket_), asio::detached);
    if (socket6_.is_open()) asio::co_spawn(executor_, receiveLoop(socket6_), asio::detached);
    asio::co_spawn(executor_, timerLoop(), asio::detached);
    std::map<unsigned, bool> running;
    for (const auto& nic : nics_) {
        if (!nic.loopback && nic.index != 0) running[nic.index] = nic.up;
    }
    if (running.empty()) return;
    std::string why;
    std::weak_ptr<MdnsResponder> weak = shared_from_this();
    links_ = LinkMonitor::create(
        executor_, std::move(running),
        [weak](unsigned index) {
            if (auto self = weak.lock()) self->linkCameUp(index);
        },
        &why);
    if (links_) {
        links_->start();
    } else {
        spdlog::warn(
            "mDNS: link changes go unnoticed ({}): after a link comes back, others are "
            "found at the next query",
            why);
    }
}

void MdnsResponder::linkCameUp(unsigned index) {
    if (closed_) return;
    std::string name = std::to_string(index);
    for (const auto& nic : nics_) {
        if (nic.index == index) name = nic.name;
    }
    const bool announcing = !published_.empty();
    spdlog::info("mDNS: link {} up again: {}{}{} (RFC 6762, 8.3)", name,
                 announcing ? "announcing again" : "",
                 announcing && browse_.active() ? " and " : "",
                 browse_.active() ? "asking again" : "");
    if (announcing) {
        sendAnswers(planner_.own());
        announceAgainAt_ = Clock::now() + std::chrono::seconds(1);
    }
    if (browse_.active()) browse_.restart(Clock::now());
    wake();
}

std::size_t MdnsResponder::subscribe(Listener listener, BrowseScope scope) {
    const std::size_t id = nextListener_++;
    // A late subscriber first hears what is already known, as if it had just been announced.
    for (const auto& s : cache_.services()) listener({ServiceEvent::Kind::Announced, s, {}});
    listeners_.emplace(id, std::move(listener));
    const bool widens = scope == BrowseScope::AllServers && scope_ == BrowseScope::DiscoveryServers;
    if (!browse_.active() || widens) {
        scope_ = scope;
        if (scope == BrowseScope::AllServers) {
            enlargeReceiveBuffer(socket_);
            enlargeReceiveBuffer(socket6_);
        }
        cache_.setInterest(scope == BrowseScope::DiscoveryServers
                               ? std::optional<std::string>(kLdsCapability)
                               : std::nullopt);
        // A process's first query waits 20-120 ms (RFC 6762, 5.2): when a cell powers on,
        // one server's question for its LDS then stands for the others' (7.3).
        std::uniform_int_distribution<int> delayMs(20, 120);
        startBrowsing(std::chrono::milliseconds(delayMs(random_)));
    }
    return id;
}

void MdnsResponder::unsubscribe(std::size_t id) {
    listeners_.erase(id);
}

void MdnsResponder::dispatch(const std::vector<ServiceEvent>& events) {
    for (const auto& e : events) {
        spdlog::debug("mDNS: {} {} at {}",
                      e.kind == ServiceEvent::Kind::Announced ? "announced" : "gone",
                      e.instance.name, e.instance.discoveryUrl());
        const auto listeners = listeners_;  // a listener may unsubscribe
        for (const auto& [id, l] : listeners) l(e);
    }
}

void MdnsResponder::ensureHostRecords() {
    if (!hostRecords_.empty()) return;
    const std::string host = fqdn(hostName_ + ".local");
    for (const auto& nic : nics_) {
        mdns_adapter_record* a =
            mdns_adapter_shared(mdnsd_.get(), host.c_str(), MDNS_ADAPTER_A,
                                static_cast<unsigned long>(config_.recordTtl.count()));
        mdns_adapter_set_ip(mdnsd_.get(), a, toNetworkOrder(nic.address));
        hostRecords_.push_back(a);
    }
}

StatusCode MdnsResponder::announce(const ServiceAnnouncement& a) {
    if (closed_) return status::BadInvalidState;
    if (auto s = validateServerName(a.name); s.isBad()) return s;
    if (a.port == 0 || a.path.size() > 200) return status::BadInvalidArgument;
    for (const auto& c : a.capabilities) {
        if (c.empty() || c.find(',') != std::string::npos || c.size() > 32) {
            return status::BadInvalidArgument;
        }
    }
    const std::string key = foldCase(a.name);
    if (auto it = published_.find(key); it != published_.end()) {
        if (it->second.announcement.port == a.port && it->second.announcement.path == a.path &&
            it->second.announcement.capabilities == a.capabilities &&
            it->second.announcement.address == a.address) {
            return status::Good;  // unchanged
        }
        withdrawRecords(it->second);
        published_.erase(it);
    }
    auto* d = mdnsd_.get();
    const auto ttl = static_cast<unsigned long>(config_.recordTtl.count());
    Published p;
    p.announcement = a;
    std::string instance = fqdn(instanceName(a.name));
    if (a.address) {
        const auto& ip = *a.address;
        p.hostFqdn = fqdn("ip-" + std::to_string(ip[0]) + "-" + std::to_string(ip[1]) + "-" +
                          std::to_string(ip[2]) + "-" + std::to_string(ip[3]) + ".local");
        mdns_adapter_record* rec = mdns_adapter_shared(d, p.hostFqdn.c_str(), MDNS_ADAPTER_A, ttl);
        mdns_adapter_set_ip(d, rec, toNetworkOrder(ip));
        p.records.push_back(rec);
    } else {
        ensureHostRecords();
        p.hostFqdn = fqdn(hostName_ + ".local");
    }
    mdns_adapter_record* ptr =
        mdns_adapter_shared(d, fqdn(kOpcUaServiceType).c_str(), MDNS_ADAPTER_PTR, ttl);
    mdns_adapter_set_host(d, ptr, instance.c_str());
    mdns_adapter_record* srv = mdns_adapter_shared(d, instance.c_str(), MDNS_ADAPTER_SRV, ttl);
    mdns_adapter_set_srv(d, srv, a.port, p.hostFqdn.c_str());
    mdns_adapter_record* txt = mdns_adapter_shared(d, instance.c_str(), MDNS_ADAPTER_TXT, ttl);
    const std::string rdata = txtRdata(a);
    mdns_adapter_set_raw(d, txt, rdata.data(), static_cast<unsigned short>(rdata.size()));
    p.records.insert(p.records.end(), {ptr, srv, txt});
    if (announcesLds(a)) {
        mdns_adapter_record* sub = mdns_adapter_shared(d, fqdn(subtypeName(kLdsCapability)).c_str(),
                                                       MDNS_ADAPTER_PTR, ttl);
        mdns_adapter_set_host(d, sub, instance.c_str());
        p.records.push_back(sub);
    }
    published_.emplace(key, std::move(p));
    rebuildOwnRecords();
    spdlog::info("mDNS: announcing '{}' port {} path '{}'", a.name, a.port, a.path);
    wake();
    return status::Good;
}

void MdnsResponder::withdrawRecords(Published& p) {
    // mdnsd_done() turns a record into its goodbye (TTL 0); libmdnsd frees it once sent.
    for (mdns_adapter_record* r : p.records) mdns_adapter_done(mdnsd_.get(), r);
    p.records.clear();
}

void MdnsResponder::withdraw(std::string_view name) {
    auto it = published_.find(foldCase(name));
    if (it == published_.end() || closed_) return;
    spdlog::info("mDNS: withdrawing '{}'", it->second.announcement.name);
    withdrawRecords(it->second);
    published_.erase(it);
    rebuildOwnRecords();
    flushOutput();
}

void MdnsResponder::shutdown() {
    if (closed_) return;
    if (mdnsd_ && !published_.empty()) {
        spdlog::info("mDNS: goodbye for {} announcement(s)", published_.size());
        // Goodbyes for the services only, not for the host's address records: other
        // processes on this host share them, and a goodbye would take their address away
        // from every peer. Our address records simply expire.
        for (auto& [key, p] : published_) withdrawRecords(p);
        // libmdnsd holds shared answers back for up to ~120 us (RFC 6762 6): wait for them,
        // a bounded number of times, so the goodbyes leave before the socket closes.
        for (int i = 0; i < 16; ++i) {
            flushOutput();
            const auto us = mdns_adapter_sleep_us(mdnsd_.get());
            if (us > 100'000) break;
            std::this_thread::sleep_for(std::chrono::microseconds(us + 1));
        }
    }
    closed_ = true;
    if (links_) links_->stop();
    announceAgainAt_.reset();
    published_.clear();
    hostRecords_.clear();
    planner_.setOwn({});
    asio::error_code ec;
    socket_.close(ec);
    socket6_.close(ec);
    timer_.cancel();
}

void MdnsResponder::queryNow() {
    startBrowsing(Clock::duration::zero());  // someone asked: now
}

void MdnsResponder::startBrowsing(Clock::duration firstDelay) {
    browse_.restart(Clock::now(), firstDelay);
    wake();
}

void MdnsResponder::rebuildOwnRecords() {
    std::vector<DnsRecord> own;
    const auto ttl = static_cast<std::uint32_t>(config_.recordTtl.count());
    auto record = [ttl](std::string name, DnsType type) {
        DnsRecord r;
        r.name = std::move(name);
        r.type = static_cast<std::uint16_t>(type);
        r.ttl = ttl;
        return r;
    };
    // Names as DnsRecord spells them: without libmdnsd's trailing dot.
    auto bare = [](std::string name) {
        if (!name.empty() && name.back() == '.') name.pop_back();
        return name;
    };
    if (!hostRecords_.empty()) {
        for (const auto& nic : nics_) {
            auto a = record(hostName_ + ".local", DnsType::A);
            a.ipv4 = nic.address;
            own.push_back(std::move(a));
        }
    }
    for (const auto& [key, p] : published_) {
        const std::string instance = instanceName(p.announcement.name);
        auto ptr = record(std::string(kOpcUaServiceType), DnsType::Ptr);
        ptr.target = instance;
        auto srv = record(instance, DnsType::Srv);
        srv.port = p.announcement.port;
        srv.target = bare(p.hostFqdn);
        auto txt = record(instance, DnsType::Txt);
        txt.txt = txtStrings(p.announcement);
        own.insert(own.end(), {ptr, srv, txt});
        if (announcesLds(p.announcement)) {
            auto sub = record(subtypeName(kLdsCapability), DnsType::Ptr);
            sub.target = instance;
            own.push_back(std::move(sub));
        }
        if (p.announcement.address) {
            auto a = record(bare(p.hostFqdn), DnsType::A);
            a.ipv4 = *p.announcement.address;
            own.push_back(std::move(a));
        }
    }
    planner_.setOwn(std::move(own));
}

void MdnsResponder::wake() {
    if (started_) timer_.cancel();
}

void MdnsResponder::wakeIfSooner() {
    for (const auto& d : {browse_.next(), cache_.nextDeadline(), planner_.nextDeadline()}) {
        if (d && *d < timer_.expiry()) {
            wake();
            return;
        }
    }
}

asio::awaitable<void> MdnsResponder::receiveLoop(asio::ip::udp::socket& socket) {
    auto self = shared_from_this();
    std::vector<std::uint8_t> buf(65536);
    while (!closed_) {
        asio::ip::udp::endpoint from;
        auto [ec, n] = co_await socket.async_receive_from(
            asio::buffer(buf), from, asio::experimental::as_tuple(asio::use_awaitable));
        if (closed_ || ec == asio::error::operation_aborted) co_return;
        if (ec) {
            spdlog::debug("mDNS receive: {}", ec.message());
            continue;
        }
        // Over IPv6 the sender has no IPv4 address to match records against: the cache then
        // takes the first address record (see ServiceCache).
        Ipv4 source{};
        if (from.address().is_v4()) {
            source = from.address().to_v4().to_bytes();
        } else if (from.address().to_v6().is_v4_mapped()) {
            source =
                asio::ip::make_address_v4(asio::ip::v4_mapped, from.address().to_v6()).to_bytes();
        }
        handleDatagram(std::span(buf.data(), n), source, from.port());
    }
}

void MdnsResponder::handleDatagram(std::span<const std::uint8_t> bytes, const Ipv4& source,
                                   std::uint16_t sourcePort) {
    ++stats_.received;
    std::string why;
    auto msg = parseDnsMessage(bytes, &why);
    if (!msg) {
        ++stats_.malformed;
        spdlog::debug("mDNS: dropped a datagram of {} bytes from {}: {}", bytes.size(),
                      toString(source), why);
        return;
    }
    if (msg->isResponse) {
        // RFC 6762 6: a response from any port but 5353 is not mDNS; ignore it.
        if (sourcePort != config_.port) return;
        const auto now = Clock::now();
        planner_.onResponse(*msg, now);
        // Only a browser keeps what it hears: a server that only announces has no use for it.
        if (browse_.active()) dispatch(cache_.ingest(*msg, source, now));
        wakeIfSooner();  // new records: perhaps new deadlines
        return;
    }
    handleQuery(*msg, bytes, source, sourcePort);
}

bool MdnsResponder::isOwnQuery(const DnsMessage& query, std::span<const std::uint8_t> bytes) const {
    if (query.id != queryId_) return false;
    return std::find(recentQueries_.begin(), recentQueries_.end(), digestOf(bytes)) !=
           recentQueries_.end();
}

void MdnsResponder::handleQuery(const DnsMessage& query, std::span<const std::uint8_t> bytes,
                                const Ipv4& source, std::uint16_t sourcePort) {
    if (closed_ || isOwnQuery(query, bytes)) return;
    ++stats_.queriesHeard;
    const auto now = Clock::now();
    if (browse_.active()) {
        // Another browser's question, with no known answer we lack, brings us the answers
        // ours would (7.3).
        std::set<std::string> knownByAsker;
        for (const auto& rr : query.records) {
            if (rr.type == static_cast<std::uint16_t>(DnsType::Ptr)) {
                knownByAsker.insert(foldCase(rr.target));
            }
        }
        for (const auto& q : query.questions) {
            const bool multicastAnswer = (q.qclass & kClassTopBit) == 0;
            if (isPtrQuestionFor(q, browseName()) && multicastAnswer &&
                sourcePort == config_.port && cache_.knowsAll(knownByAsker, now)) {
                if (browse_.duplicateSeen(now)) ++stats_.queriesSpared;
            }
            if (multicastAnswer) cache_.questionSeen(q, knownByAsker, now);
        }
    }
    if (published_.empty()) return;  // nothing of ours to answer with
    if (sourcePort != config_.port) {
        // A legacy unicast query (RFC 6762 6.7): libmdnsd answers it at once, to its port.
        if (bytes.size() <= kLibmdnsdMaxInput) feedLibmdnsd(bytes, source, sourcePort);
        answerWithAdditionals(query, source);
        flushOutput();
        wake();
        return;
    }
    planner_.onQuery(query, source, now);
    wake();
}

void MdnsResponder::feedLibmdnsd(std::span<const std::uint8_t> bytes, const Ipv4& source,
                                 std::uint16_t sourcePort) {
    // parseDnsMessage() accepted it: its names and lengths are within the datagram.
    mdns_adapter_in(mdnsd_.get(), bytes.data(), bytes.size(), toNetworkOrder(source), sourcePort);
}

void MdnsResponder::answerWithAdditionals(const DnsMessage& query, const Ipv4& source) {
    // libmdnsd answers a PTR question with the PTR record only, so a browser would need a
    // second round trip for SRV, TXT and A; several browsers (node-opcua's among them)
    // expect them in the same response (RFC 6763, 12.1). We ask libmdnsd those questions
    // too, so its next datagram carries them all.
    std::vector<DnsQuestion> extra;
    for (const auto& q : query.questions) {
        const std::string name = foldCase(q.name);
        const bool browseAll = isPtrQuestionFor(q, kOpcUaServiceType);
        const bool browseLds = isPtrQuestionFor(q, subtypeName(kLdsCapability));
        for (const auto& [key, p] : published_) {
            const std::string instance = instanceName(p.announcement.name);
            const bool browse = browseAll || (browseLds && announcesLds(p.announcement));
            if (!browse && name != foldCase(instance)) continue;
            if (browse) {
                extra.push_back(
                    {instance + ".", static_cast<std::uint16_t>(DnsType::Srv), kClassIn});
                extra.push_back(
                    {instance + ".", static_cast<std::uint16_t>(DnsType::Txt), kClassIn});
            }
            extra.push_back({p.hostFqdn, static_cast<std::uint16_t>(DnsType::A), kClassIn});
        }
    }
    if (extra.empty()) return;
    DnsMessage synthetic;
    synthetic.questions = std::move(extra);
    // Names here carry libmdnsd's trailing dot; our encoder wants them without.
    for (auto& q : synthetic.questions) q.name.pop_back();
    auto bytes = encodeDnsMessage(synthetic);
    if (!bytes || bytes->size() > kLibmdnsdMaxInput) return;
    feedLibmdnsd(*bytes, source, config_.port);
}

void MdnsResponder::flushOutput() {
    if (!mdnsd_) return;
    const unsigned char* data = nullptr;
    int multicast = 0;
    std::uint32_t ip = 0;
    unsigned short port = 0;
    // Bounded: libmdnsd produces a handful of datagrams per call; more means a bug.
    for (int i = 0; i < 64; ++i) {
        const std::size_t len = mdns_adapter_out(mdnsd_.get(), &data, &multicast, &ip, &port);
        if (len == 0) break;
        const std::span<const std::uint8_t> packet(data, len);
        if (multicast != 0) {
            sendMulticast(packet);
            continue;
        }
        // An answer to a legacy unicast query (one sent from a port other than 5353).
        asio::error_code ec;
        Ipv4 to{};
        std::memcpy(to.data(), &ip, 4);
        socket_.send_to(asio::buffer(packet.data(), packet.size()),
                        asio::ip::udp::endpoint(asio::ip::address_v4(to), port), 0, ec);
        ec ? ++stats_.sendErrors : ++stats_.sent;
    }
}

void MdnsResponder::sendMulticast(std::span<const std::uint8_t> bytes) {
    auto sent = [this](const asio::error_code& ec, const std::string& where) {
        if (ec) {
            // A link that is down (a cable pulled) fails here until it is back: not an
            // error worth more than a debug line.
            ++stats_.sendErrors;
            spdlog::debug("mDNS send on {}: {}", where, ec.message());
        } else {
            ++stats_.sent;
        }
    };
    if (socket_.is_open()) {
        const asio::ip::udp::endpoint group(asio::ip::make_address_v4(kGroup), config_.port);
        for (const auto& nic : nics_) {
            asio::error_code ec;
            socket_.set_option(
                asio::ip::multicast::outbound_interface(asio::ip::address_v4(nic.address)), ec);
            if (!ec) socket_.send_to(asio::buffer(bytes.data(), bytes.size()), group, 0, ec);
            sent(ec, nic.name);
        }
    }
    if (socket6_.is_open()) {
        for (const unsigned index : v6Interfaces_) {
            asio::error_code ec;
            auto group = asio::ip::make_address_v6(kGroup6);
            group.scope_id(index);
            socket6_.set_option(asio::ip::multicast::outbound_interface(index), ec);
            if (!ec) {
                socket6_.send_to(asio::buffer(bytes.data(), bytes.size()),
                                 asio::ip::udp::endpoint(group, config_.port), 0, ec);
            }
            sent(ec, "IPv6 interface " + std::to_string(index));
        }
    }
}

void MdnsResponder::sendQuestions(std::vector<DnsQuestion> questions, Clock::time_point now) {
    DnsMessage m;
    m.id = queryId_;
    // Known answers (7.1): the servers we know need not answer again.
    const std::string name = browseName();
    const bool browse = std::any_of(questions.begin(), questions.end(), [&](const DnsQuestion& q) {
        return isPtrQuestionFor(q, name);
    });
    m.questions = std::move(questions);
    for (auto& bytes : packDatagrams(
             std::move(m), browse ? cache_.knownAnswers(now, name) : std::vector<DnsRecord>{})) {
        recentQueries_.push_back(digestOf(bytes));
        if (recentQueries_.size() > 16) recentQueries_.erase(recentQueries_.begin());
        ++stats_.queriesSent;
        sendMulticast(bytes);
    }
}

void MdnsResponder::sendAnswers(std::vector<DnsRecord> records) {
    DnsMessage m;
    m.isResponse = true;
    for (auto& bytes : packDatagrams(std::move(m), std::move(records))) {
        ++stats_.answersSent;
        sendMulticast(bytes);
    }
}

asio::awaitable<void> MdnsResponder::timerLoop() {
    auto self = shared_from_this();
    while (!closed_) {
        const auto now = Clock::now();
        if (auto due = planner_.takeDue(now); !due.empty()) sendAnswers(std::move(due));
        if (announceAgainAt_ && now >= *announceAgainAt_) {
            announceAgainAt_.reset();
            sendAnswers(planner_.own());
        }
        flushOutput();
        std::vector<DnsQuestion> questions;
        if (browse_.active()) {
            dispatch(cache_.expire(now));
            questions = cache_.refreshQueries(now);
            if (now >= *browse_.next()) {
                const std::string name = browseName();
                if (std::none_of(questions.begin(), questions.end(),
                                 [&](const DnsQuestion& q) { return isPtrQuestionFor(q, name); })) {
                    questions.push_back({name, static_cast<std::uint16_t>(DnsType::Ptr), kClassIn});
                }
                browse_.sent(now);
            }
        }
        if (!questions.empty()) sendQuestions(std::move(questions), now);

        auto wakeAt = now + std::chrono::minutes(1);
        for (const auto& d :
             {browse_.next(), cache_.nextDeadline(), planner_.nextDeadline(), announceAgainAt_}) {
            if (d && *d < wakeAt) wakeAt = *d;
        }
        const auto sleep = std::chrono::microseconds(mdns_adapter_sleep_us(mdnsd_.get()));
        if (now + sleep < wakeAt) wakeAt = now + std::chrono::duration_cast<Clock::duration>(sleep);
        // Never spin: at least a millisecond between rounds.
        wakeAt = std::max(wakeAt, now + std::chrono::milliseconds(1));
        timer_.expires_at(wakeAt);
        co_await timer_.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    }
}

}  // namespace skillcell::ua::mdns
