#pragma once
// Replacing a file so that whoever reads it, or starts from it after a crash, finds the old
// contents or the new ones, never half of them: the bytes go to a temporary file beside it,
// which is then renamed over it. One helper for every file the components keep: keys and
// certificates, users, a tool changer's dock map, the world's state.
#include <sys/types.h>

#include <filesystem>
#include <string_view>

namespace skillcell {

/// How far the bytes must have gone before the rename.
enum class Flush : bool {
    ToDisk,    // fsync first: the file survives a power cut (keys, users, the dock map)
    ToKernel,  // written: it survives the process being killed (state rewritten many times a
               // second, such as the world's)
};

/// Writes `bytes` to `path` through a temporary file in the same directory, then a rename.
/// `mode` applies before the rename, so a private key is never readable by others, not even
/// briefly. False when it could not (the temporary file is removed).
[[nodiscard]] bool writeFileAtomically(const std::filesystem::path& path, std::string_view bytes,
                                       mode_t mode = 0644, Flush flush = Flush::ToDisk);

}  // namespace skillcell
