#pragma once
// SkillStateFollower: the state of every skill a SkillDetector reports, kept current by each
// skill's events, over one session per component. The first skill of a component opens the
// session; its other skills attach alongside it (SkillConnection::alongside), one after the
// other. A component that starts beside a cell's clients is handshaken by each of them: one
// secured session more per skill it offers was what the dashboard cost it.
//
// A component's life (its endpoint and StartTime) is what shares a session: a restarted
// component gets a new one. A skill removed while its session is being opened is not followed.
//
// Threading: everything on the executor given to create(), which must not run handlers
// concurrently; the callbacks are called there.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "skills/skill_connection.hpp"
#include "skills/skill_detector.hpp"
#include "ua/client/client.hpp"

namespace skillcell::dashboard {

class SkillStateFollower : public std::enable_shared_from_this<SkillStateFollower> {
public:
    /// `key` is CellView::keyOf(skill). The state as read when the skill is attached
    /// (`transition` null), then as each transition event brings it.
    using StateListener =
        std::function<void(const std::string& key, std::optional<skills::SkillState> state,
                           const skills::SkillTransitionRecord* transition)>;
    /// A skill is followed now, over `connection` (for what else a user reads or subscribes
    /// to on that session; it stays the follower's).
    using FollowedListener = std::function<void(const skills::SkillInstance& skill,
                                                const std::shared_ptr<skills::SkillConnection>&)>;
    /// A skill cannot be followed: `why`.
    using FailureListener =
        std::function<void(const skills::SkillInstance& skill, const std::string& why)>;

    struct Listeners {
        StateListener state;
        FollowedListener followed;
        FailureListener failed;
    };

    [[nodiscard]] static std::shared_ptr<SkillStateFollower> create(asio::any_io_executor executor,
                                                                    ua::ClientConfig config,
                                                                    Listeners listeners);
    /// Follows `skill` (a SkillEvent's Added); one already followed under its key is
    /// replaced.
    void add(const skills::SkillInstance& skill);
    /// Stops following `skill` (a SkillEvent's Removed); the session closes with its last
    /// skill.
    void remove(const skills::SkillInstance& skill);
    /// Forgets every skill and calls no listener any more; the sessions close politely.
    void stop();

    /// How many skills are followed (attached), and over how many sessions.
    [[nodiscard]] std::size_t followed() const;
    [[nodiscard]] std::size_t sessions() const;

    struct Token {
    private:
        friend class SkillStateFollower;
        Token() = default;
    };
    SkillStateFollower(Token, asio::any_io_executor executor, ua::ClientConfig config,
                       Listeners listeners);

private:
    struct Skill {
        skills::SkillInstance instance;
        std::shared_ptr<skills::SkillConnection> connection;  // null until attached
    };
    /// Attaches the skills waiting for `life`, one by one, until none waits.
    asio::awaitable<void> attachAll(std::string life);
    asio::awaitable<void> attach(skills::SkillInstance skill, std::string life);
    /// A connection of that life to go alongside (null: none attached).
    [[nodiscard]] std::shared_ptr<skills::SkillConnection> sessionOf(const std::string& life) const;
    void closeLater(std::shared_ptr<skills::SkillConnection> connection);

    asio::any_io_executor executor_;
    ua::ClientConfig config_;
    Listeners listeners_;
    bool stopped_ = false;
    std::map<std::string, Skill> skills_;  // by CellView::keyOf
    /// By component life: the keys of the skills still to attach. An entry means a
    /// coroutine is at them (attachAll), which removes it when none is left.
    std::map<std::string, std::deque<std::string>> waiting_;
};

}  // namespace skillcell::dashboard
