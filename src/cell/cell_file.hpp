#pragma once
// A cell file: one TOML file that describes a whole work cell, its software components, its
// simulated devices and their scene, its security and its network (docs/cells.md). This is
// the value it is read into, and the reader, which checks everything before anything starts:
// a wrong file gives every problem at once, each with file:line:column, and no CellFile.
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/expected.hpp"
#include "devices/common/frame.hpp"

namespace skillcell::cell {

/// A pose in the cell's base frame: the devices layer's six numbers, metres and radians about
/// the fixed X, Y, Z axes (src/devices/common/frame.hpp).
using Pose = devices::Pose6;

/// Where the cell's components find each other by mDNS.
struct Network {
    enum class Kind { PrivateNamespace, Host };
    Kind kind = Kind::PrivateNamespace;   // a namespace needs root; Host uses the host's links
    std::vector<std::string> interfaces;  // Host: the interfaces mDNS uses; empty: all
    int mdnsTtlSeconds = 120;
    int mdnsQueryPeriodSeconds = 3600;
};

struct Security {
    bool enabled = true;
    /// Empty: generate a cell CA in the cell's work directory; else a directory holding one
    /// (as `skillcell pki init` makes it).
    std::filesystem::path ca;
    /// Empty: generate the users operator (Operator), engineer (Engineer) and observer
    /// (Observer) with fresh passwords; else a user database (`skillcell user add`).
    std::filesystem::path users;
};

struct KnowledgeBase {
    std::vector<std::filesystem::path> processes;  // Turtle files loaded at start (checked)
    std::string sparqlUrl;  // an external SPARQL store instead of the KB's own Virtuoso
};

struct Mes {
    int stepTimeoutMs = 300'000;
};

/// The cell's live view in a browser (`skillcell dashboard`).
struct Dashboard {
    int port = 0;  // its HTTPS port; 0: a free one (kept across restarts by `cell up`)
};

struct Dock {
    std::string name;
    Pose pose;  // the flange pose at which its tool locks
};

/// A box in the world: a plain box, a terminal block that snaps onto a DIN rail, or a blade
/// fuse that goes into a fuse slot.
struct WorldObject {
    enum class Kind { Box, TerminalBlock, Fuse };
    std::string name;
    /// Edges, m (a terminal block: width, depth, height; a fuse: width, thickness, height).
    std::array<double, 3> size{};
    Pose pose;                   // its centre
    std::optional<double> mass;  // kg; none: not said (no gripper is checked against it)
    Kind kind = Kind::Box;
};

/// A TS35 DIN rail (src/devices/world/din_rail.hpp): the pose of its start, x along the rail,
/// y towards its upper edge, z out of its face.
struct Rail {
    std::string name;
    Pose pose;
    double length = 0;  // m
};

/// A fuse box's slot for an ATO blade fuse (src/devices/world/fuse_slot.hpp): the pose of its
/// opening's centre, z out of the box, x through its terminals.
struct FuseSlot {
    std::string name;
    Pose pose;
    /// Where its terminals really are from `pose`, in its frame (m): a box made out of
    /// tolerance, which only the world's physics knows.
    std::array<double, 3> misalignment{};
};

/// A tool: where it is stored, what the tool changer reads on its identification pin, and
/// the adapter that the changer powers when it is mounted.
struct Tool {
    std::string name;
    std::string dock;
    std::string adapter;                 // a gripper model: robotiq-2f85, dh-ag95, schmalz-ecbpi
    std::array<double, 3> gripOffset{};  // its grip point from the mounting plate, m
    std::array<double, 2> pinVoltage{};  // the band on the changer's identification pin, V
    std::string changer;  // the tool changer it is for (the only one when the file says none)
};

struct Robot {
    std::string name;
    std::string model;  // ur5
    double speed = 1;   // simulated seconds per real second
    Pose base;          // its base frame in the cell's; the cell's origin when not given
};

struct ToolChanger {
    std::string name = "toolchanger";
    std::string model = "kelvin";
    std::string robot;  // the robot it is on (the only one when the file says none)
};

struct PickAndPlace {
    std::string name = "pickplace";
};

/// What `cell up` does when a component ends without being asked to: start it again after
/// it failed (a non-zero exit or a signal: a crash, a kill), after any end, or never. A
/// component that keeps failing is given up after a few restarts within a minute.
enum class RestartPolicy { OnFailure, Always, Never };
[[nodiscard]] std::string_view toString(RestartPolicy policy);

struct CellFile {
    std::filesystem::path path;  // where it was read from; relative paths are from its folder
    std::string name;
    Network network;
    Security security;
    bool lds = false;  // a local discovery server (LDS-ME) of the cell's own
    std::optional<KnowledgeBase> kb;
    std::optional<Mes> mes;
    /// [demo] process: the IRI of the process `skillcell demo --cell` runs on this cell (one
    /// of the [kb] files'); empty when the cell names none.
    std::string demoProcess;
    std::optional<Dashboard> dashboard;
    std::vector<Dock> docks;
    std::vector<WorldObject> objects;
    std::vector<Rail> rails;
    std::vector<FuseSlot> fuseSlots;
    std::vector<Tool> tools;
    std::vector<Robot> robots;
    std::vector<ToolChanger> toolChangers;  // one per robot at most
    /// Pick-and-place composites: each runs one pick at a time, on whichever robot a step
    /// gives it, so a cell that picks with several robots at once has several.
    std::vector<PickAndPlace> pickAndPlaces;
    /// The tool changer named `changer`, or nullptr.
    [[nodiscard]] const ToolChanger* toolChanger(const std::string& changer) const;
    /// The pick-and-place composite named `composite`, or nullptr.
    [[nodiscard]] const PickAndPlace* pickAndPlace(const std::string& composite) const;
    /// Each component's `restart` key, by component name ("lds", "kb", "mes", "dashboard",
    /// "world", or a
    /// device's name); absent: RestartPolicy::OnFailure.
    std::map<std::string, RestartPolicy> restart;
    [[nodiscard]] RestartPolicy restartPolicy(const std::string& component) const;
    /// Each component's `host` key, by component name: the components that run on a host of
    /// their own, a network namespace joined to the cell's network by a link of its own (which
    /// can go down, as a cable is pulled). Absent: the cell's network namespace itself.
    std::map<std::string, std::string> hosts;
    /// The host `component` runs on; empty for the cell's own network.
    [[nodiscard]] std::string hostOf(const std::string& component) const;
    /// Every host the components name, sorted, each once.
    [[nodiscard]] std::vector<std::string> hostNames() const;
    /// The cell's components in start order: lds, kb, world, the tool changer, the robots,
    /// pick-and-place, mes, dashboard (those the file has).
    [[nodiscard]] std::vector<std::string> componentNames() const;
};

/// Why `host` cannot name a host of `cell`, or empty: 1 to 12 lower-case letters, digits or
/// '-', beginning with a letter (it names the host's link, v-HOST), and a cell in a private
/// network namespace (hosts are namespaces beside it).
[[nodiscard]] std::string hostProblem(const CellFile& cell, std::string_view host);
/// Puts `component` on `host` (`cell up --host`), as its `host` key would; why not, or empty.
[[nodiscard]] std::string placeOnHost(CellFile& cell, const std::string& component,
                                      const std::string& host);

/// One problem in a cell file, where it is.
struct Problem {
    std::string file;
    int line = 0;
    int column = 0;
    std::string message;  // names the key and what was expected
    /// "FILE:LINE:COLUMN: MESSAGE", as compilers print it ("FILE: MESSAGE" without a line).
    [[nodiscard]] std::string describe() const;
};

/// A cell file, or every problem found in it.
struct ReadResult {
    std::optional<CellFile> cell;
    std::vector<Problem> problems;  // empty when `cell` is set
};

/// The gripper models an adapter may be, as `skillcell device` names them.
[[nodiscard]] const std::vector<std::string_view>& adapterModels();
/// The robot models.
[[nodiscard]] const std::vector<std::string_view>& robotModels();

/// Reads and checks a cell file. Unknown keys, values of the wrong type or outside their
/// range, missing keys, duplicate names, dangling references (a tool in a dock that does not
/// exist), overlapping pin-voltage bands and missing process files are all problems.
[[nodiscard]] ReadResult readCellFile(const std::filesystem::path& path);
/// The same for text already in memory; `sourceName` is what problems call the file, and
/// relative paths are resolved from `baseDirectory`.
[[nodiscard]] ReadResult readCellText(std::string_view text, const std::string& sourceName,
                                      const std::filesystem::path& baseDirectory);

}  // namespace skillcell::cell
