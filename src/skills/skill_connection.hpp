#pragma once
// SkillConnection: one skill of another component, used by a composite (a tool changer runs
// the robot's move skill, a pick-and-place runs a move and a gripper's skills). It opens a
// session to the component's endpoint, finds the first skill whose type chain names the
// wanted type (by browse name, so any subtype counts) and attaches a SkillClient to it.
// Further skills of the same component go over the same session (alongside()): a robot's
// linear and point-to-point moves cost one secured handshake and one browse, not one each.
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
    [[nodiscard]] ua::Client& client() { return session_->client; }
    [[nodiscard]] const RemoteSkill& description() const { return remote_; }
    [[nodiscard]] const std::string& endpointUrl() const { return endpointUrl_; }
    /// The current value of one of the skill's parameters (BadNoMatch for an unknown name).
    asio::awaitable<ua::Result<ua::Variant>> readParameter(std::string name);
    /// The skill's LastTransition/TransitionTime (the server's clock; zero before the first
    /// transition): a Start that reached the skill changes it.
    asio::awaitable<ua::Result<ua::DateTime>> lastTransitionTime();
    /// Another skill of the same component, found as open() finds one, over this
    /// connection's session: no second handshake, no second browse (after the first by
    /// type). BadNotFound (with `why`) when the component offers none of `typeName`.
    asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> alongside(std::string typeName,
                                                                            std::string* why);
    /// Exactly `skill` (as a detector or a browse found it on this component), over this
    /// connection's session; BadSessionClosed (with `why`) once no connection keeps it open.
    asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> alongside(
        RemoteSkill skill, std::string* why, SkillClientOptions options = {});
    /// Deletes the subscription; closes the session when no other open connection shares it.
    asio::awaitable<void> close();

    struct Token {
    private:
        friend class SkillConnection;
        Token() = default;
    };
    SkillConnection(Token, asio::any_io_executor executor, std::string endpointUrl);

private:
    /// The session, shared by the connections alongside() made; `open` counts those
    /// attached and not closed yet (the last close() ends the session).
    struct Session {
        explicit Session(const asio::any_io_executor& executor) : client(executor) {}
        ua::Client client;
        std::size_t open = 0;
        std::vector<RemoteSkill> browsed;  // the component's skills, once browsed by type
    };

public:
    /// alongside()'s: another connection over `session`.
    SkillConnection(Token, std::shared_ptr<Session> session, std::string endpointUrl);

private:
    /// The component's skills (browsed once per session), and the one `typeName` names;
    /// BadNotFound with `why` when none.
    asio::awaitable<ua::Result<RemoteSkill>> find(const std::string& typeName, std::string* why);
    /// Attaches to `skill` on the session (which stays open when this fails).
    asio::awaitable<ua::StatusCode> attachTo(const RemoteSkill& skill, std::string* why,
                                             SkillClientOptions options);
    /// Closes the session after a failed open() (no other connection shares it yet).
    asio::awaitable<void> abandon();

    std::string endpointUrl_;
    std::shared_ptr<Session> session_;
    bool counted_ = false;  // attached, and counted in session_->open until close()
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
