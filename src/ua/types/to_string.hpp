#pragma once
// Human-readable text of values, for logs and command-line output (not an encoding).
#include <string>
#include <string_view>

#include "ua/types/variant.hpp"

namespace skillcell::ua {

[[nodiscard]] std::string toString(const Variant& v);
[[nodiscard]] std::string toString(const Scalar& s);
}  // namespace skillcell::ua
