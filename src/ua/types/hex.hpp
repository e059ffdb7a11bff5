#pragma once
// Hexadecimal text of bytes: thumbprints, salts and hashes in files an operator reads.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace skillcell::ua {

/// Lower-case hex, two digits per byte.
[[nodiscard]] std::string toHex(std::span<const std::uint8_t> bytes);
/// The bytes of hex text (either case); nothing for an odd length or a non-hex digit.
[[nodiscard]] std::optional<std::vector<std::uint8_t>> fromHex(std::string_view hex);

}  // namespace skillcell::ua
