// Fuzz target: one datagram as it arrives on the mDNS port. It must parse or be refused
// (never read out of bounds); a parsed one must survive the service cache and, when it is a
// query, libmdnsd (behind the adapter, which only sees validated datagrams) and the response
// planner; and what parses must encode and parse back to the same records.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ua/discovery/dns_message.hpp"
#include "ua/discovery/libmdnsd_adapter/libmdnsd_adapter.h"
#include "ua/discovery/response_planner.hpp"
#include "ua/discovery/service_cache.hpp"

namespace {

using namespace skillcell::ua::mdns;

/// One libmdnsd instance with a published service, so that queries have something to hit.
mdns_adapter* responder() {
    static mdns_adapter* a = [] {
        mdns_adapter* m = mdns_adapter_new(1472);
        auto* ptr = mdns_adapter_shared(m, "_opcua-tcp._tcp.local.", MDNS_ADAPTER_PTR, 120);
        mdns_adapter_set_host(m, ptr, "fuzz._opcua-tcp._tcp.local.");
        auto* srv = mdns_adapter_shared(m, "fuzz._opcua-tcp._tcp.local.", MDNS_ADAPTER_SRV, 120);
        mdns_adapter_set_srv(m, srv, 4840, "fuzz.local.");
        auto* a4 = mdns_adapter_shared(m, "fuzz.local.", MDNS_ADAPTER_A, 120);
        mdns_adapter_set_ip(m, a4, 0x0100007F);
        return m;
    }();
    return a;
}

/// The records a responder publishes for one server, as the planner sees them.
std::vector<DnsRecord> ownRecords() {
    auto make = [](std::string name, DnsType type) {
        DnsRecord r;
        r.name = std::move(name);
        r.type = static_cast<std::uint16_t>(type);
        r.ttl = 120;
        return r;
    };
    auto ptr = make("_opcua-tcp._tcp.local", DnsType::Ptr);
    ptr.target = "fuzz._opcua-tcp._tcp.local";
    auto srv = make("fuzz._opcua-tcp._tcp.local", DnsType::Srv);
    srv.port = 4840;
    srv.target = "fuzz.local";
    auto txt = make("fuzz._opcua-tcp._tcp.local", DnsType::Txt);
    txt.txt = {"path=/", "caps=NA"};
    auto a = make("fuzz.local", DnsType::A);
    a.ipv4 = {127, 0, 0, 1};
    return {ptr, srv, txt, a};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    auto message = parseDnsMessage(bytes);
    if (!message) return 0;

    ServiceCache cache;
    const auto now = Clock::now();
    (void)cache.ingest(*message, {127, 0, 0, 1}, now);
    (void)cache.refreshQueries(now);
    for (const auto& q : message->questions) {
        cache.questionSeen(q, {"fuzz._opcua-tcp._tcp.local"}, now);
    }
    (void)cache.knownAnswers(now);
    (void)cache.expire(now + std::chrono::hours(48));

    // The planner keeps state from one input to the next, as a responder does.
    static ResponsePlanner planner = [] {
        ResponsePlanner p(1);
        p.setOwn(ownRecords());
        return p;
    }();
    if (message->isResponse) {
        planner.onResponse(*message, now);
    } else {
        planner.onQuery(*message, {127, 0, 0, 1}, now);
    }
    (void)planner.takeDue(now + std::chrono::seconds(2));

    if (!message->isResponse && size <= MDNS_ADAPTER_MAX_INPUT) {
        mdns_adapter* a = responder();
        mdns_adapter_in(a, data, size, 0x0100007F, 5353);
        const unsigned char* out = nullptr;
        int multicast = 0;
        std::uint32_t ip = 0;
        unsigned short port = 0;
        for (int i = 0; i < 64 && mdns_adapter_out(a, &out, &multicast, &ip, &port) > 0; ++i) {
        }
    }

    auto encoded = encodeDnsMessage(*message);
    if (!encoded || encoded->size() > kMaxMdnsMessage) return 0;  // decompressed, may grow
    auto again = parseDnsMessage(*encoded);
    if (!again || again->questions.size() != message->questions.size() ||
        again->records.size() != message->records.size()) {
        std::abort();
    }
    for (std::size_t i = 0; i < message->records.size(); ++i) {
        const auto& x = message->records[i];
        const auto& y = again->records[i];
        if (foldCase(x.name) != foldCase(y.name) || x.type != y.type || x.ttl != y.ttl ||
            x.target != y.target || x.txt != y.txt || x.port != y.port || x.rdata != y.rdata) {
            std::abort();
        }
    }
    return 0;
}
