// The DNS wire format: what a well-formed message decodes to, and that every kind of
// malformed or oversized datagram is refused with the right status, never read past.
#include <gtest/gtest.h>

#include "ua/discovery/dns_message.hpp"

namespace skillcell::ua::mdns::dns_message_test {
namespace {

DnsRecord srvRecord() {
    DnsRecord r;
    r.name = "pump._opcua-tcp._tcp.local";
    r.type = static_cast<std::uint16_t>(DnsType::Srv);
    r.rrclass = kClassIn | kClassTopBit;
    r.ttl = 120;
    r.port = 4840;
    r.target = "host-a.local";
    return r;
}

TEST(DnsMessage, RoundTripsQuestionsAndEveryRecordType) {
    DnsMessage m;
    m.id = 0;
    m.isResponse = true;
    m.questions.push_back(
        {"_opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Ptr), kClassIn});
    DnsRecord ptr;
    ptr.name = "_opcua-tcp._tcp.local";
    ptr.type = static_cast<std::uint16_t>(DnsType::Ptr);
    ptr.ttl = 4500;
    ptr.target = "pump._opcua-tcp._tcp.local";
    DnsRecord txt;
    txt.name = "pump._opcua-tcp._tcp.local";
    txt.type = static_cast<std::uint16_t>(DnsType::Txt);
    txt.ttl = 120;
    txt.txt = {"path=/ua", "caps=LDS,DA", ""};
    DnsRecord a;
    a.name = "host-a.local";
    a.type = static_cast<std::uint16_t>(DnsType::A);
    a.ttl = 120;
    a.ipv4 = {198, 18, 0, 7};
    DnsRecord aaaa;
    aaaa.name = "host-a.local";
    aaaa.type = static_cast<std::uint16_t>(DnsType::Aaaa);
    aaaa.ipv6[0] = 0xfe;
    aaaa.ipv6[15] = 1;
    DnsRecord other;
    other.name = "x.local";
    other.type = 99;
    other.rdata = {1, 2, 3};
    m.records = {ptr, srvRecord(), txt, a, aaaa, other};

    auto bytes = encodeDnsMessage(m);
    ASSERT_TRUE(bytes.ok());
    std::string why;
    auto back = parseDnsMessage(*bytes, &why);
    ASSERT_TRUE(back.ok()) << why;
    EXPECT_TRUE(back->isResponse);
    ASSERT_EQ(back->questions.size(), 1u);
    EXPECT_EQ(back->questions[0].name, "_opcua-tcp._tcp.local");
    ASSERT_EQ(back->records.size(), 6u);
    EXPECT_EQ(back->records[0].target, "pump._opcua-tcp._tcp.local");
    EXPECT_EQ(back->records[1].port, 4840);
    EXPECT_EQ(back->records[1].target, "host-a.local");
    EXPECT_TRUE(back->records[1].cacheFlush());
    EXPECT_EQ(back->records[2].txt, txt.txt);
    EXPECT_EQ(back->records[3].ipv4, a.ipv4);
    EXPECT_EQ(back->records[4].ipv6, aaaa.ipv6);
    EXPECT_EQ(back->records[5].rdata, other.rdata);
}

// A response by hand: header, one PTR answer whose rdata points back at the question name.
std::vector<std::uint8_t> compressedResponse() {
    return {0, 0, 0x84, 0, 0, 1, 0, 1, 0, 0, 0, 0,
            // question at 12: "_t._tcp.local" PTR IN
            2, '_', 't', 4, '_', 't', 'c', 'p', 5, 'l', 'o', 'c', 'a', 'l', 0, 0, 12, 0, 1,
            // answer: name = pointer to 12, PTR IN, ttl 120, rdlength 5: "a" + pointer to 12
            0xC0, 12, 0, 12, 0, 1, 0, 0, 0, 120, 0, 4, 1, 'a', 0xC0, 12};
}

TEST(DnsMessage, FollowsBackwardCompressionPointers) {
    auto m = parseDnsMessage(compressedResponse());
    ASSERT_TRUE(m.ok());
    ASSERT_EQ(m->records.size(), 1u);
    EXPECT_EQ(m->records[0].name, "_t._tcp.local");
    EXPECT_EQ(m->records[0].target, "a._t._tcp.local");
}

struct Malformed {
    const char* what;
    std::vector<std::uint8_t> bytes;
};

class DnsMessageMalformed : public testing::TestWithParam<Malformed> {};

TEST_P(DnsMessageMalformed, IsRefusedWithBadDecodingError) {
    std::string why;
    auto m = parseDnsMessage(GetParam().bytes, &why);
    EXPECT_EQ(m.status(), status::BadDecodingError) << GetParam().what;
    EXPECT_FALSE(why.empty());
}

std::vector<Malformed> malformedCases() {
    const std::vector<std::uint8_t> good = compressedResponse();
    std::vector<Malformed> cases;
    cases.push_back({"empty", {}});
    cases.push_back({"half a header", {0, 0, 0x84, 0, 0}});
    auto truncated = good;
    truncated.pop_back();
    cases.push_back({"truncated rdata", truncated});
    auto trailing = good;
    trailing.push_back(0);
    cases.push_back({"trailing byte", trailing});
    auto selfPointer = good;
    selfPointer[31] = 0xC0;  // the answer's name points at itself
    selfPointer[32] = 31;
    cases.push_back({"pointer to itself", selfPointer});
    auto forward = good;
    forward[32] = 40;  // points forward
    cases.push_back({"forward pointer", forward});
    auto counts = good;
    counts[7] = 200;  // 200 answers in a 50-byte message
    cases.push_back({"counts beyond the data", counts});
    auto rdlen = good;
    rdlen[42] = 3;  // PTR rdlength 3, name is 4 bytes
    cases.push_back({"rdlength shorter than the name", rdlen});
    auto reserved = good;
    reserved[12] = 0x80;  // label type 10: reserved
    cases.push_back({"reserved label type", reserved});
    auto opcode = good;
    opcode[2] = 0x84 | (2 << 3);
    cases.push_back({"opcode STATUS", opcode});
    // A record with 5 bytes of rdata.
    std::vector<std::uint8_t> badA = {0, 0, 0x84, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 'h', 0,
                                      0, 1, 0,    1, 0, 0, 0, 1, 0, 5, 1, 2, 3, 4,   5};
    cases.push_back({"A record of 5 bytes", badA});
    // TXT string longer than its rdata.
    std::vector<std::uint8_t> badTxt = {0, 0, 0x84, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,   'h',
                                        0, 0, 16,   0, 1, 0, 0, 0, 1, 0, 3, 9, 'a', 'b'};
    cases.push_back({"TXT overrun", badTxt});
    // A label of 64 bytes.
    std::vector<std::uint8_t> longLabel = {0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 64};
    longLabel.insert(longLabel.end(), 64, 'x');
    longLabel.insert(longLabel.end(), {0, 0, 1, 0, 1});
    cases.push_back({"label of 64 bytes", longLabel});
    // A name of 5 x 63-byte labels (320 bytes on the wire).
    std::vector<std::uint8_t> longName = {0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
    for (int i = 0; i < 5; ++i) {
        longName.push_back(63);
        longName.insert(longName.end(), 63, 'y');
    }
    longName.insert(longName.end(), {0, 0, 1, 0, 1});
    cases.push_back({"name over 255 bytes", longName});
    // A label with a dot in it.
    cases.push_back({"dot inside a label",
                     {0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 3, 'a', '.', 'b', 0, 0, 1, 0, 1}});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, DnsMessageMalformed, testing::ValuesIn(malformedCases()),
                         [](const auto& param) { return "case" + std::to_string(param.index); });

TEST(DnsMessage, OversizedDatagramsAndEntryCountsAreOverTheLimits) {
    std::vector<std::uint8_t> big(kMaxMdnsMessage + 1, 0);
    EXPECT_EQ(parseDnsMessage(big).status(), status::BadEncodingLimitsExceeded);
    std::vector<std::uint8_t> many = {0, 0, 0, 0, 0x10, 0, 0, 0, 0, 0, 0, 0};  // 4096 questions
    EXPECT_EQ(parseDnsMessage(many).status(), status::BadEncodingLimitsExceeded);
}

TEST(DnsMessage, EncoderRefusesWhatCannotBeEncoded) {
    DnsMessage m;
    m.questions.push_back({std::string(64, 'x') + ".local", 1, kClassIn});
    EXPECT_EQ(encodeDnsMessage(m).status(), status::BadEncodingError);
    DnsMessage t;
    DnsRecord txt;
    txt.name = "a.local";
    txt.type = static_cast<std::uint16_t>(DnsType::Txt);
    txt.txt = {std::string(256, 'z')};
    t.records = {txt};
    EXPECT_EQ(encodeDnsMessage(t).status(), status::BadEncodingError);
}

}  // namespace
}  // namespace skillcell::ua::mdns::dns_message_test
