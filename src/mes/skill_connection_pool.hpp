#pragma once
// SkillConnectionPool: the MES's sessions to the skills it runs, kept open between steps.
//
// Opening a connection per step cost a TCP connect, a secure channel (an RSA handshake with
// security on), a session with its user check, a browse and a subscription, then tearing them
// down again: most of the MES's own time per step, and more at the skill's server. A skill
// used by one step is given back here and taken again by the next step that runs it, as long
// as its session and subscription live and its component's endpoint is the same.
//
// A connection is used by one step at a time (the order holding the component has it). Idle
// ones are closed after `idle`. A kept one is handed out only after requests through it are
// answered: the taker's own first requests (a step's Reserve and LastTransition read), so
// that proving the session costs no round trip of its own. One whose session or subscription
// was lost meanwhile (its component restarted or left) is closed when next taken, and a new
// one opened. Each step
// reserves the component anew (reservation.hpp): keeping a session is not keeping the
// component.
//
// Threading: on the executor it was made with, like ua::Client.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "skills/skill_connection.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::mes {

class SkillConnectionPool {
public:
    SkillConnectionPool(asio::any_io_executor executor, ua::ClientConfig config,
                        skills::SkillClientOptions options, std::chrono::milliseconds idle);
    SkillConnectionPool(const SkillConnectionPool&) = delete;
    SkillConnectionPool& operator=(const SkillConnectionPool&) = delete;
    ~SkillConnectionPool();

    /// What a taker sends first through the connection it takes. True when the session
    /// answered, whatever the answers say (a refusal is an answer; a closed socket is not).
    using FirstUse = std::function<asio::awaitable<bool>(skills::SkillConnection&)>;

    /// A connection attached to `skill`: an idle one that still answers, else a new one
    /// (with SkillConnection::open's errors, and `why`). `first` runs on the connection
    /// before it is handed out: on a kept one that does not answer, then again on the new one
    /// opened instead; its results are the last run's. Without it, a read of the skill's
    /// LastTransition proves a kept session.
    asio::awaitable<ua::Result<std::unique_ptr<skills::SkillConnection>>> take(
        const skills::SkillInstance& skill, std::string* why, FirstUse first = {});
    /// `connection`, attached to `skill`, is free again. Kept when it is still alive (no
    /// run in progress, session and subscription up), else closed.
    asio::awaitable<void> giveBack(const skills::SkillInstance& skill,
                                   std::unique_ptr<skills::SkillConnection> connection);
    /// Closes every idle connection.
    asio::awaitable<void> closeAll();

    /// How many connections are idle here now.
    [[nodiscard]] std::size_t idleCount() const { return idle_.size(); }
    /// How many take()s were answered with a kept connection, and how many opened one.
    [[nodiscard]] std::size_t reused() const { return reused_; }
    [[nodiscard]] std::size_t opened() const { return opened_; }

private:
    // (component URI, endpoint URL, skill node id): a component that moved to another
    // endpoint is another key, and its old connections are closed as they expire.
    using Key = std::tuple<std::string, std::string, std::string>;
    static Key keyOf(const skills::SkillInstance& skill);
    struct Idle {
        std::unique_ptr<skills::SkillConnection> connection;
        std::chrono::steady_clock::time_point since;
    };
    static bool alive(skills::SkillConnection& c);
    /// Closes the idle connections older than idle_.
    asio::awaitable<void> expire();

    asio::any_io_executor executor_;
    ua::ClientConfig config_;
    skills::SkillClientOptions options_;
    std::chrono::milliseconds idleFor_;
    std::multimap<Key, Idle> idle_;
    std::size_t reused_ = 0;
    std::size_t opened_ = 0;
};

}  // namespace skillcell::mes
