#pragma once
// SimulatedCell: the paper's work cell as `skillcell device` processes with discovery on (run
// the test in a private network namespace): the world model with two tool docks, the tool
// changer powering the Robotiq 2F-85 (parallel) and Schmalz ECBPi (vacuum) adapters, the
// UR5, and optionally the pick-and-place composite. The changer starts before the robot, so
// it has to find the robot by discovery.
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "component_process.hpp"
#include "devices/common/frame.hpp"

namespace skillcell::test {

inline constexpr const char* kRobotiqUri = "urn:skillcell:device:robotiq-2f85";
inline constexpr const char* kSchmalzUri = "urn:skillcell:device:schmalz-ecbpi";
// The flange poses (tool down) at which the docks' tools lock.
inline constexpr const char* kParallelDock = "0.3,-0.45,0.35,3.141592653589793,0,0";
inline constexpr const char* kVacuumDock = "0.45,-0.3,0.35,3.141592653589793,0,0";

/// The parallel gripper the cell has: either model offers the same skills (issue 6: a
/// gripper is swapped without a change outside its adapter).
struct ParallelGripperModel {
    const char* command;         // `skillcell device <command>`
    const char* applicationUri;  // what its adapter announces
    const char* gripOffset;      // its grip point from the mounting plate
};
inline constexpr ParallelGripperModel kRobotiq2f85{"robotiq", kRobotiqUri, "0,0,0.15"};
inline constexpr ParallelGripperModel kDhAg95{"ag95", "urn:skillcell:device:dh-ag95", "0,0,0.16"};

/// A pose parameter from "X,Y,Z[,A,B,C]".
inline ua::Variant poseValue(const char* text) {
    return devices::frameToVariant(devices::toFrame(*devices::parsePose6(text)));
}
inline ua::Variant textValue(const char* text) {
    return ua::Variant(ua::String(text));
}

inline void PrintTo(const ParallelGripperModel& model, std::ostream* out) {
    *out << model.command;
}

struct SimulatedCell {
    /// `objects`: `--object` specs for the world model. `vacuumPowered` false: the changer
    /// has no adapter process for the vacuum gripper (as if its adapter were unplugged).
    /// `robotSpeed`: the UR5's --speed (lower: its motions, and the skills using them, last
    /// longer).
    SimulatedCell(const std::string& binary, const std::vector<std::string>& objects,
                  bool withPickAndPlace, ParallelGripperModel parallel = kRobotiq2f85,
                  bool vacuumPowered = true, const std::string& robotSpeed = "50")
        : parallelUri(parallel.applicationUri) {
        std::vector<std::string> args = {"world", "--dock", std::string("dockP@") + kParallelDock,
                                         "--dock", std::string("dockV@") + kVacuumDock, "--tool",
                                         std::string("parallel:dockP@") + parallel.gripOffset,
                                         "--tool", "vacuum:dockV@0,0,0.12",
                                         // A free place beside the cell, to rearrange tools.
                                         "--dock", "shelf@0.0,-0.6,0.35,3.141592653589793,0,0"};
        for (const auto& o : objects) args.insert(args.end(), {"--object", o});
        world = start(binary, std::move(args));
        if (world->url().empty()) return;
        tools = world->pkiDir().string() + "-tools";
        const std::string common = " --port 0 --host 127.0.0.1 --insecure --speed 20 --world " +
                                   world->url() + " --mdns-ttl 5 --mdns-query-period 1";
        std::vector<std::string> changerArgs = {
            "toolchanger",
            "--world",
            world->url(),
            "--tool",
            std::string("parallel:1.0-1.5:") + parallel.applicationUri,
            "--tool",
            std::string("vacuum:2.0-2.5:") + kSchmalzUri,
            "--power",
            "parallel=" + binary + " device " + parallel.command + " --pki-dir " + tools +
                "-parallel --grip-offset " + parallel.gripOffset + common,
            "--detection-timeout-ms",
            "20000"};
        if (vacuumPowered) {
            changerArgs.insert(changerArgs.end(),
                               {"--power", "vacuum=" + binary + " device schmalz --pki-dir " +
                                               tools + "-schmalz" + common});
        }
        changer = start(binary, std::move(changerArgs));
        if (withPickAndPlace) {
            pickplace = start(
                binary, {"pickplace", "--world", world->url(), "--detection-timeout-ms", "5000"});
        }
        robot = start(binary, {"ur5", "--speed", robotSpeed, "--world", world->url()});
    }
    ~SimulatedCell() {
        // The changer powers the tools off when it stops; then their PKI directories go.
        robot.reset();
        pickplace.reset();
        changer.reset();
        std::error_code ec;
        std::filesystem::remove_all(tools + "-parallel", ec);
        std::filesystem::remove_all(tools + "-schmalz", ec);
    }
    SimulatedCell(const SimulatedCell&) = delete;
    SimulatedCell& operator=(const SimulatedCell&) = delete;

    [[nodiscard]] bool ready() const {
        return !world->url().empty() && changer && !changer->url().empty() && robot &&
               !robot->url().empty() && (!pickplace || !pickplace->url().empty());
    }

    std::unique_ptr<DeviceProcess> world, changer, pickplace, robot;
    std::string tools;        // PKI directories of the powered tools: <tools>-parallel, -schmalz
    std::string parallelUri;  // the parallel gripper's application URI

private:
    static std::unique_ptr<DeviceProcess> start(const std::string& binary,
                                                std::vector<std::string> args) {
        for (const char* a : {"--mdns-ttl", "5", "--mdns-query-period", "1"}) args.emplace_back(a);
        return std::make_unique<DeviceProcess>(binary, std::move(args), true);
    }
};

}  // namespace skillcell::test
