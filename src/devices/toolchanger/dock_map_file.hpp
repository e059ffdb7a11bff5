#pragma once
// DockMapFile: where a tool changer took each tool it holds or held, kept on disk, so that a
// restarted changer still knows the dock to put the mounted tool back into (the tool itself
// it reads from the identification pin). A real changer's controller keeps this in its
// non-volatile memory; ours keeps a small JSON file:
//
//   {"docks": {"parallel": [0.3, -0.45, 0.35, 3.14159, 0, 0]},
//    "locking": [0.3, -0.15, 0.35, 3.14159, 0, 0]}
//
// (tool id -> the flange pose at its dock: x, y, z in m, a, b, c in rad). "locking", while
// the coupling closes on a dock's tool, is that dock: a changer killed before it could note
// which tool it took finds it there when it restarts (the pin names the tool, the map does
// not). Written to a
// temporary file, flushed to disk and renamed, so that a crash leaves the old map or the new
// one, never half of one.
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "common/expected.hpp"

namespace skillcell::devices::toolchanger {

struct DockMap {
    std::map<std::string, KDL::Frame> docks;  // tool id -> where the changer took it
    std::optional<KDL::Frame> locking;        // a lock under way at this dock
};

/// The map in `file`; an empty map when there is no file yet. An Error naming the file and
/// what is wrong for one that cannot be read or parsed.
[[nodiscard]] Expected<DockMap> loadDockMap(const std::filesystem::path& file);

/// Replaces `file` with `docks`, atomically; an Error says why not.
[[nodiscard]] Status saveDockMap(const std::filesystem::path& file, const DockMap& docks);

}  // namespace skillcell::devices::toolchanger
