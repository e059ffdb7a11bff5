// ServiceCache with a fake clock: when a server counts as announced, how goodbyes and TTL
// expiry remove it, when refresh queries go out, which address is chosen.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "ua/discovery/service_cache.hpp"

namespace skillcell::ua::mdns::service_cache_test {
namespace {

using namespace std::chrono_literals;

constexpr Ipv4 kHostA{198, 18, 0, 1};
constexpr Ipv4 kHostB{198, 18, 0, 2};

DnsRecord record(std::string name, DnsType type, std::uint32_t ttl) {
    DnsRecord r;
    r.name = std::move(name);
    r.type = static_cast<std::uint16_t>(type);
    r.ttl = ttl;
    return r;
}

/// The four records of one announcement, as a responder sends them.
DnsMessage announcement(const std::string& server, const std::string& host, Ipv4 address,
                        std::uint16_t port, std::uint32_t ttl = 120,
                        std::vector<std::string> txt = {"path=/", "caps=LDS"}) {
    const std::string instance = server + "._opcua-tcp._tcp.local";
    DnsMessage m;
    m.isResponse = true;
    auto ptr = record("_opcua-tcp._tcp.local", DnsType::Ptr, ttl);
    ptr.target = instance;
    auto srv = record(instance, DnsType::Srv, ttl);
    srv.target = host;
    srv.port = port;
    auto t = record(instance, DnsType::Txt, ttl);
    t.txt = std::move(txt);
    auto a = record(host, DnsType::A, ttl);
    a.ipv4 = address;
    m.records = {ptr, srv, t, a};
    return m;
}

class ServiceCacheTest : public testing::Test {
protected:
    Clock::time_point t0 = Clock::time_point{} + 1000s;
    ServiceCache cache;
};

TEST_F(ServiceCacheTest, AnnouncesACompleteServiceOnce) {
    auto events = cache.ingest(announcement("pump", "host-a.local", kHostA, 4840), kHostA, t0);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, ServiceEvent::Kind::Announced);
    const auto& s = events[0].instance;
    EXPECT_EQ(s.name, "pump");
    EXPECT_EQ(s.discoveryUrl(), "opc.tcp://198.18.0.1:4840/");
    EXPECT_TRUE(s.hasCapability("lds"));
    // The same records again (a re-announcement) change nothing.
    EXPECT_TRUE(
        cache.ingest(announcement("pump", "host-a.local", kHostA, 4840), kHostA, t0 + 1s).empty());
    EXPECT_EQ(cache.size(), 1u);
}

TEST_F(ServiceCacheTest, WaitsForEveryRecordBeforeAnnouncing) {
    auto m = announcement("pump", "host-a.local", kHostA, 4840);
    DnsMessage partial = m;
    partial.records.pop_back();  // no A record yet
    EXPECT_TRUE(cache.ingest(partial, kHostA, t0).empty());
    DnsMessage rest;
    rest.isResponse = true;
    rest.records = {m.records.back()};
    EXPECT_EQ(cache.ingest(rest, kHostA, t0).size(), 1u);
}

TEST_F(ServiceCacheTest, AGoodbyeRemovesAtOnce) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840), kHostA, t0);
    auto bye = announcement("pump", "host-a.local", kHostA, 4840, 0);
    bye.records.pop_back();  // services say goodbye; the host's address stays
    auto events = cache.ingest(bye, kHostA, t0 + 1s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, ServiceEvent::Kind::Gone);
    EXPECT_EQ(events[0].reason, RemovalReason::Goodbye);
    EXPECT_EQ(cache.size(), 0u);
}

TEST_F(ServiceCacheTest, ExpiresWhenTheTtlRunsOutAndNotBefore) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 3), kHostA, t0);
    EXPECT_TRUE(cache.expire(t0 + 2999ms).empty());
    auto events = cache.expire(t0 + 3s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, ServiceEvent::Kind::Gone);
    EXPECT_EQ(events[0].reason, RemovalReason::Expired);
}

TEST_F(ServiceCacheTest, AsksAgainAt80To95PercentOfTheTtl) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 10), kHostA, t0);
    EXPECT_TRUE(cache.refreshQueries(t0 + 7s).empty());
    EXPECT_EQ(*cache.nextDeadline(), t0 + 8s);
    auto q = cache.refreshQueries(t0 + 8s);
    auto asks = [&](const std::string& name, DnsType type) {
        return std::any_of(q.begin(), q.end(), [&](const DnsQuestion& x) {
            return x.name == name && x.type == static_cast<std::uint16_t>(type);
        });
    };
    EXPECT_TRUE(asks("pump._opcua-tcp._tcp.local", DnsType::Srv));
    EXPECT_TRUE(asks("pump._opcua-tcp._tcp.local", DnsType::Txt));
    EXPECT_TRUE(asks("host-a.local", DnsType::A));
    EXPECT_TRUE(asks("_opcua-tcp._tcp.local", DnsType::Ptr));
    EXPECT_TRUE(cache.refreshQueries(t0 + 8s).empty());  // asked once per threshold
    EXPECT_FALSE(cache.refreshQueries(t0 + 8500ms).empty());
    // The answer renews the records: no expiry at the old TTL.
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 10), kHostA, t0 + 9s);
    EXPECT_TRUE(cache.expire(t0 + 10s).empty());
    EXPECT_EQ(cache.size(), 1u);
}

TEST_F(ServiceCacheTest, PicksTheAddressTheServiceWasAnnouncedFrom) {
    // Two hosts with the same host name (network namespaces share one UTS name), each
    // announcing its own address: each service gets the address of its own sender.
    cache.ingest(announcement("a", "twin.local", kHostA, 4840), kHostA, t0);
    cache.ingest(announcement("b", "twin.local", kHostB, 4841), kHostB, t0);
    for (const auto& s : cache.services()) {
        EXPECT_EQ(s.address, s.name == "a" ? kHostA : kHostB) << s.name;
    }
}

TEST_F(ServiceCacheTest, ReadsPathAndCapabilitiesFromTxt) {
    auto events = cache.ingest(
        announcement("x", "h.local", kHostA, 4840, 120, {"PATH=UA/Server", "caps=DA,HD,,"}), kHostA,
        t0);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].instance.path, "/UA/Server");
    EXPECT_EQ(events[0].instance.capabilities, (std::vector<std::string>{"DA", "HD"}));
}

TEST_F(ServiceCacheTest, AChangedPortIsAnnouncedAgain) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840), kHostA, t0);
    auto events = cache.ingest(announcement("pump", "host-a.local", kHostA, 4841), kHostA, t0 + 1s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, ServiceEvent::Kind::Announced);
    EXPECT_EQ(events[0].instance.port, 4841);
}

TEST_F(ServiceCacheTest, IgnoresOtherServiceTypesAndClasses) {
    auto m = announcement("pump", "host-a.local", kHostA, 4840);
    for (auto& r : m.records) {
        if (r.name.find("_opcua-tcp") != std::string::npos) {
            r.name = "x._http._tcp.local";
        }
    }
    EXPECT_TRUE(cache.ingest(m, kHostA, t0).empty());
    auto chaos = announcement("pump", "host-a.local", kHostA, 4840);
    for (auto& r : chaos.records) r.rrclass = 3;  // CHAOS
    EXPECT_TRUE(cache.ingest(chaos, kHostA, t0).empty());
}

TEST_F(ServiceCacheTest, AFloodOfAnnouncementsIsBounded) {
    for (int i = 0; i < 3000; ++i) {
        cache.ingest(announcement("s" + std::to_string(i), "h.local", kHostA, 4840), kHostA, t0);
    }
    EXPECT_LE(cache.size(), 1024u);
    EXPECT_GT(cache.size(), 0u);
}

}  // namespace
}  // namespace skillcell::ua::mdns::service_cache_test

namespace skillcell::ua::mdns::service_cache_test {
namespace {

TEST(ServiceCacheLiteral, AnIpv4LiteralTargetNeedsNoAddressRecord) {
    // node-opcua on loopback: SRV target "127.0.0.1", no A record.
    ServiceCache cache;
    auto m = announcement("node-lds", "127.0.0.1", {127, 0, 0, 1}, 4840);
    m.records.pop_back();
    auto events = cache.ingest(m, {127, 0, 0, 1}, Clock::now());
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].instance.discoveryUrl(), "opc.tcp://127.0.0.1:4840/");
    EXPECT_FALSE(parseIpv4Literal("127.0.0.256"));
    EXPECT_FALSE(parseIpv4Literal("1.2.3"));
    EXPECT_FALSE(parseIpv4Literal("a.b.c.d"));
}

TEST_F(ServiceCacheTest, KnownAnswersAreThePointersWithMoreThanHalfTheirTtlLeft) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 100), kHostA, t0);
    cache.ingest(announcement("press", "host-b.local", kHostB, 4840, 100), kHostB, t0 + 30s);
    auto known = cache.knownAnswers(t0 + 40s);
    ASSERT_EQ(known.size(), 2u);
    EXPECT_EQ(known[0].target, "press._opcua-tcp._tcp.local");
    EXPECT_EQ(known[0].ttl, 90u);  // what it has left
    EXPECT_EQ(known[1].ttl, 60u);
    // At 50 s pump has half its TTL left: no longer a known answer.
    known = cache.knownAnswers(t0 + 50s);
    ASSERT_EQ(known.size(), 1u);
    EXPECT_EQ(known[0].target, "press._opcua-tcp._tcp.local");
    EXPECT_TRUE(cache.knowsAll({"press._opcua-tcp._tcp.local"}, t0 + 50s));
    EXPECT_FALSE(cache.knowsAll({"pump._opcua-tcp._tcp.local"}, t0 + 50s));
    EXPECT_FALSE(cache.knowsAll({"other._opcua-tcp._tcp.local"}, t0 + 50s));
}

TEST_F(ServiceCacheTest, AnotherHostAskingFirstCountsAsOurRefresh) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 100), kHostA, t0);
    // Another host asks for pump's SRV and TXT and the address just before our 80 % refresh.
    const std::set<std::string> none;
    cache.questionSeen(
        {"pump._opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Srv), kClassIn}, none,
        t0 + 78s);
    cache.questionSeen(
        {"pump._opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Txt), kClassIn}, none,
        t0 + 78s);
    cache.questionSeen({"host-a.local", static_cast<std::uint16_t>(DnsType::A), kClassIn}, none,
                       t0 + 78s);
    // Its browse lists pump as known: that does not refresh our pointer.
    cache.questionSeen(
        {"_opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Ptr), kClassIn},
        {"pump._opcua-tcp._tcp.local"}, t0 + 78s);
    auto q = cache.refreshQueries(t0 + 80s);
    ASSERT_EQ(q.size(), 1u);
    EXPECT_EQ(q[0].name, "_opcua-tcp._tcp.local");
}

TEST_F(ServiceCacheTest, AQuestionSeenLongBeforeOurRefreshDoesNotReplaceIt) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 100), kHostA, t0);
    cache.questionSeen(
        {"pump._opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Srv), kClassIn}, {},
        t0 + 50s);
    const auto q = cache.refreshQueries(t0 + 80s);
    EXPECT_TRUE(std::any_of(q.begin(), q.end(), [](const DnsQuestion& x) {
        return x.type == static_cast<std::uint16_t>(DnsType::Srv);
    }));
}

TEST(ServiceCacheSubtype, TheLdsSubtypeIsNamedAfterTheCapability) {
    EXPECT_EQ(subtypeName(kLdsCapability), "_lds._sub._opcua-tcp._tcp.local");
}

TEST_F(ServiceCacheTest, ASubtypePointerNamesTheInstanceAsTheTypesDoes) {
    // An LDS answering a query for the subtype: its PTR is the subtype's, not the type's.
    auto m = announcement("the-lds", "host-a.local", kHostA, 4840);
    m.records[0].name = "_lds._sub._opcua-tcp._tcp.local";
    auto events = cache.ingest(m, kHostA, t0);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].instance.name, "the-lds");
    // A subtype of another service type, or a malformed one, names nothing.
    ServiceCache other;
    auto wrong = announcement("x", "host-b.local", kHostB, 4840);
    wrong.records[0].name = "_lds._sub._http._tcp.local";
    EXPECT_TRUE(other.ingest(wrong, kHostB, t0).empty());
    wrong.records[0].name = "_a.b._sub._opcua-tcp._tcp.local";
    EXPECT_TRUE(other.ingest(wrong, kHostB, t0).empty());
}

TEST_F(ServiceCacheTest, AnInterestInLdsesRefreshesOnlyTheirRecordsAndAsksForTheSubtype) {
    cache.setInterest(std::string(kLdsCapability));
    EXPECT_EQ(cache.browseName(), "_lds._sub._opcua-tcp._tcp.local");
    cache.ingest(announcement("the-lds", "host-a.local", kHostA, 4840, 10), kHostA, t0);
    cache.ingest(announcement("pump", "host-b.local", kHostB, 4841, 10, {"path=/", "caps=DA"}),
                 kHostB, t0);
    EXPECT_EQ(cache.size(), 1u);  // the pump's TXT says it is no LDS: it is not kept
    auto q = cache.refreshQueries(t0 + 8s);
    std::set<std::string> asked;
    for (const auto& x : q) asked.insert(x.name);
    EXPECT_EQ(asked, (std::set<std::string>{"_lds._sub._opcua-tcp._tcp.local",
                                            "the-lds._opcua-tcp._tcp.local", "host-a.local"}));
    // The known answers of a subtype query list the LDSes only, under the subtype's name.
    auto known = cache.knownAnswers(t0 + 1s, cache.browseName());
    ASSERT_EQ(known.size(), 1u);
    EXPECT_EQ(known[0].name, "_lds._sub._opcua-tcp._tcp.local");
    EXPECT_EQ(known[0].target, "the-lds._opcua-tcp._tcp.local");
    EXPECT_EQ(cache.knownAnswers(t0 + 1s).size(), 1u);  // of the type: every server kept
    const auto gone = cache.expire(t0 + 10s);
    EXPECT_EQ(gone.size(), 1u);
}

// A registrar hears every server's answer to every detector's browse: it keeps only the
// instances that may be LDSes, and the addresses of their hosts.
TEST_F(ServiceCacheTest, AnInterestInLdsesKeepsNoRecordOfTheOtherServers) {
    cache.setInterest(std::string(kLdsCapability));
    for (int i = 0; i < 50; ++i) {
        const Ipv4 ip{198, 18, 2, static_cast<std::uint8_t>(i)};
        EXPECT_TRUE(
            cache
                .ingest(announcement("s" + std::to_string(i), "h" + std::to_string(i) + ".local",
                                     ip, 4840, 120, {"path=/", "caps=DA"}),
                        ip, t0)
                .empty());
    }
    EXPECT_EQ(cache.size(), 0u);
    EXPECT_EQ(cache.queued(), 0u);  // nothing stored, nothing waiting for its time
    EXPECT_TRUE(cache.refreshQueries(t0).empty());
    // An LDS is kept; when its TXT no longer names the capability, it is gone.
    ASSERT_EQ(
        cache.ingest(announcement("the-lds", "host-a.local", kHostA, 4840), kHostA, t0).size(), 1u);
    auto changed = announcement("the-lds", "host-a.local", kHostA, 4840, 120, {"caps=DA"});
    changed.records = {changed.records[2]};  // the TXT alone
    const auto events = cache.ingest(changed, kHostA, t0 + 1s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, ServiceEvent::Kind::Gone);
    EXPECT_EQ(cache.size(), 0u);
    EXPECT_TRUE(cache.knownAnswers(t0 + 2s).empty());
}

// A server that becomes an LDS may say so in its TXT alone: the cache, which did not keep its
// other records, asks for the LDSes' PTR (whose answer brings SRV, TXT and address along).
TEST_F(ServiceCacheTest, AnInterestInLdsesAsksForAnLdsItKnowsOnlyTheTxtOf) {
    cache.setInterest(std::string(kLdsCapability));
    auto m = announcement("new-lds", "host-a.local", kHostA, 4840);
    m.records = {m.records[2]};
    EXPECT_TRUE(cache.ingest(m, kHostA, t0).empty());
    EXPECT_TRUE(cache.ingest(m, kHostA, t0).empty());  // heard twice: asked once
    ASSERT_TRUE(cache.nextDeadline());
    EXPECT_LE(*cache.nextDeadline(), t0);
    const auto q = cache.refreshQueries(t0);
    ASSERT_EQ(q.size(), 1u);
    EXPECT_EQ(q[0].name, "_lds._sub._opcua-tcp._tcp.local");
    EXPECT_EQ(q[0].type, static_cast<std::uint16_t>(DnsType::Ptr));
    EXPECT_EQ(
        cache.ingest(announcement("new-lds", "host-a.local", kHostA, 4840), kHostA, t0 + 1s).size(),
        1u);
}

TEST_F(ServiceCacheTest, AnotherHostsSubtypeQueryCountsAsOurRefreshOfTheLdsesOnly) {
    cache.setInterest(std::string(kLdsCapability));
    cache.ingest(announcement("the-lds", "host-a.local", kHostA, 4840, 100), kHostA, t0);
    cache.questionSeen(
        {"_lds._sub._opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Ptr), kClassIn}, {},
        t0 + 79s);
    auto q = cache.refreshQueries(t0 + 80s);
    EXPECT_TRUE(std::none_of(q.begin(), q.end(), [](const DnsQuestion& x) {
        return x.type == static_cast<std::uint16_t>(DnsType::Ptr);
    }));
}

// Records' times wait in a queue, moved later lazily: a record renewed before its refresh
// time is not asked for at the old time, and the next deadline follows the renewal.
TEST_F(ServiceCacheTest, ARecordRenewedBeforeItsRefreshTimeIsAskedForAtItsNewOneOnly) {
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 100), kHostA, t0);
    EXPECT_EQ(*cache.nextDeadline(), t0 + 80s);
    cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 100), kHostA, t0 + 50s);
    // The old time comes (an early wake): nothing to ask, nothing gone.
    EXPECT_TRUE(cache.refreshQueries(t0 + 80s).empty());
    EXPECT_TRUE(cache.expire(t0 + 80s).empty());
    EXPECT_EQ(*cache.nextDeadline(), t0 + 130s);
    EXPECT_EQ(cache.refreshQueries(t0 + 130s).size(), 4u);  // PTR, SRV, TXT, A
    EXPECT_EQ(cache.expire(t0 + 149s).size(), 0u);
    EXPECT_EQ(cache.expire(t0 + 150s).size(), 1u);  // gone at its renewed TTL
}

// With an interest in LDSes, a server's refresh times pass unasked while it is not known to
// be one; once its TXT says it is, what is due is asked for at once.
TEST_F(ServiceCacheTest, ARecordThatComesToCountIsAskedForWhenItsRefreshIsDue) {
    cache.setInterest(std::string(kLdsCapability));
    auto m = announcement("late-lds", "host-a.local", kHostA, 4840, 100);
    const auto txt = m.records[2];
    m.records.erase(m.records.begin() + 2);  // its TXT comes later
    cache.ingest(m, kHostA, t0);
    EXPECT_TRUE(cache.refreshQueries(t0 + 81s).empty());  // nothing known to count yet
    DnsMessage late;
    late.isResponse = true;
    late.records = {txt};
    EXPECT_EQ(cache.ingest(late, kHostA, t0 + 82s).size(), 1u);  // announced: an LDS
    std::set<std::string> asked;
    for (const auto& q : cache.refreshQueries(t0 + 82s)) asked.insert(q.name);
    EXPECT_EQ(asked, (std::set<std::string>{"_lds._sub._opcua-tcp._tcp.local",
                                            "late-lds._opcua-tcp._tcp.local", "host-a.local"}));
}

// Many instances: the queue holds one entry per record however often they are renewed, and
// everything still expires on time.
TEST_F(ServiceCacheTest, ManyRenewalsStillExpireEachRecordOnTime) {
    for (int round = 0; round < 20; ++round) {
        for (int i = 0; i < 50; ++i) {
            const Ipv4 ip{198, 18, 1, static_cast<std::uint8_t>(i)};
            cache.ingest(announcement("s" + std::to_string(i), "h" + std::to_string(i) + ".local",
                                      ip, 4840, 100),
                         ip, t0 + std::chrono::seconds(round));
        }
    }
    EXPECT_EQ(cache.size(), 50u);
    EXPECT_TRUE(cache.expire(t0 + 118s).empty());
    EXPECT_EQ(cache.expire(t0 + 119s).size(), 50u);
    EXPECT_EQ(cache.size(), 0u);
    (void)cache.refreshQueries(t0 + 119s);  // the refreshes that came due on the way
    EXPECT_FALSE(cache.nextDeadline().has_value());
}

// A sender that shortens its records' TTL again and again moves their times earlier each
// time: the queue is made again from the records before it grows without end.
TEST_F(ServiceCacheTest, RecordsShortenedAgainAndAgainKeepTheQueueBounded) {
    std::size_t most = 0;
    for (std::uint32_t ttl = 66'000; ttl > 0; --ttl) {  // past 64 Ki entries once
        cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, ttl), kHostA, t0);
        most = std::max(most, cache.queued());
    }
    EXPECT_LE(most, 64u * 1024u + 1u);
    EXPECT_EQ(cache.size(), 1u);
    EXPECT_TRUE(cache.expire(t0).empty());
    EXPECT_EQ(cache.expire(t0 + 1s).size(), 1u);  // the last TTL, 1 s, still counts
}

TEST(ServiceCacheJitter, RefreshTimesSpreadOverTwoPercentOfTheTtl) {
    const auto t0 = Clock::time_point{} + 1000s;
    std::set<Clock::time_point> deadlines;
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
        ServiceCache cache(std::string(kOpcUaServiceType), seed);
        cache.ingest(announcement("pump", "host-a.local", kHostA, 4840, 1000), kHostA, t0);
        const auto d = *cache.nextDeadline();
        EXPECT_GE(d, t0 + 800s);
        EXPECT_LE(d, t0 + 820s);
        deadlines.insert(d);
    }
    EXPECT_GT(deadlines.size(), 3u);
}

TEST(ServiceCacheLiteral, AsksForTheAddressOfATargetThatCameWithout) {
    ServiceCache cache;
    auto m = announcement("pump", "far.local", {198, 18, 0, 1}, 4840);
    m.records.pop_back();
    EXPECT_TRUE(cache.ingest(m, {198, 18, 0, 1}, Clock::now()).empty());
    auto q = cache.refreshQueries(Clock::now());
    ASSERT_EQ(q.size(), 1u);
    EXPECT_EQ(q[0].name, "far.local");
    EXPECT_EQ(q[0].type, static_cast<std::uint16_t>(DnsType::A));
}

}  // namespace
}  // namespace skillcell::ua::mdns::service_cache_test
