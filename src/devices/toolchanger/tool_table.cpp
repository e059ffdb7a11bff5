#include "devices/toolchanger/tool_table.hpp"

#include <algorithm>
#include <charconv>

namespace skillcell::devices::toolchanger {
namespace {

ua::StatusCode invalid(std::string* why, std::string text) {
    if (why != nullptr) *why = std::move(text);
    return ua::status::BadInvalidArgument;
}

std::optional<double> parseVolts(std::string_view text) {
    double v = 0;
    const auto* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (ec != std::errc() || ptr != end || !(v >= 0 && v <= 100)) return std::nullopt;
    return v;
}

std::vector<std::string> splitBlanks(std::string_view text) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < text.size() && text[j] != ' ' && text[j] != '\t') ++j;
        if (j > i) out.emplace_back(text.substr(i, j - i));
        i = j;
    }
    return out;
}

}  // namespace

ua::StatusCode ToolTable::add(std::string_view spec, std::string* why) {
    const std::string expected =
        "expected ID:MIN-MAX:APPLICATION-URI (volts), got '" + std::string(spec) + "'";
    const auto c1 = spec.find(':');
    const auto c2 = c1 == std::string_view::npos ? c1 : spec.find(':', c1 + 1);
    if (c2 == std::string_view::npos) return invalid(why, expected);
    const std::string_view band = spec.substr(c1 + 1, c2 - c1 - 1);
    const auto dash = band.find('-');
    if (dash == std::string_view::npos) return invalid(why, expected);
    const auto lo = parseVolts(band.substr(0, dash));
    const auto hi = parseVolts(band.substr(dash + 1));
    if (!lo || !hi) return invalid(why, expected);
    ToolEntry entry;
    entry.id = std::string(spec.substr(0, c1));
    entry.minVolts = *lo;
    entry.maxVolts = *hi;
    entry.applicationUri = std::string(spec.substr(c2 + 1));
    return add(std::move(entry), why);
}

ua::StatusCode ToolTable::add(ToolEntry entry, std::string* why) {
    if (entry.id.empty() || entry.applicationUri.empty()) {
        return invalid(why, "a tool needs an id and an application URI");
    }
    if (!(entry.minVolts < entry.maxVolts) || entry.minVolts < kNoToolVolts) {
        return invalid(why, "tool " + entry.id + ": its band must be MIN < MAX, above " +
                                std::to_string(kNoToolVolts) + " V (no tool)");
    }
    for (const auto& e : entries_) {
        if (e.id == entry.id || e.applicationUri == entry.applicationUri) {
            return invalid(why,
                           "tool " + entry.id + ": id or application URI already used by " + e.id);
        }
        if (entry.minVolts <= e.maxVolts && e.minVolts <= entry.maxVolts) {
            return invalid(why, "tool " + entry.id + ": its band overlaps that of " + e.id);
        }
    }
    entries_.push_back(std::move(entry));
    return ua::status::Good;
}

ua::StatusCode ToolTable::setPowerCommand(std::string_view spec, std::string* why) {
    const auto eq = spec.find('=');
    if (eq == std::string_view::npos) {
        return invalid(why, "expected ID=PROGRAM [ARG...], got '" + std::string(spec) + "'");
    }
    const std::string id(spec.substr(0, eq));
    auto it = std::find_if(entries_.begin(), entries_.end(),
                           [&](const ToolEntry& e) { return e.id == id; });
    if (it == entries_.end()) return invalid(why, "--power " + id + ": no such tool (--tool)");
    auto argv = splitBlanks(spec.substr(eq + 1));
    if (argv.empty()) return invalid(why, "--power " + id + ": no program");
    it->powerCommand = std::move(argv);
    return ua::status::Good;
}

PinReading ToolTable::identify(double volts) const {
    if (volts < kNoToolVolts) return {PinReading::Kind::NoTool, nullptr};
    for (const auto& e : entries_) {
        if (volts >= e.minVolts && volts <= e.maxVolts) return {PinReading::Kind::Tool, &e};
    }
    return {PinReading::Kind::Fault, nullptr};
}

const ToolEntry* ToolTable::byId(std::string_view id) const {
    for (const auto& e : entries_) {
        if (e.id == id) return &e;
    }
    return nullptr;
}

const ToolEntry* ToolTable::byApplicationUri(std::string_view uri) const {
    for (const auto& e : entries_) {
        if (e.applicationUri == uri) return &e;
    }
    return nullptr;
}

}  // namespace skillcell::devices::toolchanger
