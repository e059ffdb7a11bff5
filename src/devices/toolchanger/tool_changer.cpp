#include "devices/toolchanger/tool_changer.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <cstdio>
#include <optional>

#include "devices/common/blocking_call.hpp"
#include "devices/common/frame.hpp"
#include "devices/common/lost_device_retry.hpp"
#include "devices/toolchanger/dock_map_file.hpp"
#include "ua/types/connection_loss.hpp"

namespace skillcell::devices::toolchanger {
namespace {

constexpr const char* kMoveType = "CartesianLinearMoveSkillType";
constexpr auto kTransfer = RobotMotion::Path::Transfer;
constexpr auto kLinear = RobotMotion::Path::Linear;

std::string volts(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f V", v);
    return text;
}

/// Whether the component's skills are detected: what the next step needs of a tool.
bool hasComponent(const skills::SkillDetector& detector, const std::string& uri) {
    const auto all = detector.instances();
    return std::any_of(all.begin(), all.end(),
                       [&](const skills::SkillInstance& s) { return s.componentUri == uri; });
}

}  // namespace

std::shared_ptr<ToolChanger> ToolChanger::create(asio::any_io_executor executor, ToolChangerIo& io,
                                                 ToolTable tools,
                                                 std::shared_ptr<skills::SkillDetector> detector,
                                                 ToolChangerOptions options) {
    return std::make_shared<ToolChanger>(Token{}, std::move(executor), io, std::move(tools),
                                         std::move(detector), std::move(options));
}

ToolChanger::ToolChanger(Token, asio::any_io_executor executor, ToolChangerIo& io, ToolTable tools,
                         std::shared_ptr<skills::SkillDetector> detector,
                         ToolChangerOptions options)
    : executor_(std::move(executor)),
      io_(io),
      tools_(std::move(tools)),
      detector_(std::move(detector)),
      options_(std::move(options)),
      subSkill_(executor_) {
    if (options_.dockMapFile.empty()) return;
    auto docks = loadDockMap(options_.dockMapFile);
    if (!docks) {
        // The changer still works: a mounted tool's dock is then unknown until an operator
        // detaches it at its dock, as after a first start.
        spdlog::error("tool changer: the dock map: {}; starting without it",
                      docks.failure().message);
        return;
    }
    locking_ = docks->locking;
    if (locking_) {
        spdlog::info("tool changer: a lock was under way at {} when it stopped",
                     describe(*locking_));
    }
    for (auto& [tool, dock] : docks->docks) {
        if (tools_.byId(tool) == nullptr) {
            spdlog::warn(
                "tool changer: the dock map names tool '{}', which the tool table "
                "does not know; dropped",
                tool);
            continue;
        }
        spdlog::info("tool changer: tool {} was taken from {} (dock map)", tool, describe(dock));
        docks_.emplace(tool, dock);
    }
}

void ToolChanger::rememberDock(const std::string& tool, const std::optional<KDL::Frame>& dock) {
    if (dock) {
        docks_[tool] = *dock;
    } else {
        docks_.erase(tool);
    }
    locking_.reset();
    saveDocks();
}

void ToolChanger::noteLocking(const std::optional<KDL::Frame>& dock) {
    locking_ = dock;
    saveDocks();
}

void ToolChanger::adoptLocking(const ToolEntry* mounted) {
    if (!locking_) return;
    if (mounted == nullptr) {  // the coupling never closed on a tool
        noteLocking(std::nullopt);
        return;
    }
    if (docks_.contains(mounted->id)) return;
    spdlog::info("tool changer: tool {} was locked at {} as the changer stopped: its dock",
                 mounted->id, describe(*locking_));
    rememberDock(mounted->id, *locking_);
}

void ToolChanger::saveDocks() {
    if (options_.dockMapFile.empty()) return;
    if (auto s = saveDockMap(options_.dockMapFile, DockMap{docks_, locking_}); !s) {
        spdlog::error("tool changer: the dock map: {}", s.failure().message);
    }
}

ToolChanger::~ToolChanger() {
    ioThread_.join();
}

KDL::Frame ToolChanger::approachOf(const KDL::Frame& position) const {
    return position * KDL::Frame(KDL::Vector(0, 0, -options_.approachDistance));
}

void ToolChanger::halt() {
    subSkill_.halt();
}

void ToolChanger::shutdown() {
    halt();
    ioThread_.stop();
    ioThread_.join();
    power_.offAll();
}

void ToolChanger::suspend() {
    subSkill_.suspend();
}

void ToolChanger::resume() {
    subSkill_.resume();
}

asio::awaitable<ToolChanger::Pin> ToolChanger::readPin() {
    auto read = [this] { return io_.identificationCounts(); };
    auto counts = co_await blockingCall(ioThread_, std::move(read));
    Pin pin;
    if (!counts) {
        pin.status = counts.status();
        ioLost_ = ioLost_ || ua::isTransient(pin.status);
        co_return pin;
    }
    pin.volts = adcVolts(*counts);
    pin.reading = tools_.identify(pin.volts);
    if (onMountedTool) {
        onMountedTool(pin.reading.kind == PinReading::Kind::Tool ? pin.reading.tool->id : "");
    }
    co_return pin;
}

asio::awaitable<ua::StatusCode> ToolChanger::setLock(bool lock) {
    auto set = [this, lock] { return io_.setLockValve(lock); };
    const ua::StatusCode s = co_await blockingCall(ioThread_, std::move(set));
    ioLost_ = ioLost_ || ua::isTransient(s);
    co_return s;
}

asio::awaitable<ua::Result<bool>> ToolChanger::lockedNow() {
    auto read = [this] { return io_.locked(); };
    auto locked = co_await blockingCall(ioThread_, std::move(read));
    ioLost_ = ioLost_ || (!locked && ua::isTransient(locked.status()));
    co_return locked;
}

asio::awaitable<ua::Result<std::string>> ToolChanger::recover() {
    auto self = shared_from_this();
    const Pin pin = co_await readPin();
    if (pin.status.isBad()) {
        spdlog::error("tool changer: cannot read the identification pin at start: {}",
                      ua::statusName(pin.status));
        co_return pin.status;
    }
    if (pin.reading.kind == PinReading::Kind::Fault) {
        spdlog::error("tool changer: the identification pin reads {} at start: wiring fault",
                      volts(pin.volts));
        co_return ua::status::BadDeviceFailure;
    }
    if (pin.reading.kind != PinReading::Kind::Tool) {
        spdlog::info("tool changer: no tool mounted ({})", volts(pin.volts));
        co_return std::string();
    }
    const ToolEntry& tool = *pin.reading.tool;
    spdlog::warn("tool changer: tool {} is mounted already ({}): powering it again", tool.id,
                 volts(pin.volts));
    if (auto why = co_await powerOn(tool); !why.empty()) {
        spdlog::error("tool changer: tool {} is mounted but could not be powered: {}", tool.id,
                      why);
    }
    co_return tool.id;
}

asio::awaitable<std::string> ToolChanger::powerOn(const ToolEntry& tool) {
    if (tool.powerCommand.empty()) co_return std::string();
    auto on = [this, id = tool.id, argv = tool.powerCommand] {
        std::string why;
        const auto s = power_.on(id, argv, &why);
        return s.isBad() ? why : std::string();
    };
    co_return co_await blockingCall(ioThread_, std::move(on));
}

asio::awaitable<void> ToolChanger::powerOff(const ToolEntry& tool) {
    auto off = [this, id = tool.id] { return power_.off(id); };
    (void)co_await blockingCall(ioThread_, std::move(off));
}

asio::awaitable<bool> ToolChanger::waitForComponent(std::string applicationUri) {
    if (hasComponent(*detector_, applicationUri)) co_return true;
    auto self = shared_from_this();
    auto timer = std::make_shared<asio::steady_timer>(executor_, options_.detectionTimeout);
    const std::size_t id =
        detector_->subscribe([timer, applicationUri](const skills::SkillEvent& e) {
            if (e.kind == skills::SkillEvent::Kind::Added &&
                e.instance.componentUri == applicationUri) {
                timer->cancel();
            }
        });
    co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    detector_->unsubscribe(id);
    co_return hasComponent(*detector_, applicationUri);
}

asio::awaitable<ToolChanger::Motion> ToolChanger::openMove(const std::string& endpoint,
                                                           std::string& why,
                                                           std::vector<skills::ComponentLife>& gone,
                                                           bool* unreachable,
                                                           skills::ComponentLife* life) {
    std::string url = endpoint;
    if (url.empty()) {
        if (!detector_) {
            why = "MoveSkillControllerEndpoint is empty and this changer detects no skills";
            co_return nullptr;
        }
        // The robot may still be starting: wait for its move skill to be detected.
        std::string type = kMoveType;
        url = co_await skills::detectedSkillEndpoint(*detector_, type, options_.detectionTimeout,
                                                     options_.robotUri, gone);
        if (url.empty()) {
            why = std::string("no ") + kMoveType +
                  (options_.robotUri.empty() ? "" : " of " + options_.robotUri) +
                  " was detected within " + std::to_string(options_.detectionTimeout.count()) +
                  " ms";
            co_return nullptr;
        }
    }
    const skills::ComponentLife found =
        detector_ ? skills::lifeAt(*detector_, url) : skills::ComponentLife{url, 0};
    if (life != nullptr && endpoint.empty()) *life = found;
    bool lost = false;
    auto move = co_await RobotMotion::open(executor_, url, options_.client, why, false,
                                           kDeadHolderLease, &lost);
    if (lost) {
        if (endpoint.empty()) gone.push_back(found);
        if (unreachable != nullptr) *unreachable = true;
    }
    co_return move;
}

asio::awaitable<std::string> ToolChanger::moveTo(RobotMotion& move, KDL::Frame flange,
                                                 RobotMotion::Path path, std::uint64_t generation) {
    if (subSkill_.halted(generation)) co_return std::string("halted");
    std::string why = co_await move.moveTo(subSkill_, flange, path, options_.moveTimeout);
    if (subSkill_.halted(generation)) co_return std::string("halted");
    co_return why;
}

asio::awaitable<std::string> ToolChanger::attachAt(RobotMotion& move, KDL::Frame position,
                                                   std::string appUri, std::uint64_t generation) {
    Pin pin = co_await readPin();
    if (pin.status.isBad()) {
        co_return "cannot read the identification pin: " + std::string(ua::statusName(pin.status));
    }
    if (pin.reading.kind == PinReading::Kind::Tool) {
        co_return "tool " + pin.reading.tool->id + " is attached already: detach it first";
    }
    if (pin.reading.kind == PinReading::Kind::Fault) {
        co_return "the identification pin reads " + volts(pin.volts) +
            " with no tool locked: wiring fault";
    }
    const KDL::Frame approach = approachOf(position);
    if (auto why = co_await moveTo(move, approach, kTransfer, generation); !why.empty()) {
        co_return why;
    }
    if (auto why = co_await moveTo(move, position, kLinear, generation); !why.empty()) {
        co_return why;
    }
    // Noted before the coupling closes: a changer killed before it noted the tool it took
    // knows from this where that tool's dock is.
    noteLocking(position);
    if (const auto s = co_await setLock(true); s.isBad()) {
        noteLocking(std::nullopt);
        co_return "cannot switch the lock valve: " + std::string(ua::statusName(s));
    }
    const auto locked = co_await lockedNow();
    if (!locked || !*locked) {
        (void)co_await setLock(false);
        noteLocking(std::nullopt);
        (void)co_await moveTo(move, approach, kLinear, generation);
        co_return "the coupling did not lock at " + describe(position) + ": no tool there";
    }
    pin = co_await readPin();
    if (pin.status.isBad() || pin.reading.kind != PinReading::Kind::Tool) {
        co_return "the coupling locked, but the identification pin reads " + volts(pin.volts) +
            ": a tool this changer does not know";
    }
    const ToolEntry& tool = *pin.reading.tool;
    if (!appUri.empty() && tool.applicationUri != appUri) {
        // The wrong tool: leave it where it was.
        (void)co_await setLock(false);
        noteLocking(std::nullopt);  // after: killed before, the locked tool is from here
        (void)co_await moveTo(move, approach, kLinear, generation);
        co_return "the tool at " + describe(position) + " is " + tool.id + " (" +
            tool.applicationUri + "), not " + appUri;
    }
    rememberDock(tool.id, position);
    spdlog::info("tool changer: tool {} locked ({})", tool.id, volts(pin.volts));
    if (auto why = co_await powerOn(tool); !why.empty()) {
        co_return "tool " + tool.id + " is locked but could not be powered: " + why;
    }
    if (auto why = co_await moveTo(move, approach, kLinear, generation); !why.empty())
        co_return why;
    // The attach ends when the tool can be used: its adapter's skills are detected (the one
    // the table names for this tool, whether or not the caller named it).
    if (tool.powerCommand.empty()) co_return std::string();
    if (!detector_) {
        spdlog::warn("tool changer: no detector: not waiting for {}", tool.applicationUri);
        co_return std::string();
    }
    if (!co_await waitForComponent(tool.applicationUri)) {
        co_return "tool " + tool.id + " is attached and powered, but its adapter " +
            tool.applicationUri + " was not detected within " +
            std::to_string(options_.detectionTimeout.count()) + " ms";
    }
    spdlog::info("tool changer: tool {} detected as {}", tool.id, tool.applicationUri);
    co_return std::string();
}

asio::awaitable<std::string> ToolChanger::detachAt(RobotMotion& move, KDL::Frame position,
                                                   std::uint64_t generation) {
    const Pin pin = co_await readPin();
    if (pin.status.isBad()) {
        co_return "cannot read the identification pin: " + std::string(ua::statusName(pin.status));
    }
    if (pin.reading.kind == PinReading::Kind::NoTool) co_return std::string();  // nothing to do
    if (pin.reading.kind == PinReading::Kind::Fault) {
        co_return "the identification pin reads " + volts(pin.volts) +
            ": a tool this changer does not know";
    }
    const ToolEntry& tool = *pin.reading.tool;
    const KDL::Frame approach = approachOf(position);
    if (auto why = co_await moveTo(move, approach, kTransfer, generation); !why.empty()) {
        co_return why;
    }
    if (auto why = co_await moveTo(move, position, kLinear, generation); !why.empty()) {
        co_return why;
    }
    // Power first: the tool's adapter says goodbye before the contacts open.
    co_await powerOff(tool);
    if (const auto s = co_await setLock(false); s.isBad()) {
        co_return "cannot switch the lock valve: " + std::string(ua::statusName(s));
    }
    const auto locked = co_await lockedNow();
    if (!locked || *locked) {
        (void)co_await setLock(true);
        (void)co_await powerOn(tool);
        co_return "the coupling did not open at " + describe(position) + ": not a free dock";
    }
    rememberDock(tool.id, std::nullopt);
    spdlog::info("tool changer: tool {} left at {}", tool.id, describe(position));
    if (auto why = co_await moveTo(move, approach, kLinear, generation); !why.empty())
        co_return why;
    (void)co_await readPin();  // publishes "no tool"
    co_return std::string();
}

bool ToolChanger::isWanted(const ToolEntry& mounted, const ToolRequest& request) const {
    if (!request.toolAppUri.empty()) return mounted.applicationUri == request.toolAppUri;
    // No tool named: the one at ToolPosition is wanted, and the mounted one came from there.
    const auto dock = docks_.find(mounted.id);
    return dock != docks_.end() && near(dock->second, request.toolPosition, 1e-3, 1e-3);
}

asio::awaitable<std::string> ToolChanger::run(ToolRequest request) {
    auto self = shared_from_this();
    const std::uint64_t generation = subSkill_.begin();
    // The robot lost mid-run: the run goes on from what the identification pin says once
    // discovery finds the robot again.
    std::vector<skills::ComponentLife> gone;  // robots lost in earlier tries
    co_return co_await goOnAfterLostDevice(
        executor_,
        [this, &request, &gone, generation](bool& lost) -> asio::awaitable<std::string> {
            co_return co_await attempt(request, generation, lost, gone);
        },
        [this, generation] { return subSkill_.halted(generation); }, "tool changer");
}

asio::awaitable<std::string> ToolChanger::attempt(const ToolRequest& request,
                                                  std::uint64_t generation, bool& lost,
                                                  std::vector<skills::ComponentLife>& gone) {
    std::string why;
    ioLost_ = false;
    skills::ComponentLife life;  // the detected robot's, as it was found
    Motion move = co_await openMove(request.moveEndpoint, why, gone, &lost, &life);
    if (!move) co_return why;
    if (request.operation == ToolOperation::Attach) {
        why = co_await attachAt(*move, request.toolPosition, request.toolAppUri, generation);
    } else if (request.operation == ToolOperation::Detach) {
        why = co_await detachAt(*move, request.toolPosition, generation);
    } else {
        const Pin pin = co_await readPin();
        const ToolEntry* current =
            pin.reading.kind == PinReading::Kind::Tool ? pin.reading.tool : nullptr;
        if (pin.status.isGood() && pin.reading.kind != PinReading::Kind::Fault) {
            adoptLocking(current);
        }
        if (pin.status.isBad()) {
            why = "cannot read the identification pin: " + std::string(ua::statusName(pin.status));
        } else if (current != nullptr && isWanted(*current, request)) {
            spdlog::info("tool changer: tool {} is attached already", current->id);
        } else if (current != nullptr && !docks_.contains(current->id)) {
            why = "tool " + current->id +
                  " was not attached by this changer, so its dock is unknown: DetachTool it "
                  "at its dock first";
        } else {
            if (current != nullptr) {
                why = co_await detachAt(*move, docks_.at(current->id), generation);
            }
            if (why.empty()) {
                why =
                    co_await attachAt(*move, request.toolPosition, request.toolAppUri, generation);
            }
        }
    }
    const bool robotLost = !move->connected();
    if (robotLost && !life.endpointUrl.empty()) gone.push_back(life);
    lost = robotLost || ioLost_;
    co_await move->close();
    co_return why;
}

}  // namespace skillcell::devices::toolchanger
