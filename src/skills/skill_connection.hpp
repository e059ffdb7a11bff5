#pragma once
// SkillConnection: one skill of another component, used by a composite (a tool changer runs
// the robot's move skill, a pick-and-place runs a move and a gripper's skills). It opens a
// session to the component's endpoint, finds the first skill whose type chain names the
// wanted type (by browse name, so any subtype counts) and attaches a SkillClient to it.
//
// Threading: like ua::Client, on the executor it was opened with.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "skills/remote_skill_browser.hpp"
#include "skills/skill_client.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::skills {

class SkillConnection {
public:
    /// BadNotFound (with `why`) when the component offers no skill of type `typeName`
    /// ("CartesianLinearMoveSkillType", "GraspSkillType", ...); the connection's or the
    /// browse's status otherwise.
    static asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> open(
        asio::any_io_executor executor, std::string endpointUrl, std::string typeName,
        ua::ClientConfig config, std::string* why);
    /// Opens a session to the component of `instance` (as the SkillDetector found it) and
    /// attaches a SkillClient to exactly that skill.
    static asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> open(
        asio::any_io_executor executor, SkillInstance instance, ua::ClientConfig config,
        std::string* why, SkillClientOptions options = {});
    ~SkillConnection();
    SkillConnection(const SkillConnection&) = delete;
    SkillConnection& operator=(const SkillConnection&) = delete;

    [[nodiscard]] SkillClient& skill() { return *skill_; }
    /// The session to the skill's component, for what else a user reads there.
    [[nodiscard]] ua::Client& client() { return *client_; }
    [[nodiscard]] const RemoteSkill& description() const { return remote_; }
    [[nodiscard]] const std::string& endpointUrl() const { return endpointUrl_; }
    /// The current value of one of the skill's parameters (BadNoMatch for an unknown name).
    asio::awaitable<ua::Result<ua::Variant>> readParameter(std::string name);
    /// The skill's LastTransition/TransitionTime (the server's clock; zero before the first
    /// transition): a Start that reached the skill changes it.
    asio::awaitable<ua::Result<ua::DateTime>> lastTransitionTime();
    /// Deletes the subscription and closes the session.
    asio::awaitable<void> close();

    struct Token {
    private:
        friend class SkillConnection;
        Token() = default;
    };
    SkillConnection(Token, asio::any_io_executor executor, std::string endpointUrl);

private:
    /// Connects and attaches to `skill`: the rest of both open()s.
    asio::awaitable<ua::StatusCode> attachTo(const RemoteSkill& skill, std::string* why,
                                             SkillClientOptions options);

    std::string endpointUrl_;
    std::unique_ptr<ua::Client> client_;
    std::shared_ptr<SkillClient> skill_;
    RemoteSkill remote_;
};

/// One life of a component at an endpoint (its address and ServerStatus.StartTime): what a
/// composite that lost a device there must not take again, while the detector still lists
/// it (a dead server is dropped only when the detector notices).
struct ComponentLife {
    std::string endpointUrl;
    std::int64_t startTicks = 0;
    friend bool operator==(const ComponentLife&, const ComponentLife&) = default;
};

/// The life of the component `detector` lists at `endpointUrl` (a zero StartTime when none).
[[nodiscard]] ComponentLife lifeAt(const SkillDetector& detector, const std::string& endpointUrl);

/// The endpoint of a live skill whose type chain names `typeName`, as `detector` knows it,
/// of the component `componentUri` (empty: of any), in none of the lives `gone`; waits up to
/// `timeout` for one to be detected (a component may still be starting, or starting again).
/// Empty when none came. On the detector's executor.
asio::awaitable<std::string> detectedSkillEndpoint(SkillDetector& detector, std::string typeName,
                                                   std::chrono::milliseconds timeout,
                                                   std::string componentUri = {},
                                                   std::vector<ComponentLife> gone = {});

}  // namespace skillcell::skills
