#pragma once
// The application URI each kind of component announces unless told otherwise: said once
// here, for the commands that start them (`skillcell lds`, `kb`, `mes`, `device ...`) and for
// `cell up` and the demo, which commission their certificates before they start.
#include <string>
#include <string_view>

namespace skillcell::cell {

inline constexpr std::string_view kLdsUri = "urn:skillcell:lds";
inline constexpr std::string_view kKbUri = "urn:skillcell:kb";
inline constexpr std::string_view kMesUri = "urn:skillcell:mes";
inline constexpr std::string_view kDashboardUri = "urn:skillcell:dashboard";
inline constexpr std::string_view kWorldUri = "urn:skillcell:device:world";
inline constexpr std::string_view kUr5Uri = "urn:skillcell:device:ur5";
inline constexpr std::string_view kIiwaUri = "urn:skillcell:device:lbr-iiwa7";
inline constexpr std::string_view kToolChangerUri = "urn:skillcell:device:kelvin-toolchanger";
inline constexpr std::string_view kPickAndPlaceUri = "urn:skillcell:device:pick-and-place";

/// The URI of a component named `name` in a cell file whose kind announces `kindUri`: the
/// kind's own when the name is the kind's default ("ur5", "toolchanger"), else the kind's
/// with ":<name>" added, so that two robots of one model differ.
[[nodiscard]] inline std::string componentUri(std::string_view kindUri, std::string_view name,
                                              std::string_view defaultName) {
    std::string uri(kindUri);
    if (name != defaultName) uri += ":" + std::string(name);
    return uri;
}

}  // namespace skillcell::cell
