#pragma once
// Human-readable text of values, for logs and command-line output (not an encoding).
#include <string>
#include <string_view>

#include "ua/types/variant.hpp"

namespace skillcell::ua {

[[nodiscard]] std::string toString(const Variant& v);
[[nodiscard]] std::string toString(const Scalar& s);
/// A JSON string literal of `s` for machine-readable output (`--json`): quotes, backslashes
/// and control characters escaped; other bytes (UTF-8 from a server) pass through.
[[nodiscard]] std::string jsonQuoted(std::string_view s);

}  // namespace skillcell::ua
