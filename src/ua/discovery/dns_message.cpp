#include "ua/discovery/dns_message.hpp"

#include <algorithm>

namespace skillcell::ua::mdns {

namespace {

constexpr std::size_t kHeaderBytes = 12;
constexpr std::size_t kMaxLabel = 63;
constexpr std::size_t kMaxName = 255;  // wire length, RFC 1035 2.3.4

class Parser {
public:
    Parser(std::span<const std::uint8_t> bytes, std::string* error)
        : bytes_(bytes), error_(error) {}

    bool fail(const char* what) {
        if (ok_ && error_ != nullptr)
            *error_ = std::string(what) + " at byte " + std::to_string(pos_);
        ok_ = false;
        return false;
    }
    [[nodiscard]] bool ok() const { return ok_; }
    [[nodiscard]] std::size_t pos() const { return pos_; }
    [[nodiscard]] std::size_t remaining() const { return bytes_.size() - pos_; }

    bool u8(std::uint8_t& v) {
        if (remaining() < 1) return fail("truncated");
        v = bytes_[pos_++];
        return true;
    }
    bool u16(std::uint16_t& v) {
        if (remaining() < 2) return fail("truncated");
        v = static_cast<std::uint16_t>((bytes_[pos_] << 8) | bytes_[pos_ + 1]);
        pos_ += 2;
        return true;
    }
    bool u32(std::uint32_t& v) {
        if (remaining() < 4) return fail("truncated");
        v = (std::uint32_t{bytes_[pos_]} << 24) | (std::uint32_t{bytes_[pos_ + 1]} << 16) |
            (std::uint32_t{bytes_[pos_ + 2]} << 8) | std::uint32_t{bytes_[pos_ + 3]};
        pos_ += 4;
        return true;
    }
    bool raw(std::size_t n, std::span<const std::uint8_t>& out) {
        if (remaining() < n) return fail("truncated");
        out = bytes_.subspan(pos_, n);
        pos_ += n;
        return true;
    }

    /// A possibly compressed name. A pointer must point strictly before the start of the
    /// label sequence that contains it, so that following pointers always moves backwards
    /// and ends.
    bool name(std::string& out) {
        out.clear();
        std::size_t cursor = pos_;
        std::size_t limit = pos_;  // pointers must go below this
        bool jumped = false;
        std::size_t wireLength = 1;
        for (;;) {
            if (cursor >= bytes_.size()) return fail("truncated name");
            const std::uint8_t len = bytes_[cursor];
            if ((len & 0xC0) == 0xC0) {
                if (cursor + 1 >= bytes_.size()) return fail("truncated name pointer");
                const std::size_t target = ((len & 0x3F) << 8) | bytes_[cursor + 1];
                if (target >= limit) return fail("name pointer does not point backwards");
                if (!jumped) pos_ = cursor + 2;
                jumped = true;
                limit = target;
                cursor = target;
                continue;
            }
            if ((len & 0xC0) != 0) return fail("reserved label type");
            if (len == 0) {
                if (!jumped) pos_ = cursor + 1;
                return true;
            }
            if (len > kMaxLabel) return fail("label longer than 63 bytes");
            if (cursor + 1 + len > bytes_.size()) return fail("truncated label");
            wireLength += 1 + len;
            if (wireLength > kMaxName) return fail("name longer than 255 bytes");
            if (!out.empty()) out.push_back('.');
            for (std::size_t i = 0; i < len; ++i) {
                const auto c = static_cast<char>(bytes_[cursor + 1 + i]);
                // A dot inside a label could not be told from a separator in the dotted
                // form that names travel in here (and in libmdnsd): refuse it.
                if (c == '.' || c == '\0') return fail("label with a dot or NUL byte");
                out.push_back(c);
            }
            cursor += 1 + len;
        }
    }

private:
    std::span<const std::uint8_t> bytes_;
    std::string* error_;
    std::size_t pos_ = 0;
    bool ok_ = true;
};

bool parseRdata(Parser& p, DnsRecord& rr, std::uint16_t rdlength) {
    const std::size_t end = p.pos() + rdlength;
    if (p.remaining() < rdlength) return p.fail("rdata longer than the message");
    std::span<const std::uint8_t> raw;
    switch (static_cast<DnsType>(rr.type)) {
        case DnsType::A:
            if (rdlength != 4) return p.fail("A record rdata is not 4 bytes");
            if (!p.raw(4, raw)) return false;
            std::copy(raw.begin(), raw.end(), rr.ipv4.begin());
            return true;
        case DnsType::Aaaa:
            if (rdlength != 16) return p.fail("AAAA record rdata is not 16 bytes");
            if (!p.raw(16, raw)) return false;
            std::copy(raw.begin(), raw.end(), rr.ipv6.begin());
            return true;
        case DnsType::Ptr:
            if (!p.name(rr.target)) return false;
            break;
        case DnsType::Srv:
            if (!p.u16(rr.priority) || !p.u16(rr.weight) || !p.u16(rr.port)) return false;
            if (!p.name(rr.target)) return false;
            break;
        case DnsType::Txt: {
            while (p.pos() < end) {
                std::uint8_t len = 0;
                if (!p.u8(len)) return false;
                if (p.pos() + len > end) return p.fail("TXT string overruns its rdata");
                if (!p.raw(len, raw)) return false;
                rr.txt.emplace_back(raw.begin(), raw.end());
            }
            break;
        }
        case DnsType::Any:
        default:
            if (!p.raw(rdlength, raw)) return false;
            rr.rdata.assign(raw.begin(), raw.end());
            break;
    }
    if (p.pos() != end) return p.fail("rdata does not match its rdlength");
    return true;
}

void putU16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    out.push_back(static_cast<std::uint8_t>(v));
}

void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    putU16(out, static_cast<std::uint16_t>(v >> 16));
    putU16(out, static_cast<std::uint16_t>(v));
}

bool putName(std::vector<std::uint8_t>& out, std::string_view name) {
    std::size_t wire = 1;
    while (!name.empty()) {
        const auto dot = name.find('.');
        const std::string_view label = name.substr(0, dot);
        if (label.empty() || label.size() > kMaxLabel) return false;
        wire += 1 + label.size();
        if (wire > kMaxName) return false;
        out.push_back(static_cast<std::uint8_t>(label.size()));
        out.insert(out.end(), label.begin(), label.end());
        name = dot == std::string_view::npos ? std::string_view{} : name.substr(dot + 1);
    }
    out.push_back(0);
    return true;
}

}  // namespace

std::string foldCase(std::string_view name) {
    std::string out(name);
    std::transform(out.begin(), out.end(), out.begin(), [](char c) {
        return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
    });
    return out;
}

Result<DnsMessage> parseDnsMessage(std::span<const std::uint8_t> bytes, std::string* error,
                                   DnsLimits limits) {
    if (bytes.size() > limits.maxMessageBytes) {
        if (error != nullptr) *error = "message of " + std::to_string(bytes.size()) + " bytes";
        return status::BadEncodingLimitsExceeded;
    }
    Parser p(bytes, error);
    DnsMessage m;
    std::uint16_t flags = 0;
    std::uint16_t counts[4] = {};
    if (bytes.size() < kHeaderBytes) {
        p.fail("shorter than a DNS header");
        return status::BadDecodingError;
    }
    (void)p.u16(m.id);
    (void)p.u16(flags);
    for (auto& c : counts) (void)p.u16(c);
    m.isResponse = (flags & 0x8000) != 0;
    m.truncated = (flags & 0x0200) != 0;
    if (((flags >> 11) & 0xF) != 0) {  // RFC 6762 18.3: other opcodes are silently ignored
        p.fail("opcode is not QUERY");
        return status::BadDecodingError;
    }
    const std::size_t entries = std::size_t{counts[0]} + counts[1] + counts[2] + counts[3];
    if (entries > limits.maxEntries) {
        if (error != nullptr) *error = std::to_string(entries) + " entries";
        return status::BadEncodingLimitsExceeded;
    }
    // Every question takes at least 5 bytes and every record at least 11: a count that
    // cannot fit is refused before anything is reserved for it.
    if (std::size_t{counts[0]} * 5 + (entries - counts[0]) * 11 > p.remaining()) {
        p.fail("counts larger than the message");
        return status::BadDecodingError;
    }
    m.questions.resize(counts[0]);
    for (auto& q : m.questions) {
        if (!p.name(q.name) || !p.u16(q.type) || !p.u16(q.qclass)) return status::BadDecodingError;
    }
    m.answerCount = counts[1];
    m.records.resize(entries - counts[0]);
    for (auto& rr : m.records) {
        std::uint16_t rdlength = 0;
        if (!p.name(rr.name) || !p.u16(rr.type) || !p.u16(rr.rrclass) || !p.u32(rr.ttl) ||
            !p.u16(rdlength) || !parseRdata(p, rr, rdlength)) {
            return status::BadDecodingError;
        }
    }
    if (p.remaining() != 0) {
        p.fail("trailing bytes");
        return status::BadDecodingError;
    }
    return m;
}

Result<std::vector<std::uint8_t>> encodeDnsMessage(const DnsMessage& message) {
    std::vector<std::uint8_t> out;
    putU16(out, message.id);
    // A response: QR + AA; TC when more known answers follow.
    putU16(out, static_cast<std::uint16_t>((message.isResponse ? 0x8400 : 0) |
                                           (message.truncated ? 0x0200 : 0)));
    putU16(out, static_cast<std::uint16_t>(message.questions.size()));
    putU16(out, static_cast<std::uint16_t>(message.records.size()));
    putU16(out, 0);
    putU16(out, 0);
    for (const auto& q : message.questions) {
        if (!putName(out, q.name)) return status::BadEncodingError;
        putU16(out, q.type);
        putU16(out, q.qclass);
    }
    for (const auto& rr : message.records) {
        if (!putName(out, rr.name)) return status::BadEncodingError;
        putU16(out, rr.type);
        putU16(out, rr.rrclass);
        putU32(out, rr.ttl);
        const std::size_t lengthAt = out.size();
        putU16(out, 0);
        switch (static_cast<DnsType>(rr.type)) {
            case DnsType::A:
                out.insert(out.end(), rr.ipv4.begin(), rr.ipv4.end());
                break;
            case DnsType::Aaaa:
                out.insert(out.end(), rr.ipv6.begin(), rr.ipv6.end());
                break;
            case DnsType::Ptr:
                if (!putName(out, rr.target)) return status::BadEncodingError;
                break;
            case DnsType::Srv:
                putU16(out, rr.priority);
                putU16(out, rr.weight);
                putU16(out, rr.port);
                if (!putName(out, rr.target)) return status::BadEncodingError;
                break;
            case DnsType::Txt:
                for (const auto& s : rr.txt) {
                    if (s.size() > 255) return status::BadEncodingError;
                    out.push_back(static_cast<std::uint8_t>(s.size()));
                    out.insert(out.end(), s.begin(), s.end());
                }
                break;
            case DnsType::Any:
            default:
                out.insert(out.end(), rr.rdata.begin(), rr.rdata.end());
                break;
        }
        const std::size_t rdlength = out.size() - lengthAt - 2;
        if (rdlength > 0xFFFF) return status::BadEncodingError;
        out[lengthAt] = static_cast<std::uint8_t>(rdlength >> 8);
        out[lengthAt + 1] = static_cast<std::uint8_t>(rdlength);
    }
    return out;
}

}  // namespace skillcell::ua::mdns
