#pragma once
// PickAndPlace: the pick-and-place composite. It reads the object's box and pose from the
// world model and the grip point (offset and type) from the tool's Grasp skill, plans the
// flange poses (GraspPlanner: a vacuum gripper from the top, a parallel one from the side,
// approaches 5 cm off), and runs the robot's moves (RobotMotion: point to point to the
// approaches, linear in and out) and the tool's Grasp and Release through SkillClients:
// approach, grasp pose, Grasp, retreat, place approach, place, Release, retreat. A terminal
// block for a DIN rail is hooked over the rail's upper edge and rotated down instead of being
// put down (rail_planner.hpp), and the world must show it snapped. A blade fuse is gripped
// from the top and inserted into its slot with the robot's force-limited move
// (fuse_planner.hpp), and the world must show it seated. The move and tool
// skills come by endpoint, or are the ones the SkillDetector finds: the robot, where none is
// named, the one that carries the tool (the tool's RobotUri), so that in a cell of several
// robots a pick moves the gripper it uses. It publishes its current step;
// a sub-skill that fails or is missing ends the run with the step and the reason. While it
// runs it holds the robot and the tool (their reservations, for its application URI), so
// that nothing else moves them under it.
//
// Threading: runs as coroutines on `executor` (the server's); the world model's blocking
// calls run on its own I/O thread.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/thread_pool.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "devices/common/robot_motion.hpp"
#include "devices/pickplace/grasp_planner.hpp"
#include "devices/pickplace/rail_planner.hpp"
#include "devices/world/world_link.hpp"
#include "skills/skill_connection.hpp"
#include "skills/sub_skill_runner.hpp"

namespace skillcell::devices::pickplace {

struct PickAndPlaceOptions {
    PickAndPlaceOptions() = default;  // not an aggregate: GCC 12 (see ua::ClientConfig)
    double approachDistance = kDefaultApproachDistance;
    std::chrono::milliseconds skillTimeout{60'000};  // each sub-skill
    /// How long to wait for a move or tool skill to be detected when no endpoint is given.
    std::chrono::milliseconds detectionTimeout{30'000};
    /// How the composite connects to the robot and the tool (its certificate and user).
    ua::ClientConfig client;
};

/// A terminal block's place on a DIN rail (rail_planner.hpp).
struct RailTarget {
    std::string railId;
    double position = -1;  // m, the block's centre along the rail; negative: the next free
};

/// A blade fuse's slot (fuse_planner.hpp).
struct FuseTarget {
    std::string slotId;
    double forceLimit = 0;  // N, where the insertion stops
};

struct PickRequest {
    std::string objectId;
    std::string toolEndpoint;  // empty: the detected Grasp skill's component (of toolUri)
    std::string toolUri;       // with no toolEndpoint: the tool's component URI; empty: any
    std::string moveEndpoint;  // empty: the CartesianLinearMove of the robot carrying the tool
    KDL::Frame placePosition;  // where the object's centre and orientation end up
    /// Set: the object is a terminal block hooked onto this rail (placePosition unused).
    std::optional<RailTarget> rail;
    /// Set: the object is a blade fuse inserted into this slot (placePosition unused).
    std::optional<FuseTarget> fuse;
};

class PickAndPlace : public std::enable_shared_from_this<PickAndPlace> {
public:
    /// `world` must outlive the composite; `detector` may be null (then both endpoints are
    /// needed).
    [[nodiscard]] static std::shared_ptr<PickAndPlace> create(
        asio::any_io_executor executor, WorldLink& world,
        std::shared_ptr<skills::SkillDetector> detector, PickAndPlaceOptions options = {});
    ~PickAndPlace();
    PickAndPlace(const PickAndPlace&) = delete;
    PickAndPlace& operator=(const PickAndPlace&) = delete;

    /// One pick and place; an empty string on success, else the failed step and why.
    asio::awaitable<std::string> run(PickRequest request);
    /// Stops the current run (halts the running sub-skill); run() returns "halted".
    void halt();
    /// Suspends or resumes the running sub-skill.
    void suspend();
    void resume();
    /// Halts and stops the I/O thread (the component's end).
    void shutdown();

    [[nodiscard]] const asio::any_io_executor& executor() const { return executor_; }
    /// Called on the executor with each step's name as it begins ("" when a run ends).
    std::function<void(const std::string&)> onStep;

    struct Token {
    private:
        friend class PickAndPlace;
        Token() = default;
    };
    PickAndPlace(Token, asio::any_io_executor executor, WorldLink& world,
                 std::shared_ptr<skills::SkillDetector> detector, PickAndPlaceOptions options);

private:
    using Connection = std::unique_ptr<skills::SkillConnection>;
    struct Skills {
        std::unique_ptr<RobotMotion> move;
        Connection grasp, release;
        std::optional<std::uint64_t> toolToken;  // the tool's reservation, while held
        bool unreachable = false;                // a device found by discovery could not be reached
        /// Lives of devices lost in earlier tries, not to be taken again (in), and this try's
        /// lost ones added (out).
        std::vector<skills::ComponentLife> gone;
        /// The life of each device this try found by discovery, by endpoint.
        std::map<std::string, skills::ComponentLife> found;
        /// The application URI of each server this try connected to, by endpoint: how a
        /// device named by its endpoint is found again after it restarts elsewhere.
        std::map<std::string, std::string> uris;
        bool lost = false;  // set by noteLosses()
        /// Notes, before the try closes its connections, whether it lost a device it drives
        /// (one unreachable, or a session gone) in `lost`; the lives of the lost ones join
        /// `gone`.
        void noteLosses();
    };

    /// The component the detector found at `endpoint`; empty when none.
    [[nodiscard]] std::string componentAt(const std::string& endpoint) const;
    /// One attempt at the run: "" or why it failed; `skills` says whether a device was lost.
    asio::awaitable<std::string> attempt(const PickRequest& request, std::uint64_t generation,
                                         Skills& skills);
    asio::awaitable<std::string> openSkills(const PickRequest& request, Skills& skills);
    /// The skill at `endpoint`, or (empty) the detected one of `typeName`, of the component
    /// `componentUri` if one is named, in none of `skills.gone`. `skills.unreachable` is set
    /// when it was found but could not be reached.
    asio::awaitable<Connection> open(std::string endpoint, std::string typeName, std::string& why,
                                     std::string componentUri, Skills& skills);
    /// One thing the composite does, in order: a move, a tool skill, or a check of the world.
    struct Action {
        enum class Kind {
            Transfer,
            Linear,
            Insert,  // linear, force-limited
            Open,
            Grasp,
            Release,
            CheckSnapped,
            CheckMounted,
            CheckSeated,
        };
        Kind kind;
        std::string name;
        KDL::Frame flange;  // moves
    };
    using Script = std::vector<Action>;

    /// What the scene shows of the object and the robot this composite drives: a run cut
    /// short (its composite killed) may have left the object in that robot's gripper, or at
    /// its place already.
    struct Perceived {
        std::string robot;   // the world's id of the robot this composite drives; may be empty
        KDL::Frame flange;   // that robot's flange
        std::string holder;  // the robot that holds the object; empty: none
    };
    asio::awaitable<std::string> perceive(const PickRequest& request, Skills& skills,
                                          Perceived& seen);
    asio::awaitable<std::string> plan(const PickRequest& request, Skills& skills, Script& script);
    asio::awaitable<std::string> planRail(const PickRequest& request, const BoxSize& size,
                                          const KDL::Frame& pose, const KDL::Frame& gripOffset,
                                          GripPointType type, Script& script);
    asio::awaitable<std::string> planFuse(const PickRequest& request, const BoxSize& size,
                                          const KDL::Frame& pose, const KDL::Frame& gripOffset,
                                          GripPointType type, Script& script);
    asio::awaitable<std::string> execute(const Script& script, const PickRequest& request,
                                         Skills& skills, std::uint64_t generation);
    asio::awaitable<std::string> step(std::string name, skills::SkillConnection& skill,
                                      std::uint64_t generation);
    asio::awaitable<std::string> move(std::string name, RobotMotion& motion, KDL::Frame flange,
                                      RobotMotion::Path path, std::uint64_t generation,
                                      MoveLimits limits = {});
    void publish(const std::string& name);

    asio::any_io_executor executor_;
    WorldLink& world_;
    std::shared_ptr<skills::SkillDetector> detector_;
    PickAndPlaceOptions options_;
    skills::SubSkillRunner subSkill_;  // the move, Grasp or Release run now
    asio::thread_pool ioThread_{1};    // last: joined first, while the rest still exists
};

}  // namespace skillcell::devices::pickplace
