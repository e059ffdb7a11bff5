#pragma once
// Small helpers the PKI files share: files, and the optional error text of their functions.
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace skillcell::ua::pki {

/// Writes `bytes` to `path` through a temporary file in the same directory, then a rename:
/// readers see the old file or the new one, never half of one. `mode` applies before the
/// rename, so a private key is never readable by others, not even briefly.
[[nodiscard]] bool writeFileAtomically(const std::filesystem::path& path, std::string_view bytes,
                                       mode_t mode);

/// The whole file; empty when it cannot be read.
[[nodiscard]] std::vector<std::uint8_t> readWholeFile(const std::filesystem::path& path);

/// Fills in a caller's `std::string* error`, when it gave one.
inline void setError(std::string* error, std::string why) {
    if (error != nullptr) *error = std::move(why);
}

}  // namespace skillcell::ua::pki
