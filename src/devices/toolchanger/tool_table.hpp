#pragma once
// ToolTable: the tools a Kelvin tool changer knows. Each tool carries a coding resistor that
// puts a voltage on the changer's identification pin; the changer reads it with an ADC and
// finds the tool by the band the voltage falls in. No tool: the pin is near 0 V. A voltage
// between bands (a bad contact, a tool the table does not know) is a fault, never a guess.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ua/types/result.hpp"

namespace skillcell::devices::toolchanger {

/// Below this the pin reads "no tool".
inline constexpr double kNoToolVolts = 0.2;

struct ToolEntry {
    std::string id;       // the tool's id in the world model ("parallel-gripper")
    double minVolts = 0;  // its band on the identification pin
    double maxVolts = 0;
    std::string applicationUri;  // the application URI its adapter announces
    /// The adapter process the changer powers up when the tool is attached (argv; empty:
    /// the tool has no electronics to power).
    std::vector<std::string> powerCommand;

    [[nodiscard]] double nominalVolts() const { return (minVolts + maxVolts) / 2; }
};

/// What the identification pin says.
struct PinReading {
    enum class Kind : std::uint8_t { NoTool, Tool, Fault };
    Kind kind = Kind::NoTool;
    const ToolEntry* tool = nullptr;  // for Tool
};

class ToolTable {
public:
    /// Adds "ID:MIN-MAX:APPLICATION-URI" (volts; the URI may contain colons). BadInvalidArgument
    /// (with `why`) for bad syntax, a band that is empty, starts below kNoToolVolts or overlaps
    /// another, or an id or URI already in the table.
    ua::StatusCode add(std::string_view spec, std::string* why = nullptr);
    ua::StatusCode add(ToolEntry entry, std::string* why = nullptr);
    /// Sets the power command of a tool from "ID=PROGRAM ARG..." (split at blanks).
    ua::StatusCode setPowerCommand(std::string_view spec, std::string* why = nullptr);

    [[nodiscard]] PinReading identify(double volts) const;
    [[nodiscard]] const ToolEntry* byId(std::string_view id) const;
    [[nodiscard]] const ToolEntry* byApplicationUri(std::string_view uri) const;
    [[nodiscard]] const std::vector<ToolEntry>& entries() const { return entries_; }

private:
    std::vector<ToolEntry> entries_;
};

}  // namespace skillcell::devices::toolchanger
