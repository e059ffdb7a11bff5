#pragma once
// DnsMessage: the DNS wire format (RFC 1035, with the mDNS bits of RFC 6762) as far as
// discovery needs it: questions and the record types A, AAAA, PTR, SRV and TXT.
//
// Every datagram that arrives on the mDNS port passes parseDnsMessage() before anything else
// sees it: it is bounds-checked, compression pointers may only point backwards (no loops),
// names and counts are limited. Only a datagram that passes is handed on to libmdnsd, whose
// own parser has no length argument and trusts its input.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ua/types/result.hpp"

namespace skillcell::ua::mdns {

enum class DnsType : std::uint16_t { A = 1, Ptr = 12, Txt = 16, Aaaa = 28, Srv = 33, Any = 255 };

inline constexpr std::uint16_t kClassIn = 1;
/// RFC 6762: the top bit of a question's class asks for a unicast answer; of a record's
/// class it means "cache flush" (this record replaces all earlier ones of its name/type).
inline constexpr std::uint16_t kClassTopBit = 0x8000;
/// Whether a question's or record's class is IN, whatever its top bit says.
[[nodiscard]] constexpr bool isClassIn(std::uint16_t cls) {
    return (cls & ~kClassTopBit) == kClassIn;
}
/// RFC 6762, 17: an mDNS message is at most 9000 bytes.
inline constexpr std::size_t kMaxMdnsMessage = 9000;

struct DnsQuestion {
    std::string name;  // dotted, without the trailing dot, as received (case kept)
    std::uint16_t type = 0;
    std::uint16_t qclass = kClassIn;
};

struct DnsRecord {
    std::string name;
    std::uint16_t type = 0;
    std::uint16_t rrclass = kClassIn;  // with the cache-flush bit
    std::uint32_t ttl = 0;
    // Decoded rdata of the known types; `rdata` keeps the raw bytes of the others.
    std::string target;  // PTR: the instance; SRV: the host
    std::uint16_t priority = 0;
    std::uint16_t weight = 0;
    std::uint16_t port = 0;
    std::vector<std::string> txt;
    std::array<std::uint8_t, 4> ipv4{};
    std::array<std::uint8_t, 16> ipv6{};
    std::vector<std::uint8_t> rdata;

    [[nodiscard]] bool cacheFlush() const { return (rrclass & kClassTopBit) != 0; }
};

struct DnsMessage {
    std::uint16_t id = 0;
    bool isResponse = false;
    /// TC: in a query, more known answers follow in the next datagrams (RFC 6762, 7.2).
    bool truncated = false;
    std::vector<DnsQuestion> questions;
    /// Answers, then authority, then additional records: for discovery they all count.
    std::vector<DnsRecord> records;
    std::size_t answerCount = 0;
};

struct DnsLimits {
    std::size_t maxMessageBytes = kMaxMdnsMessage;
    std::size_t maxEntries = 256;  // questions + records
};

/// Parses one datagram. BadDecodingError (with `error` naming the fault, if given) for
/// anything malformed: truncation, a pointer that does not point backwards, a label over 63
/// bytes or a name over 255, rdata that does not fill its rdlength exactly, trailing bytes.
/// BadEncodingLimitsExceeded when the datagram or its entry count is over the limits.
[[nodiscard]] Result<DnsMessage> parseDnsMessage(std::span<const std::uint8_t> bytes,
                                                 std::string* error = nullptr,
                                                 DnsLimits limits = {});

/// Encodes a message without name compression (questions, then every record as an answer).
/// BadEncodingError for a name or TXT string that cannot be encoded.
[[nodiscard]] Result<std::vector<std::uint8_t>> encodeDnsMessage(const DnsMessage& message);

/// ASCII-lowercase copy: DNS names compare case-insensitively.
[[nodiscard]] std::string foldCase(std::string_view name);

}  // namespace skillcell::ua::mdns
