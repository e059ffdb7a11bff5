#pragma once
// SimulatedCell: the paper's work cell as `skillcell device` processes with discovery on (run
// the test in a private network namespace): the world model with the docks and tools of
// examples/cells/paper.toml (the cell file the demo runs), the tool changer with that file's
// tool table, powering the parallel gripper's adapter (a model the test chooses) and the
// Schmalz ECBPi (vacuum), the UR5, and optionally the pick-and-place composite. The changer
// starts before the robot, so it has to find the robot by discovery.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "cell/cell_file.hpp"
#include "cell/device_arguments.hpp"
#include "component_process.hpp"
#include "devices/common/frame.hpp"

namespace skillcell::test {

/// An example cell file (examples/cells/NAME.toml). A file that does not read is a broken
/// test setup: it says why and aborts.
inline cell::CellFile exampleCell(const std::string& name) {
    auto read = cell::readCellFile(std::filesystem::path(SKILLCELL_SOURCE_DIR) / "examples/cells" /
                                   (name + ".toml"));
    if (!read.cell) {
        for (const auto& p : read.problems) std::fprintf(stderr, "%s\n", p.describe().c_str());
        std::abort();
    }
    return *read.cell;
}

/// The paper's cell, read once: a test that changes it changes a copy.
inline const cell::CellFile& paperCell() {
    static const cell::CellFile paper = exampleCell("paper");
    return paper;
}

/// A dock's pose in the devices' syntax: the flange pose at which its tool locks.
inline std::string dockPose(std::string_view name) {
    for (const auto& d : paperCell().docks) {
        if (d.name == name) return cell::poseArgument(d.pose);
    }
    std::fprintf(stderr, "the paper's cell has no dock %s\n", std::string(name).c_str());
    std::abort();
}
inline std::string parallelDock() {
    return dockPose("dockP");
}
inline std::string vacuumDock() {
    return dockPose("dockV");
}

/// The paper's boxes in `device world --object` syntax.
inline std::vector<std::string> paperObjects() {
    std::vector<std::string> out;
    for (const auto& o : paperCell().objects) out.push_back(cell::objectArgument(o));
    return out;
}

/// The application URI an adapter model announces (src/cell/device_arguments.cpp).
inline const char* adapterUri(std::string_view model) {
    return cell::findAdapterModel(model)->applicationUri.data();  // a literal: NUL-terminated
}
inline const char* robotiqUri() {
    return adapterUri("robotiq-2f85");
}
inline const char* schmalzUri() {
    return adapterUri("schmalz-ecbpi");
}

/// The parallel gripper the cell has: either model offers the same skills (issue 6: a
/// gripper is swapped without a change outside its adapter).
struct ParallelGripperModel {
    const char* model;                 // its adapter model, as cell files name it
    std::array<double, 3> gripOffset;  // its grip point from the mounting plate
    [[nodiscard]] const cell::AdapterModel& adapter() const {
        return *cell::findAdapterModel(model);
    }
};
inline constexpr ParallelGripperModel kRobotiq2f85{"robotiq-2f85", {0, 0, 0.15}};
inline constexpr ParallelGripperModel kDhAg95{"dh-ag95", {0, 0, 0.16}};

/// A pose parameter from "X,Y,Z[,A,B,C]".
inline ua::Variant poseValue(const std::string& text) {
    return devices::frameToVariant(devices::toFrame(*devices::parsePose6(text)));
}
inline ua::Variant textValue(const char* text) {
    return ua::Variant(ua::String(text));
}

inline void PrintTo(const ParallelGripperModel& model, std::ostream* out) {
    *out << model.model;
}

struct SimulatedCell {
    /// `objects`: `--object` specs for the world model. `vacuumPowered` false: the changer
    /// has no adapter process for the vacuum gripper (as if its adapter were unplugged).
    /// `robotSpeed`: the UR5's --speed (lower: its motions, and the skills using them, last
    /// longer). `moreWorld`: further arguments of the world model (rails, terminal blocks).
    /// `robotModel`: `skillcell device` of the robot (ur5, iiwa).
    SimulatedCell(const std::string& binary, const std::vector<std::string>& objects,
                  bool withPickAndPlace, ParallelGripperModel parallel = kRobotiq2f85,
                  bool vacuumPowered = true, const std::string& robotSpeed = "50",
                  const std::vector<std::string>& moreWorld = {},
                  const std::string& robotModel = "ur5")
        : parallelUri(parallel.adapter().applicationUri),
          robotName(paperCell().robots.front().name) {
        // The paper's cell with this test's parallel gripper in its dock, and its own boxes.
        cell::CellFile c = paperCell();
        for (auto& tool : c.tools) {
            if (tool.name == "parallel") {
                tool.adapter = parallel.model;
                tool.gripOffset = parallel.gripOffset;
            }
        }
        // A free place beside the cell, to rearrange tools.
        c.docks.push_back({"shelf", {0.0, -0.6, 0.35, 3.141592653589793, 0, 0}});
        c.objects.clear();
        std::vector<std::string> args = {"world"};
        const auto scene = cell::worldArguments(c);
        args.insert(args.end(), scene.begin(), scene.end());
        for (const auto& o : objects) args.insert(args.end(), {"--object", o});
        args.insert(args.end(), moreWorld.begin(), moreWorld.end());
        world = start(binary, std::move(args));
        if (world->url().empty()) return;
        tools = world->pkiDir().string() + "-tools";
        const std::string common = " --port 0 --host 127.0.0.1 --insecure --speed 20 --world " +
                                   world->url() + " --robot " + robotName +
                                   " --mdns-ttl 5 --mdns-query-period 1";
        const auto power = [&](const cell::Tool& tool, const cell::AdapterModel& model) {
            return binary + " device " + std::string(model.command) + " --pki-dir " + tools + "-" +
                   tool.name + " --grip-offset " + cell::vectorArgument(tool.gripOffset) + common;
        };
        std::vector<std::string> changerArgs = {
            "toolchanger", "--world",    world->url(),
            "--robot",     robotName,    "--detection-timeout-ms",
            "20000",       "--dock-map", tools + "-docks.json"};
        const auto table = cell::toolTableArguments(c, power);
        for (std::size_t i = 0; i + 1 < table.size(); i += 2) {
            // Without power for the vacuum gripper, as if its adapter were unplugged.
            if (!vacuumPowered && table[i] == "--power" && table[i + 1].rfind("vacuum=", 0) == 0) {
                continue;
            }
            changerArgs.insert(changerArgs.end(), {table[i], table[i + 1]});
        }
        binary_ = binary;
        changerArgs_ = changerArgs;
        changer = start(binary, std::move(changerArgs));
        if (withPickAndPlace) {
            pickplace = start(binary, pickAndPlaceArgs());
        }
        robotArgs_ = {robotModel,   "--speed", robotSpeed, "--world",
                      world->url(), "--robot", robotName};
        robot = start(binary, robotArgs_);
    }
    ~SimulatedCell() {
        // The changer powers the tools off when it stops; then their PKI directories go.
        robot.reset();
        pickplace.reset();
        changer.reset();
        std::error_code ec;
        for (const auto& tool : paperCell().tools)
            std::filesystem::remove_all(tools + "-" + tool.name, ec);
        std::filesystem::remove(tools + "-docks.json", ec);
    }
    SimulatedCell(const SimulatedCell&) = delete;
    SimulatedCell& operator=(const SimulatedCell&) = delete;

    /// The changer's dock map (its --dock-map).
    [[nodiscard]] std::string dockMapFile() const { return tools + "-docks.json"; }
    /// Starts the tool changer again with the same arguments (after a test killed it).
    void restartChanger() {
        changer.reset();
        changer = start(binary_, changerArgs_);
    }

    /// Starts the robot again (after a test killed it).
    void restartRobot() {
        robot.reset();
        robot = start(binary_, robotArgs_);
    }
    /// Starts the pick-and-place composite again (after a test killed it).
    void restartPickAndPlace() {
        pickplace.reset();
        pickplace = start(binary_, pickAndPlaceArgs());
    }

    [[nodiscard]] bool ready() const {
        return !world->url().empty() && changer && !changer->url().empty() && robot &&
               !robot->url().empty() && (!pickplace || !pickplace->url().empty());
    }

    std::unique_ptr<DeviceProcess> world, changer, pickplace, robot;
    std::string tools;        // PKI directories of the powered tools: <tools>-<tool name>
    std::string parallelUri;  // the parallel gripper's application URI
    std::string robotName;    // the world's id of the robot (the paper cell's name for it)

private:
    std::string binary_;
    std::vector<std::string> changerArgs_;
    std::vector<std::string> robotArgs_;

    [[nodiscard]] std::vector<std::string> pickAndPlaceArgs() const {
        return {"pickplace", "--world", world->url(), "--detection-timeout-ms", "5000"};
    }

    static std::unique_ptr<DeviceProcess> start(const std::string& binary,
                                                std::vector<std::string> args) {
        for (const char* a : {"--mdns-ttl", "5", "--mdns-query-period", "1"}) args.emplace_back(a);
        return std::make_unique<DeviceProcess>(binary, std::move(args), true);
    }
};

}  // namespace skillcell::test
