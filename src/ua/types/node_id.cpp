#include "ua/types/node_id.hpp"

#include <array>
#include <charconv>
#include <cstdio>

namespace skillcell::ua {
namespace {

constexpr std::string_view kBase64 =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64Encode(const std::vector<std::uint8_t>& in) {
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < in.size(); i += 3) {
        std::uint32_t v = static_cast<std::uint32_t>(in[i]) << 16;
        if (i + 1 < in.size()) v |= static_cast<std::uint32_t>(in[i + 1]) << 8;
        if (i + 2 < in.size()) v |= in[i + 2];
        out += kBase64[(v >> 18) & 63];
        out += kBase64[(v >> 12) & 63];
        out += i + 1 < in.size() ? kBase64[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? kBase64[v & 63] : '=';
    }
    return out;
}

std::optional<std::vector<std::uint8_t>> base64Decode(std::string_view in) {
    std::vector<std::uint8_t> out;
    std::uint32_t acc = 0;
    int bits = 0;
    for (char c : in) {
        if (c == '=') break;
        const auto pos = kBase64.find(c);
        if (pos == std::string_view::npos) return std::nullopt;
        acc = (acc << 6) | static_cast<std::uint32_t>(pos);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xFF));
        }
    }
    return out;
}

std::string guidToString(const Guid& g) {
    std::array<char, 40> buf{};
    std::snprintf(buf.data(), buf.size(), "%08X-%04X-%04X-%02X%02X-%02X%02X%02X%02X%02X%02X",
                  g.data1, g.data2, g.data3, g.data4[0], g.data4[1], g.data4[2], g.data4[3],
                  g.data4[4], g.data4[5], g.data4[6], g.data4[7]);
    return buf.data();
}

template <class Int>
std::optional<Int> parseHex(std::string_view s) {
    Int v{};
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
    if (ec != std::errc{} || p != s.data() + s.size()) return std::nullopt;
    return v;
}

std::optional<Guid> parseGuid(std::string_view s) {
    // 8-4-4-4-12 hex digits
    if (s.size() != 36 || s[8] != '-' || s[13] != '-' || s[18] != '-' || s[23] != '-') {
        return std::nullopt;
    }
    Guid g;
    auto d1 = parseHex<std::uint32_t>(s.substr(0, 8));
    auto d2 = parseHex<std::uint16_t>(s.substr(9, 4));
    auto d3 = parseHex<std::uint16_t>(s.substr(14, 4));
    if (!d1 || !d2 || !d3) return std::nullopt;
    g.data1 = *d1;
    g.data2 = *d2;
    g.data3 = *d3;
    const std::string tail = std::string(s.substr(19, 4)) + std::string(s.substr(24, 12));
    for (std::size_t i = 0; i < 8; ++i) {
        auto b = parseHex<std::uint8_t>(std::string_view(tail).substr(i * 2, 2));
        if (!b) return std::nullopt;
        g.data4[i] = *b;
    }
    return g;
}

}  // namespace

std::string NodeId::toString() const {
    std::string out;
    if (ns_ != 0) out = "ns=" + std::to_string(ns_) + ";";
    switch (idType()) {
        case IdType::Numeric:
            return out + "i=" + std::to_string(numeric());
        case IdType::Text:
            return out + "s=" + std::get<String>(id_);
        case IdType::Uuid:
            return out + "g=" + guidToString(std::get<Guid>(id_));
        case IdType::Opaque:
            return out + "b=" + base64Encode(std::get<ByteString>(id_).bytes);
    }
    return out;
}

std::optional<NodeId> NodeId::parse(std::string_view text) {
    std::uint16_t ns = 0;
    if (text.starts_with("ns=")) {
        const auto semi = text.find(';');
        if (semi == std::string_view::npos) return std::nullopt;
        auto [p, ec] = std::from_chars(text.data() + 3, text.data() + semi, ns);
        if (ec != std::errc{} || p != text.data() + semi) return std::nullopt;
        text.remove_prefix(semi + 1);
    }
    if (text.size() < 2 || text[1] != '=') return std::nullopt;
    const char kind = text[0];
    const std::string_view body = text.substr(2);
    switch (kind) {
        case 'i': {
            std::uint32_t v = 0;
            auto [p, ec] = std::from_chars(body.data(), body.data() + body.size(), v);
            if (ec != std::errc{} || p != body.data() + body.size() || body.empty()) {
                return std::nullopt;
            }
            return NodeId(ns, v);
        }
        case 's':
            return NodeId(ns, String(body));
        case 'g': {
            auto g = parseGuid(body);
            if (!g) return std::nullopt;
            return NodeId(ns, *g);
        }
        case 'b': {
            auto b = base64Decode(body);
            if (!b) return std::nullopt;
            return NodeId(ns, ByteString(std::move(*b)));
        }
        default:
            return std::nullopt;
    }
}

std::string ExpandedNodeId::toString() const {
    std::string out;
    if (serverIndex != 0) out += "svr=" + std::to_string(serverIndex) + ";";
    if (!namespaceUri.empty()) out += "nsu=" + namespaceUri + ";";
    return out + nodeId.toString();
}

std::size_t hashValue(const NodeId& id) {
    std::size_t h = std::hash<std::uint16_t>{}(id.namespaceIndex()) * 0x9E3779B97F4A7C15ull;
    std::visit(
        [&h](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::uint32_t>) {
                h ^= std::hash<std::uint32_t>{}(v);
            } else if constexpr (std::is_same_v<T, String>) {
                h ^= std::hash<std::string>{}(v);
            } else if constexpr (std::is_same_v<T, Guid>) {
                h ^= std::hash<std::uint32_t>{}(v.data1) ^ (std::size_t{v.data2} << 20);
            } else {
                h ^= std::hash<std::string_view>{}(std::string_view(
                    reinterpret_cast<const char*>(v.bytes.data()), v.bytes.size()));
            }
        },
        id.identifier());
    return h;
}

}  // namespace skillcell::ua
