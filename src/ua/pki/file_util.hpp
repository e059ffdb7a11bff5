#pragma once
// Small file helpers the PKI files share.
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace skillcell::ua::pki {

/// Writes `bytes` to `path` through a temporary file in the same directory, then a rename:
/// readers see the old file or the new one, never half of one. `mode` applies before the
/// rename, so a private key is never readable by others, not even briefly.
[[nodiscard]] bool writeFileAtomically(const std::filesystem::path& path, std::string_view bytes,
                                       mode_t mode);

/// The whole file; empty when it cannot be read.
[[nodiscard]] std::vector<std::uint8_t> readWholeFile(const std::filesystem::path& path);

}  // namespace skillcell::ua::pki
