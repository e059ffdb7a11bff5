#pragma once
// RobotMotion: a robot's Cartesian moves as a composite uses them (the tool changer, the
// pick and place): a transfer through free space goes point to point (CartesianPtpMove: the
// joints interpolate, so no wrist singularity lies on the way), an approach or a retreat goes
// in a straight line (CartesianLinearMove), and an insertion in a straight line that stops on
// contact (CartesianForceLimitedLinearMove, on arms that sense force). The skills are found on
// the robot's component; without a PTP skill every move is linear. Poses are flange poses
// (ToolFrame identity).
//
// The moves share one session to the robot's component (SkillConnection::alongside): one
// secured handshake and one browse for the robot, where there were one for each move.
//
// A composite holds the robot while it drives it: open() reserves the robot's component
// (docs/skills.md, "Reservation") for the composite's application URI through that session,
// and close() releases it. Another MES, or another composite, cannot move the robot meanwhile;
// a restarted composite (same URI) takes back what its former self held.
//
// Threading: on the executor it was opened with.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "skills/skill_connection.hpp"
#include "skills/sub_skill_runner.hpp"

namespace skillcell::devices {

/// A composite's sessions to the devices it drives are its lease on them (skills/reservation
/// .hpp): it asks for sessions that time out this soon, so that one killed while holding a
/// robot or a tool frees it within that, and another composite waits a little longer than that
/// for a device another holder has reserved.
inline constexpr std::chrono::milliseconds kCompositeSessionTimeout{10'000};
inline constexpr std::chrono::milliseconds kDeadHolderLease{12'000};

/// What a linear move may not exceed; 0: the robot's own limits.
struct MoveLimits {
    double force = 0;     // N, RobotMotion::Path::ForceLimited: where it stops
    double velocity = 0;  // m/s of the tool centre point, linear paths
};

class RobotMotion {
public:
    enum class Path : std::uint8_t { Linear, Transfer, ForceLimited };

    /// Opens the robot's CartesianLinearMove (required) and CartesianPtpMove (optional) at
    /// `endpoint`, and with `forceLimited` its CartesianForceLimitedLinearMove (optional: a
    /// connection of its own, so only for who inserts), and reserves the robot for
    /// `config.applicationUri`; null with `why` when the linear move is not there or the
    /// robot is reserved by another.
    /// `patience`: how long to wait for a robot another holder has reserved (skills::hold).
    /// `unreachable` (if given) is set when the robot could not be reached at all, or its
    /// connection closed before the reservation (not when it was reached and refused).
    static asio::awaitable<std::unique_ptr<RobotMotion>> open(
        asio::any_io_executor executor, std::string endpoint, ua::ClientConfig config,
        std::string& why, bool forceLimited = false,
        std::chrono::milliseconds patience = kDeadHolderLease, bool* unreachable = nullptr);
    ~RobotMotion();
    RobotMotion(const RobotMotion&) = delete;
    RobotMotion& operator=(const RobotMotion&) = delete;

    /// Moves the flange to `flange` as `runner`'s current sub-skill; "" or why it failed.
    asio::awaitable<std::string> moveTo(skills::SubSkillRunner& runner, KDL::Frame flange,
                                        Path path, std::chrono::milliseconds timeout,
                                        MoveLimits limits = {});
    /// Where the robot stands: its ReachCentre (the shoulder, in the cell's frame), as its
    /// linear move publishes it.
    asio::awaitable<ua::Result<KDL::Frame>> reachCentre();
    /// Whether the session to the robot is still up (false once its component died).
    [[nodiscard]] bool connected();
    /// Whether the robot offers force-limited moves.
    [[nodiscard]] bool sensesForce() const { return static_cast<bool>(forceLimited_); }
    /// Releases the robot and closes the session.
    asio::awaitable<void> close();
    [[nodiscard]] const std::string& endpointUrl() const { return linear_->endpointUrl(); }

    struct Token {
    private:
        friend class RobotMotion;
        Token() = default;
    };
    explicit RobotMotion(Token) {}

private:
    std::unique_ptr<skills::SkillConnection> linear_;
    std::unique_ptr<skills::SkillConnection> ptp_;           // may be null
    std::unique_ptr<skills::SkillConnection> forceLimited_;  // may be null
    std::optional<std::uint64_t> token_;                     // none: the robot has no reservation
};

/// "Finished", or "Failed: <reason> (<status>)": how a sub-skill's run ended, for a reason.
[[nodiscard]] std::string describeOutcome(const skills::SkillOutcome& outcome);

}  // namespace skillcell::devices
