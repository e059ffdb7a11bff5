#pragma once
// WorldLink: a device's connection to the world model component (world_nodes.hpp), with
// plain blocking calls. Simulated hardware uses it from its own thread (never from a
// server's io_context thread: each call waits for a round trip) to report what it does
// to the world (the flange moved, an object was grasped) and to ask what is there.
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>

#include "ua/client/blocking_client.hpp"
#include "ua/types/connection_loss.hpp"

namespace skillcell::devices {

class WorldLink {
public:
    /// Connects to the world model at `url` and finds its namespace (BadNotFound when the
    /// server serves no world). Changing the world needs the Operator role. `robot` is the
    /// world's id of the robot whose flange this device moves or acts at (the flange, tool
    /// and grasp calls are its); empty for a device that only reads the scene.
    [[nodiscard]] static ua::Result<std::unique_ptr<WorldLink>> connect(
        const std::string& url, ua::ClientConfig config = {}, std::string robot = {});
    WorldLink(const WorldLink&) = delete;
    WorldLink& operator=(const WorldLink&) = delete;
    ~WorldLink();

    /// Reports the flange; `contactForce` (if given) receives the force the held object
    /// meets there (N).
    ua::StatusCode setFlangePose(const KDL::Frame& flange, double* contactForce = nullptr);
    ua::StatusCode mountTool(const std::string& dockId);
    ua::StatusCode unmountTool(const std::string& dockId);
    ua::StatusCode grasp(const std::string& objectId);
    ua::StatusCode release();
    ua::StatusCode addObject(const std::string& id, const std::array<double, 3>& size,
                             const KDL::Frame& pose);
    ua::StatusCode addTerminalBlock(const std::string& id, const std::array<double, 3>& size,
                                    const KDL::Frame& pose);
    ua::StatusCode addRail(const std::string& id, const KDL::Frame& pose, double length,
                           double width);
    ua::StatusCode addFuse(const std::string& id, const std::array<double, 3>& size,
                           const KDL::Frame& pose);
    ua::StatusCode addFuseSlot(const std::string& id, const KDL::Frame& pose, double depth);
    ua::StatusCode addDock(const std::string& id, const KDL::Frame& pose);
    ua::StatusCode addTool(const std::string& id, const std::string& dockId,
                           const KDL::Frame& gripPoint);
    ua::StatusCode addRobot(const std::string& id, const KDL::Frame& base);
    /// A person moves a stored tool to a free dock (World::moveTool).
    ua::StatusCode moveTool(const std::string& id, const std::string& dockId);

    struct Found {
        std::string objectId;
        std::array<double, 3> extent{};  // along the grip point's x, y, z axes
    };
    /// The free object at the mounted tool's grip point; nullopt when there is none.
    [[nodiscard]] ua::Result<std::optional<Found>> objectAtGripPoint();
    /// The dock the flange is at; empty when none.
    [[nodiscard]] ua::Result<std::string> dockAtFlange();
    [[nodiscard]] ua::Result<KDL::Frame> objectPose(const std::string& objectId);
    /// The object's box edges x, y, z (m); BadNodeIdUnknown for an unknown object.
    [[nodiscard]] ua::Result<std::array<double, 3>> objectSize(const std::string& objectId);
    [[nodiscard]] ua::Result<std::string> mountedTool();
    [[nodiscard]] ua::Result<std::string> graspedObject();
    [[nodiscard]] ua::Result<KDL::Frame> flangePose();
    /// The mounted tool's grip point, in the cell's frame (the flange when no tool).
    [[nodiscard]] ua::Result<KDL::Frame> gripPoint();
    /// The ids of the objects (World/Objects) and the docks (World/Docks), as browsed.
    [[nodiscard]] ua::Result<std::vector<std::string>> objectIds();
    /// How often a gripper took hold of the object.
    [[nodiscard]] ua::Result<std::uint32_t> objectGrasps(const std::string& objectId);
    /// A robot as the scene shows it: where it stands, where its flange is, what it holds.
    struct RobotView {
        std::string id;
        KDL::Frame base, flange;
        std::string held;  // empty: nothing
    };
    /// Every robot of the world (what a composite that drives "the robot carrying the tool"
    /// perceives to find which one that is, and what it holds).
    [[nodiscard]] ua::Result<std::vector<RobotView>> robots();
    [[nodiscard]] ua::Result<std::vector<std::string>> dockIds();
    [[nodiscard]] ua::Result<KDL::Frame> dockPose(const std::string& dockId);
    /// The tool stored in the dock; empty when it is empty.
    [[nodiscard]] ua::Result<std::string> dockTool(const std::string& dockId);

    struct Rail {
        KDL::Frame pose;
        double length = 0, width = 0;  // m
    };
    /// A DIN rail's pose, length and width; BadNodeIdUnknown for an unknown rail.
    [[nodiscard]] ua::Result<Rail> rail(const std::string& railId);
    [[nodiscard]] ua::Result<std::vector<std::string>> railIds();
    struct Mount {
        std::string rail;
        double position = 0;  // m, the block's centre along the rail
    };
    /// Where a terminal block is mounted; nullopt when it is on no rail. BadNodeIdUnknown
    /// for an object that is no terminal block.
    [[nodiscard]] ua::Result<std::optional<Mount>> railMount(const std::string& objectId);
    /// Why the terminal block, held lying on a rail, has not snapped; empty when it has.
    [[nodiscard]] ua::Result<std::string> railRefusal(const std::string& blockId);

    struct Slot {
        KDL::Frame pose;  // the opening's centre, z out of the box
        double depth = 0;
        std::string fuse;  // seated in it; empty when none
    };
    /// A fuse slot; BadNodeIdUnknown for an unknown one.
    [[nodiscard]] ua::Result<Slot> fuseSlot(const std::string& slotId);
    /// The slot a fuse is seated in; empty when none. BadNodeIdUnknown for an object that
    /// is no fuse.
    [[nodiscard]] ua::Result<std::string> fuseSeat(const std::string& fuseId);
    /// The force the held object meets (N; a fuse entering a slot).
    [[nodiscard]] ua::Result<double> contactForce();

    struct Token {
    private:
        friend class WorldLink;
        Token() = default;
    };
    WorldLink(Token, std::string robot) : robot_(std::move(robot)) {}
    [[nodiscard]] const std::string& robot() const { return robot_; }

    /// Runs `call` (what a sensor sees), again every 100 ms while it finds the world out of
    /// reach or not ready, up to `patience`. Returns `call`'s last result (a StatusCode or a
    /// ua::Result).
    template <class Call>
    auto untilHeard(Call call, std::chrono::milliseconds patience) {
        const auto deadline = std::chrono::steady_clock::now() + patience;
        for (int tries = 1;; ++tries) {
            auto r = call();
            if (!ua::isTransient(statusOf(r)) || std::chrono::steady_clock::now() >= deadline) {
                if (tries > 1) heardAfter(tries, statusOf(r));
                return r;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(100));  // it is restarting
        }
    }

    /// Tells the world of something that happened (a grasp, a release): at once when it can,
    /// else, while the world is out of reach or not ready (restarting), from a thread of the
    /// link's own, again every 100 ms for up to a minute, in the order told: a world that
    /// restarts loses no physical event, and the device that tells it is not held up (a
    /// gripper's reply to its controller must not wait for the simulation). `what` names
    /// the event in the log.
    void tell(std::function<ua::StatusCode()> event, std::string what);
    /// Whether something told has not been heard yet: a simulated device shows the motion
    /// that caused it as still under way meanwhile, so that nothing above it acts on a grasp
    /// or release the world does not know of (the simulation is paused while its physics
    /// restarts). Any thread.
    [[nodiscard]] bool behind() const { return behind_.load(); }
    /// Waits until everything told has been heard (or given up on), at most `patience`;
    /// whether it has. For a device whose reads may wait for the world (an in-process one).
    bool waitUntilHeard(std::chrono::milliseconds patience);

    /// Whether the link's connection is up, as far as it knows without asking the world: no
    /// call found the world out of reach, and the world has not closed the connection (as
    /// its process does when it ends). Any thread; no round trip.
    [[nodiscard]] bool connected();
    /// How many times the link has connected (to the same world model, or to the one that
    /// took its place after a restart). Any thread.
    [[nodiscard]] std::uint64_t connections() const { return connections_.load(); }

    /// Whether a call found the world out of reach since the last clearLoss(): a composite
    /// takes a try that lost its view of the cell again. The link itself connects again on
    /// the call after one that found the world gone (the world restarted).
    [[nodiscard]] bool lostConnection() const { return lostSinceMark_; }
    void clearLoss() { lostSinceMark_ = false; }

private:
    static ua::StatusCode statusOf(ua::StatusCode s) { return s; }
    template <class T>
    static ua::StatusCode statusOf(const ua::Result<T>& r) {
        return r.status();
    }
    static void heardAfter(int tries, ua::StatusCode s);
    /// Connects and finds the world's namespace.
    ua::StatusCode open();
    /// Connects again first when the last call found the world out of reach.
    void reconnectIfLost();
    /// Notes whether `s` says the world is out of reach.
    void note(ua::StatusCode s);
    /// Sends `request` (a call of client_) when the world is in reach; once more on a new
    /// session when the world had closed the link's (idle longer than its timeout while the
    /// channel stayed up), which it refuses before running anything of the request.
    template <class Request>
    auto onSession(const Request& request) -> decltype(request());
    ua::Result<ua::Variant> readValue(const std::string& path);
    ua::Result<std::vector<ua::Variant>> call(const char* method, std::vector<ua::Variant> in);
    /// A call about this link's robot: its id goes first.
    ua::Result<std::vector<ua::Variant>> robotCall(const char* method,
                                                   std::vector<ua::Variant> in = {});
    /// "World/Robots/<robot>/" + name.
    [[nodiscard]] std::string robotPath(const char* name) const;
    ua::Result<std::string> readString(const std::string& path);
    ua::Result<KDL::Frame> readFrame(const std::string& path);
    ua::Result<double> readDouble(const std::string& path);
    ua::Result<std::vector<std::string>> children(const std::string& path);
    [[nodiscard]] ua::NodeId id(const std::string& path) const {
        return ua::NodeId(ns_.load(), ua::String(path));
    }

    /// Delivers the events tell() could not, in order (its thread).
    void deliverBacklog();

    ua::BlockingClient client_;
    std::string url_;
    ua::ClientConfig config_;
    std::atomic<std::uint16_t> ns_{0};
    std::string robot_;
    std::mutex reconnectMutex_;  // one reconnect at a time, whichever thread calls
    std::atomic<bool> lost_{false};
    std::atomic<std::uint64_t> connections_{0};
    std::atomic<bool> sessionClosed_{false};  // lost_ with the channel up: reconnect anew
    std::atomic<bool> lostSinceMark_{false};
    // Events not heard yet (tell()), and the thread that delivers them, started with the
    // first; its members are under backlogMutex_.
    struct Told {
        std::function<ua::StatusCode()> event;
        std::string what;
        std::chrono::steady_clock::time_point since;
    };
    std::mutex backlogMutex_;
    std::condition_variable backlogChanged_;
    std::deque<Told> backlog_;
    std::atomic<bool> behind_{false};  // !backlog_.empty(), readable without the lock
    bool stopping_ = false;
    std::thread backlogThread_;  // last: joined before the rest goes
};

}  // namespace skillcell::devices
