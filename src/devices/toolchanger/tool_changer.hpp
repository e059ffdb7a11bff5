#pragma once
// ToolChanger: the Kelvin tool changer's controller. It attaches, detaches and changes
// tools by running the robot's CartesianLinearMove skill (given by endpoint, or the one the
// SkillDetector finds; it waits for the robot to be announced), switching the coupling and
// reading the tool's identification pin (ToolChangerIo), and powering the tool (its
// adapter process). An attach of a powered tool ends when the SkillDetector sees the tool's
// adapter (the application URI its table entry names): the tool's skills are there for the
// next step. Plug & Produce, by the changer.
//
// Every operation: to the approach 5 cm back along the flange's z axis from the tool position
// (point to point), in linearly, lock or open, back out linearly.
//
// Threading: operations run as coroutines on `executor` (the server's); the I/O (the pin,
// the valve, the power) runs on the changer's own I/O thread, so the server never blocks.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/thread_pool.hpp>
#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "devices/common/robot_motion.hpp"
#include "devices/toolchanger/tool_changer_io.hpp"
#include "devices/toolchanger/tool_power_supply.hpp"
#include "devices/toolchanger/tool_table.hpp"
#include "skills/skill_connection.hpp"
#include "skills/skill_detector.hpp"
#include "skills/sub_skill_runner.hpp"

namespace skillcell::devices::toolchanger {

struct ToolChangerOptions {
    ToolChangerOptions() = default;  // not an aggregate: GCC 12 (see ua::ClientConfig)
    double approachDistance = 0.05;  // m, along the flange's z axis
    std::chrono::milliseconds moveTimeout{60'000};
    /// How long to wait for the robot's move skill, and for a powered tool's adapter, to be
    /// detected.
    std::chrono::milliseconds detectionTimeout{30'000};
    /// How the changer connects to the robot (its certificate and user).
    ua::ClientConfig client;
    /// The application URI of the robot the changer is on, whose move skill it uses when a
    /// request names none; empty: the first robot detected (a cell with one robot).
    std::string robotUri;
    /// Where the changer keeps the dock of each tool it took (dock_map_file.hpp), so that a
    /// restarted changer can put the mounted tool back; empty: in memory only.
    std::filesystem::path dockMapFile;
};

enum class ToolOperation : std::uint8_t { Attach, Detach, Change };

struct ToolRequest {
    ToolOperation operation = ToolOperation::Attach;
    KDL::Frame toolPosition;   // the flange pose at the dock
    std::string moveEndpoint;  // empty: the detected CartesianLinearMove
    std::string toolAppUri;    // Attach, Change: the tool wanted (empty: the one at the dock)
};

class ToolChanger : public std::enable_shared_from_this<ToolChanger> {
public:
    /// `io` must outlive the changer; `detector` may be null (then moveEndpoint is needed and
    /// an attach does not wait for the tool's adapter).
    [[nodiscard]] static std::shared_ptr<ToolChanger> create(
        asio::any_io_executor executor, ToolChangerIo& io, ToolTable tools,
        std::shared_ptr<skills::SkillDetector> detector, ToolChangerOptions options = {});
    ~ToolChanger();
    ToolChanger(const ToolChanger&) = delete;
    ToolChanger& operator=(const ToolChanger&) = delete;

    /// One operation; an empty string on success, else why it failed.
    asio::awaitable<std::string> run(ToolRequest request);
    /// What a (re)started changer does first: it asks the hardware which tool is mounted
    /// (the identification pin, reported by onMountedTool) and powers that tool again, for
    /// after a crash or a power cut the changer's memory is gone but the tool is still
    /// locked on. The mounted tool's id ("" none), or why the pin could not be read.
    asio::awaitable<ua::Result<std::string>> recover();
    /// Stops the current operation (halts the robot's move); run() returns "halted".
    void halt();
    /// Halts, stops the I/O thread and powers every tool off (the component's end: nothing
    /// runs on the I/O after this).
    void shutdown();
    /// Suspends or resumes the robot's current move.
    void suspend();
    void resume();

    [[nodiscard]] const asio::any_io_executor& executor() const { return executor_; }
    [[nodiscard]] const ToolTable& tools() const { return tools_; }
    /// Called on the executor whenever the pin was read: the mounted tool's id ("" none).
    std::function<void(const std::string&)> onMountedTool;

    struct Token {
    private:
        friend class ToolChanger;
        Token() = default;
    };
    ToolChanger(Token, asio::any_io_executor executor, ToolChangerIo& io, ToolTable tools,
                std::shared_ptr<skills::SkillDetector> detector, ToolChangerOptions options);

private:
    struct Pin {
        ua::StatusCode status;
        PinReading reading;
        double volts = 0;
    };
    using Motion = std::unique_ptr<RobotMotion>;

    asio::awaitable<Pin> readPin();
    asio::awaitable<ua::StatusCode> setLock(bool lock);
    asio::awaitable<ua::Result<bool>> lockedNow();
    asio::awaitable<std::string> powerOn(const ToolEntry& tool);
    asio::awaitable<void> powerOff(const ToolEntry& tool);
    /// The robot at `endpoint`, or (empty) the detected one in none of the lives `gone`;
    /// `unreachable` is set, and its life added to `gone`, when it was found but could not be
    /// reached. `life` (if given) is the detected robot's life it connected to (none for a
    /// given endpoint): the one a try that loses it adds to `gone`, not a later one.
    asio::awaitable<Motion> openMove(const std::string& endpoint, std::string& why,
                                     std::vector<skills::ComponentLife>& gone,
                                     bool* unreachable = nullptr,
                                     skills::ComponentLife* life = nullptr);
    /// One try of run(); `lost` is set when it lost the robot or its I/O (whose lives
    /// `gone` gains).
    asio::awaitable<std::string> attempt(const ToolRequest& request, std::uint64_t generation,
                                         bool& lost, std::vector<skills::ComponentLife>& gone);
    asio::awaitable<std::string> moveTo(RobotMotion& move, KDL::Frame flange,
                                        RobotMotion::Path path, std::uint64_t generation);
    asio::awaitable<std::string> attachAt(RobotMotion& move, KDL::Frame position,
                                          std::string appUri, std::uint64_t generation);
    asio::awaitable<std::string> detachAt(RobotMotion& move, KDL::Frame position,
                                          std::uint64_t generation);
    asio::awaitable<bool> waitForComponent(std::string applicationUri);
    /// Whether the mounted tool is the one a ChangeTool asks for (by ToolAppUri, or else by
    /// the dock it was taken from).
    [[nodiscard]] bool isWanted(const ToolEntry& mounted, const ToolRequest& request) const;
    [[nodiscard]] KDL::Frame approachOf(const KDL::Frame& position) const;

    asio::any_io_executor executor_;
    ToolChangerIo& io_;
    ToolTable tools_;
    std::shared_ptr<skills::SkillDetector> detector_;
    ToolChangerOptions options_;
    ToolPowerSupply power_;
    /// Records where `tool` was taken (a pose) or that it is back in a dock (none), in
    /// docks_ and in the dock map file; a lock under way is over.
    void rememberDock(const std::string& tool, const std::optional<KDL::Frame>& dock);
    /// Records, before the coupling closes at `dock`, that a lock is under way there (none:
    /// it is over, and nothing was taken).
    void noteLocking(const std::optional<KDL::Frame>& dock);
    /// The mounted tool as the pin reads it: one without a dock of its own was taken where
    /// a lock was under way when this changer (or the one before its restart) stopped.
    void adoptLocking(const ToolEntry* mounted);
    void saveDocks();

    std::map<std::string, KDL::Frame> docks_;  // tool id -> where this changer took it
    std::optional<KDL::Frame> locking_;        // a lock under way at this dock
    // Whether an I/O call of the current try found the I/O out of reach (the fieldbus down,
    // the I/O restarting): such a try is taken again, as one that lost the robot is.
    bool ioLost_ = false;
    skills::SubSkillRunner subSkill_;  // the robot's move, run now
    asio::thread_pool ioThread_{1};    // last: joined first, while the rest still exists
};

}  // namespace skillcell::devices::toolchanger
