#pragma once
// Small helpers the PKI files share: files, and the optional error text of their functions.
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/atomic_file.hpp"  // writeFileAtomically, for the keys and certificates

namespace skillcell::ua::pki {

/// The whole file; empty when it cannot be read.
[[nodiscard]] std::vector<std::uint8_t> readWholeFile(const std::filesystem::path& path);

/// Fills in a caller's `std::string* error`, when it gave one.
inline void setError(std::string* error, std::string why) {
    if (error != nullptr) *error = std::move(why);
}

}  // namespace skillcell::ua::pki
