#pragma once
// From a cell file to the command lines of its simulated devices (`skillcell device ...`):
// the world model's scene, the tool changer's tool table and the adapters it powers. The cell
// file says each thing once; these functions say it in each device's option syntax.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "cell/cell_file.hpp"

namespace skillcell::cell {

/// A gripper model that a tool's adapter may be.
struct AdapterModel {
    std::string_view name;            // in cell files: robotiq-2f85
    std::string_view command;         // `skillcell device <command>`: robotiq
    std::string_view applicationUri;  // what its adapter announces
    std::string_view gripType;        // how it grips: "parallel" or "vacuum" (its GripPointType)
};

/// Every adapter model, in the order `skillcell device --help` lists them.
[[nodiscard]] const std::vector<AdapterModel>& adapterModelTable();
/// The model of that name, or nullptr.
[[nodiscard]] const AdapterModel* findAdapterModel(std::string_view name);

/// The component a tool's adapter is when tool changer `changer` powers it: its name (its
/// PKI directory and log) and application URI. The adapters of the changer with the default
/// name ("toolchanger") are the models' own (robotiq, urn:skillcell:device:robotiq-2f85);
/// another changer's have its name added (robotiq-left, ...:robotiq-2f85:left), so that two
/// changers may power grippers of one model.
struct AdapterComponent {
    std::string name;
    std::string applicationUri;
};
[[nodiscard]] AdapterComponent adapterComponent(const AdapterModel& model,
                                                std::string_view changer);

/// "x,y,z" when the orientation is zero, else "x,y,z,a,b,c": the devices' pose syntax, with
/// every digit a double needs to read back the same.
[[nodiscard]] std::string poseArgument(const Pose& pose);
/// "x,y,z".
[[nodiscard]] std::string vectorArgument(const std::array<double, 3>& v);

/// A box in `device world --object` syntax: ID:SX,SY,SZ@POSE.
[[nodiscard]] std::string objectArgument(const WorldObject& object);

/// `device world` options for the cell's scene: --robot ID@BASE for each robot, --dock ID@POSE
/// for each dock, --tool
/// ID:DOCK@GRIP-OFFSET for each tool, --object ID:SX,SY,SZ@POSE for each object.
[[nodiscard]] std::vector<std::string> worldArguments(const CellFile& cell);

/// The program and arguments that power a tool's adapter (the tool changer splits it at
/// blanks): given by whoever starts the cell, who knows the binary, the world's endpoint and
/// the security options.
using PowerCommand = std::function<std::string(const Tool&, const AdapterModel&)>;

/// `device toolchanger` options for the tools of the changer `changer` (empty: every tool of
/// the cell): --tool ID:MIN-MAX:APPLICATION-URI and --power ID=COMMAND for each.
[[nodiscard]] std::vector<std::string> toolTableArguments(const CellFile& cell,
                                                          const PowerCommand& power,
                                                          const std::string& changer = {});

}  // namespace skillcell::cell
