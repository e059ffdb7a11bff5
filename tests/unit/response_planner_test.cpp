// ResponsePlanner and BrowseSchedule with a fake clock: when our answers leave and what they
// leave out (RFC 6762 6, 7.1, 7.2, 7.4), and how a browser's queries back off (5.2, 7.3).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "ua/discovery/browse_schedule.hpp"
#include "ua/discovery/response_planner.hpp"

namespace skillcell::ua::mdns::response_planner_test {
namespace {

using namespace std::chrono_literals;

constexpr Ipv4 kAsker{198, 18, 0, 7};
constexpr Ipv4 kOtherAsker{198, 18, 0, 8};
constexpr std::uint32_t kTtl = 120;
const std::string kType(kOpcUaServiceType);

DnsRecord rec(std::string name, DnsType type, std::uint32_t ttl = kTtl) {
    DnsRecord r;
    r.name = std::move(name);
    r.type = static_cast<std::uint16_t>(type);
    r.ttl = ttl;
    return r;
}

/// What one process publishes for the servers `names` on host h.local, 198.18.0.1.
std::vector<DnsRecord> published(const std::vector<std::string>& names) {
    std::vector<DnsRecord> out;
    auto a = rec("h.local", DnsType::A);
    a.ipv4 = {198, 18, 0, 1};
    out.push_back(a);
    for (const auto& n : names) {
        auto ptr = rec(kType, DnsType::Ptr);
        ptr.target = n + "." + kType;
        auto srv = rec(n + "." + kType, DnsType::Srv);
        srv.port = 4840;
        srv.target = "h.local";
        auto txt = rec(n + "." + kType, DnsType::Txt);
        txt.txt = {"path=/", "caps=NA"};
        out.insert(out.end(), {ptr, srv, txt});
    }
    return out;
}

DnsMessage browse(std::vector<DnsRecord> knownAnswers = {}) {
    DnsMessage m;
    m.questions = {{kType, static_cast<std::uint16_t>(DnsType::Ptr), kClassIn}};
    m.records = std::move(knownAnswers);
    return m;
}

DnsRecord ptrTo(const std::string& name, std::uint32_t ttl) {
    auto p = rec(kType, DnsType::Ptr, ttl);
    p.target = name + "." + kType;
    return p;
}

std::vector<std::string> describe(const std::vector<DnsRecord>& records) {
    std::vector<std::string> out;
    for (const auto& r : records) {
        out.push_back(std::to_string(r.type) + " " + r.name +
                      (r.target.empty() ? "" : " -> " + r.target));
    }
    std::sort(out.begin(), out.end());
    return out;
}

class ResponsePlannerTest : public testing::Test {
protected:
    Clock::time_point t0 = Clock::time_point{} + 1000s;
    ResponsePlanner planner{42};
    std::vector<DnsRecord> own = published({"pump", "press"});
    ResponsePlannerTest() { planner.setOwn(own); }
};

TEST_F(ResponsePlannerTest, ABrowseIsAnsweredAfter20To120MsWithServiceAndAddressRecords) {
    planner.onQuery(browse(), kAsker, t0);
    const auto due = planner.nextDeadline();
    ASSERT_TRUE(due);
    EXPECT_GE(*due - t0, 20ms);
    EXPECT_LE(*due - t0, 120ms);
    EXPECT_TRUE(planner.takeDue(*due - 1ms).empty());
    const auto sent = planner.takeDue(*due);
    // Both PTRs, with each instance's SRV and TXT and the host's address, in one answer.
    EXPECT_EQ(sent.size(), 7u);
    EXPECT_EQ(planner.pendingCount(), 0u);
}

TEST(ResponsePlannerSubtype, AQueryForTheLdsSubtypeIsAnsweredByTheLdsAlone) {
    // One process publishes a pump and an LDS; the LDS also under the subtype (RFC 6763 7.1).
    auto own = published({"pump", "the-lds"});
    const std::string subtype = subtypeName(kLdsCapability);
    auto sub = rec(subtype, DnsType::Ptr);
    sub.target = "the-lds." + kType;
    own.push_back(sub);
    ResponsePlanner planner(7);
    planner.setOwn(own);
    const auto t0 = Clock::time_point{} + 1000s;
    DnsMessage q;
    q.questions = {{subtype, static_cast<std::uint16_t>(DnsType::Ptr), kClassIn}};
    planner.onQuery(q, kAsker, t0);
    const auto sent = planner.takeDue(*planner.nextDeadline());
    std::set<std::string> names;
    for (const auto& r : sent) names.insert(r.name);
    // The subtype's PTR, the LDS's SRV and TXT and the host's address; nothing of the pump.
    EXPECT_EQ(sent.size(), 4u);
    EXPECT_EQ(names, (std::set<std::string>{subtype, "the-lds." + kType, "h.local"}));
    // Who knows the LDS already (a known answer under the subtype) gets nothing.
    DnsMessage knowing = q;
    auto known = sub;
    known.ttl = kTtl;
    knowing.records = {known};
    planner.onQuery(knowing, kAsker, t0 + 5s);
    EXPECT_EQ(planner.pendingCount(), 0u);
}

TEST_F(ResponsePlannerTest, DelaysDifferFromQueryToQuery) {
    std::set<Clock::duration> delays;
    for (int i = 0; i < 8; ++i) {
        const auto at = t0 + std::chrono::seconds(2 * i);  // past the one-second repeat gap
        planner.onQuery(browse(), kAsker, at);
        delays.insert(*planner.nextDeadline() - at);
        (void)planner.takeDue(*planner.nextDeadline());
    }
    EXPECT_GT(delays.size(), 1u);
}

TEST_F(ResponsePlannerTest, AKnownAnswerWithHalfItsTtlSuppressesThatServiceOnly) {
    planner.onQuery(browse({ptrTo("pump", kTtl / 2)}), kAsker, t0);
    const auto sent = describe(planner.takeDue(t0 + 200ms));
    EXPECT_EQ(sent, describe({own[0], own[4], own[5], own[6]}));  // press and the address
}

TEST_F(ResponsePlannerTest, AKnownAnswerWithLessThanHalfItsTtlDoesNotSuppress) {
    planner.onQuery(browse({ptrTo("pump", kTtl / 2 - 1), ptrTo("press", kTtl / 2 - 1)}), kAsker,
                    t0);
    EXPECT_EQ(planner.takeDue(t0 + 200ms).size(), 7u);
}

TEST_F(ResponsePlannerTest, AQueryWhoseKnownAnswersCoverEverythingIsNotAnswered) {
    planner.onQuery(browse({ptrTo("pump", kTtl), ptrTo("press", kTtl)}), kAsker, t0);
    EXPECT_FALSE(planner.nextDeadline());
}

TEST_F(ResponsePlannerTest, MoreKnownAnswersToComeWait400To500MsAndCount) {
    auto first = browse({ptrTo("pump", kTtl)});
    first.truncated = true;
    planner.onQuery(first, kAsker, t0);
    const auto due = *planner.nextDeadline();
    EXPECT_GE(due - t0, 400ms);
    EXPECT_LE(due - t0, 500ms);
    DnsMessage rest;  // the continuation: known answers only
    rest.records = {ptrTo("press", kTtl)};
    planner.onQuery(rest, kAsker, t0 + 10ms);
    EXPECT_TRUE(planner.takeDue(due - 1ms).empty());
    // The querier knows both servers: nothing to send.
    EXPECT_TRUE(planner.takeDue(due).empty());
    EXPECT_FALSE(planner.nextDeadline());
}

TEST_F(ResponsePlannerTest, AHeldQueryIsAnsweredWithWhatItsKnownAnswersLack) {
    auto first = browse({ptrTo("pump", kTtl)});
    first.truncated = true;
    planner.onQuery(first, kAsker, t0);
    const auto due = *planner.nextDeadline();
    EXPECT_EQ(describe(planner.takeDue(due)),
              describe({own[0], own[4], own[5], own[6]}));  // press and the address
}

TEST_F(ResponsePlannerTest, AnotherQuerierKeepsTheAnswerThatOneQuerierRetires) {
    auto q = browse();
    q.truncated = true;
    planner.onQuery(q, kAsker, t0);
    planner.onQuery(browse(), kOtherAsker, t0 + 1ms);
    DnsMessage rest;
    rest.records = {ptrTo("pump", kTtl), ptrTo("press", kTtl)};
    planner.onQuery(rest, kAsker, t0 + 2ms);
    EXPECT_EQ(planner.takeDue(t0 + 600ms).size(), 7u);
}

TEST_F(ResponsePlannerTest, AQueryFromTheAddressOfAHeldOneIsAnsweredOnItsOwn) {
    // Two processes of one host (one address): the first's browse knows every server and is
    // held for more known answers; the second's knows none and must still be answered.
    auto first = browse({ptrTo("pump", kTtl), ptrTo("press", kTtl)});
    first.truncated = true;
    planner.onQuery(first, kAsker, t0);
    planner.onQuery(browse(), kAsker, t0 + 5ms);
    const auto due = *planner.nextDeadline();
    EXPECT_LE(due - t0, 5ms + 120ms);
    EXPECT_EQ(planner.takeDue(due).size(), 7u);  // both services and the address
    // The held query's own continuation still joins it, and it asks for nothing more.
    DnsMessage rest;
    rest.records = {ptrTo("pump", kTtl)};
    planner.onQuery(rest, kAsker, t0 + 10ms);
    EXPECT_TRUE(planner.takeDue(t0 + 600ms).empty());
}

TEST_F(ResponsePlannerTest, AnswersPendingTogetherLeaveTogether) {
    DnsMessage srvQuestion;
    srvQuestion.questions = {{"pump." + kType, static_cast<std::uint16_t>(DnsType::Srv), kClassIn}};
    planner.onQuery(srvQuestion, kAsker, t0);
    planner.onQuery(browse({ptrTo("pump", kTtl)}), kOtherAsker, t0 + 5ms);
    const auto due = *planner.nextDeadline();
    const auto sent = planner.takeDue(due + 120ms);
    // press's PTR, SRV, TXT; pump's SRV; the address: one datagram's worth, not two.
    EXPECT_EQ(sent.size(), 5u);
    EXPECT_EQ(planner.pendingCount(), 0u);
}

TEST_F(ResponsePlannerTest, ARecordAnotherResponderSentMeanwhileIsNotSentAgain) {
    planner.onQuery(browse(), kAsker, t0);
    DnsMessage response;
    response.isResponse = true;
    response.records = {own[1], own[2], own[3]};  // pump's PTR, SRV, TXT, full TTL
    planner.onResponse(response, t0 + 10ms);
    EXPECT_EQ(describe(planner.takeDue(t0 + 200ms)), describe({own[0], own[4], own[5], own[6]}));
}

TEST_F(ResponsePlannerTest, ADuplicateWithLessThanHalfOurTtlDoesNotSuppress) {
    planner.onQuery(browse(), kAsker, t0);
    DnsMessage response;
    response.isResponse = true;
    response.records = {own[1]};
    response.records[0].ttl = kTtl / 2 - 1;
    planner.onResponse(response, t0 + 10ms);
    EXPECT_EQ(planner.takeDue(t0 + 200ms).size(), 7u);
}

TEST_F(ResponsePlannerTest, ARecordIsNotMulticastTwiceWithinASecond) {
    planner.onQuery(browse(), kAsker, t0);
    ASSERT_EQ(planner.takeDue(t0 + 200ms).size(), 7u);
    planner.onQuery(browse(), kOtherAsker, t0 + 300ms);
    const auto due = *planner.nextDeadline();
    EXPECT_GE(due, t0 + 1200ms);
    EXPECT_TRUE(planner.takeDue(t0 + 1100ms).empty());
    EXPECT_EQ(planner.takeDue(due).size(), 7u);
}

TEST_F(ResponsePlannerTest, QuestionsForWhatWeDoNotHaveAreNotAnswered) {
    DnsMessage q;
    q.questions = {{"other." + kType, static_cast<std::uint16_t>(DnsType::Srv), kClassIn},
                   {"_http._tcp.local", static_cast<std::uint16_t>(DnsType::Ptr), kClassIn},
                   {kType, static_cast<std::uint16_t>(DnsType::Ptr), 3}};  // CHAOS
    planner.onQuery(q, kAsker, t0);
    EXPECT_FALSE(planner.nextDeadline());
}

TEST_F(ResponsePlannerTest, ARecordNobodyAsksForIsSentAgainTwoSecondsBeforeItsTtlRunsOut) {
    DnsMessage announcement;  // libmdnsd's, looped back to us
    announcement.isResponse = true;
    announcement.records = own;
    EXPECT_FALSE(planner.nextDeadline());  // nothing of ours on the link yet: nothing to renew
    planner.onResponse(announcement, t0);
    EXPECT_EQ(*planner.nextDeadline(), t0 + 118s);
    EXPECT_TRUE(planner.takeDue(t0 + 117s).empty());
    EXPECT_EQ(planner.takeDue(t0 + 118s).size(), 7u);
    EXPECT_EQ(*planner.nextDeadline(), t0 + 236s);
}

TEST_F(ResponsePlannerTest, AShortTtlIsRenewedAtHalfOfItButNotWithinASecond) {
    std::vector<DnsRecord> shortLived = published({"pump"});
    for (auto& r : shortLived) r.ttl = 3;
    planner.setOwn(shortLived);
    DnsMessage announcement;
    announcement.isResponse = true;
    announcement.records = shortLived;
    planner.onResponse(announcement, t0);
    EXPECT_EQ(*planner.nextDeadline(), t0 + 1500ms);
    for (auto& r : shortLived) r.ttl = 1;
    planner.setOwn(shortLived);
    planner.onResponse(announcement, t0);
    EXPECT_EQ(*planner.nextDeadline(), t0 + 1s);
}

TEST(RecordIdentity, IgnoresCaseTtlAndClassButNotData) {
    auto a = ptrTo("Pump", 120);
    auto b = ptrTo("pump", 10);
    b.rrclass = kClassIn | kClassTopBit;
    EXPECT_EQ(recordIdentity(a), recordIdentity(b));
    EXPECT_NE(recordIdentity(a), recordIdentity(ptrTo("press", 120)));
}

TEST(BrowseSchedule, AsksAtOnceThenBacksOffByDoublingUpToTheLongest) {
    const auto t0 = Clock::time_point{} + 1000s;
    BrowseSchedule s(10s);
    EXPECT_FALSE(s.active());
    s.restart(t0);
    EXPECT_EQ(*s.next(), t0);
    auto t = t0;
    std::vector<Clock::duration> gaps;
    for (int i = 0; i < 6; ++i) {
        s.sent(t);
        gaps.push_back(*s.next() - t);
        t = *s.next();
    }
    const std::vector<Clock::duration> expected = {1s, 2s, 4s, 8s, 10s, 10s};
    EXPECT_EQ(gaps, expected);
    s.restart(t);  // queryNow(): from the start again
    s.sent(t);
    EXPECT_EQ(*s.next() - t, 1s);
}

TEST(BrowseSchedule, AnotherHostsQueryCountsAsOursOnlyWhenOursIsNear) {
    const auto t0 = Clock::time_point{} + 1000s;
    BrowseSchedule s(std::chrono::minutes(60));
    s.restart(t0);
    s.sent(t0);                    // next at t0 + 1 s
    s.sent(t0 + 1s);               // next at t0 + 3 s, then 4 s
    s.duplicateSeen(t0 + 1500ms);  // just after ours: no change
    EXPECT_EQ(*s.next(), t0 + 3s);
    s.duplicateSeen(t0 + 2500ms);  // ours was due in 0.5 s: counts as sent then
    EXPECT_EQ(*s.next(), t0 + 3s + 4s);
}

// RFC 6762, 5.2 and 7.3: a process's first query waits, and another host's question asked
// meanwhile stands for it, however early in the wait it comes.
// Hosts that count one question as theirs keep each its own phase: with 500 servers looking
// for an LDS, answering to the same question at the same instant would be 500 queries at
// once at every step of the backoff.
TEST(BrowseSchedule, HostsThatHeardOneQuestionDoNotAskAgainAtOneInstant) {
    const auto t0 = Clock::time_point{} + 1000s;
    BrowseSchedule a(std::chrono::minutes(60));
    BrowseSchedule b(std::chrono::minutes(60));
    a.restart(t0, 40ms);
    b.restart(t0, 90ms);
    a.duplicateSeen(t0 + 30ms);  // a third host asked first
    b.duplicateSeen(t0 + 30ms);
    EXPECT_EQ(*a.next(), t0 + 40ms + 1s);
    EXPECT_EQ(*b.next(), t0 + 90ms + 1s);
}

TEST(BrowseSchedule, TheFirstQueryWaitsItsDelayAndAnotherHostsQuestionMeanwhileStandsForIt) {
    const auto t0 = Clock::time_point{} + 1000s;
    BrowseSchedule s(std::chrono::minutes(60));
    s.restart(t0, 70ms);
    EXPECT_EQ(*s.next(), t0 + 70ms);
    s.duplicateSeen(t0 + 5ms);  // early in the wait: still counts, as sent when due
    EXPECT_EQ(*s.next(), t0 + 70ms + 1s);
    // After the first, the half-wait rule holds again: just after ours, no change.
    s.duplicateSeen(t0 + 100ms);
    EXPECT_EQ(*s.next(), t0 + 70ms + 1s);

    BrowseSchedule alone(std::chrono::minutes(60));
    alone.restart(t0, 120ms);
    alone.sent(t0 + 120ms);  // nobody asked: ours goes out, then 1 s, 2 s ...
    EXPECT_EQ(*alone.next(), t0 + 120ms + 1s);
}

}  // namespace
}  // namespace skillcell::ua::mdns::response_planner_test
