#pragma once
// The simple built-in types of OPC 10000-6, 5.1.2, as small regular value types.
//
// Null versus empty: OPC UA distinguishes a null String/ByteString/array (length -1) from an
// empty one (length 0). skillcell decodes both to an empty value and encodes empty as null
// (-1): no service this stack implements gives the two different meanings, and it keeps
// every string a plain std::string.
#include <array>
#include <chrono>
#include <compare>
#include <cstdint>
#include <string>
#include <vector>

namespace skillcell::ua {

using String = std::string;

struct ByteString {
    std::vector<std::uint8_t> bytes;

    ByteString() = default;
    explicit ByteString(std::vector<std::uint8_t> b) : bytes(std::move(b)) {}
    [[nodiscard]] bool empty() const { return bytes.empty(); }
    [[nodiscard]] std::size_t size() const { return bytes.size(); }
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the literal 0 of the defaulted <=>
    friend auto operator<=>(const ByteString&, const ByteString&) = default;
};

struct XmlElement {
    std::string xml;
    friend auto operator<=>(const XmlElement&, const XmlElement&) = default;
};

struct Guid {
    std::uint32_t data1 = 0;
    std::uint16_t data2 = 0;
    std::uint16_t data3 = 0;
    std::array<std::uint8_t, 8> data4{};
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the literal 0 of the defaulted <=>
    friend auto operator<=>(const Guid&, const Guid&) = default;
};

/// 100-nanosecond intervals since 1601-01-01 UTC (OPC 10000-6, 5.2.2.5).
struct DateTime {
    std::int64_t ticks = 0;

    static constexpr std::int64_t kUnixEpochTicks = 116444736000000000LL;
    [[nodiscard]] static DateTime now();
    [[nodiscard]] static DateTime fromUnixNanoseconds(std::int64_t ns) {
        return DateTime{kUnixEpochTicks + ns / 100};
    }
    [[nodiscard]] std::int64_t unixNanoseconds() const { return (ticks - kUnixEpochTicks) * 100; }
    /// ISO 8601 in UTC, e.g. "2026-11-22T11:23:25.123Z".
    [[nodiscard]] std::string toIso8601() const;
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the literal 0 of the defaulted <=>
    friend auto operator<=>(const DateTime&, const DateTime&) = default;
};

struct QualifiedName {
    std::uint16_t namespaceIndex = 0;
    String name;
    friend auto operator<=>(const QualifiedName&, const QualifiedName&) = default;
};

struct LocalizedText {
    String locale;
    String text;
    friend auto operator<=>(const LocalizedText&, const LocalizedText&) = default;
};

}  // namespace skillcell::ua
