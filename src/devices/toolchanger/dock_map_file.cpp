#include "devices/toolchanger/dock_map_file.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "common/atomic_file.hpp"
#include "devices/common/frame.hpp"

namespace skillcell::devices::toolchanger {

namespace {

std::optional<KDL::Frame> frameOf(const nlohmann::json& pose) {
    if (!pose.is_array() || pose.size() != 6 ||
        !std::all_of(pose.begin(), pose.end(), [](const auto& v) { return v.is_number(); })) {
        return std::nullopt;
    }
    return toFrame(Pose6{pose[0].get<double>(), pose[1].get<double>(), pose[2].get<double>(),
                         pose[3].get<double>(), pose[4].get<double>(), pose[5].get<double>()});
}

nlohmann::json arrayOf(const KDL::Frame& frame) {
    const Pose6 p = toPose6(frame);
    return {p.x, p.y, p.z, p.a, p.b, p.c};
}

}  // namespace

Expected<DockMap> loadDockMap(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return DockMap{};
    std::ifstream in(file);
    if (!in) return Error{"cannot read " + file.string()};
    const auto json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (json.is_discarded() || !json.is_object() || !json.contains("docks") ||
        !json["docks"].is_object()) {
        return Error{file.string() + ": not a dock map ({\"docks\": {TOOL: [x, y, z, a, b, c]}})"};
    }
    DockMap map;
    for (const auto& [tool, pose] : json["docks"].items()) {
        const auto frame = frameOf(pose);
        if (!frame) {
            return Error{file.string() + ": tool '" + tool + "': expected [x, y, z, a, b, c]"};
        }
        map.docks.emplace(tool, *frame);
    }
    if (const auto locking = json.find("locking"); locking != json.end()) {
        map.locking = frameOf(*locking);
        if (!map.locking) return Error{file.string() + ": locking: expected [x, y, z, a, b, c]"};
    }
    return map;
}

Status saveDockMap(const std::filesystem::path& file, const DockMap& map) {
    nlohmann::json json;
    json["docks"] = nlohmann::json::object();
    for (const auto& [tool, frame] : map.docks) json["docks"][tool] = arrayOf(frame);
    if (map.locking) json["locking"] = arrayOf(*map.locking);
    if (!writeFileAtomically(file, json.dump() + "\n")) {
        return Error{"cannot replace " + file.string()};
    }
    return Done{};
}

}  // namespace skillcell::devices::toolchanger
