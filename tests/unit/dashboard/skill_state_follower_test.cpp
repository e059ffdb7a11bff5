// SkillStateFollower against a component with two skills on loopback: both skills are followed
// over one session (the component is handshaken once, not once per skill), a run of either
// brings its transitions, the session stays while one of them is followed and ends with the
// last; a skill removed while its session is being opened is never followed, and nothing of
// it stays open at the component.
#include "dashboard/skill_state_follower.hpp"

#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>

#include "client_thread.hpp"
#include "dashboard/cell_view.hpp"
#include "noop_component.hpp"
#include "skills/remote_skill_browser.hpp"

namespace skillcell::dashboard {
namespace {

using namespace std::chrono_literals;

/// A component with a linear and a point-to-point move.
struct TwoSkillComponent : test::NoOpComponent {
    TwoSkillComponent() : test::NoOpComponent("urn:skillcell:test:follower", 0ms) {
        server->inServer([this](ua::Server& s) {
            const auto type = skills->findSkillType("CartesianPtpMoveSkillType");
            if (type) {
                (void)skills->add(*type, "Ptp",
                                  std::make_unique<skills::NoOpBehaviour>(s.executor(), 0ms));
            }
            return 0;
        });
    }
    std::size_t sessions() {
        return server->inServer([](ua::Server& s) { return s.sessionCount(); });
    }
    /// Waits, at most 5 s, until the component has `n` sessions (a close is a request the
    /// follower sends on its own); the count either way.
    std::size_t sessionsBecome(std::size_t n) {
        const auto until = std::chrono::steady_clock::now() + 5s;
        while (sessions() != n && std::chrono::steady_clock::now() < until) {
            std::this_thread::sleep_for(5ms);
        }
        return sessions();
    }
};

/// What the follower reports, for the test to wait on.
class Reports {
public:
    SkillStateFollower::Listeners listeners() {
        SkillStateFollower::Listeners l;
        l.state = [this](const std::string& key, std::optional<skills::SkillState> state,
                         const skills::SkillTransitionRecord* transition) {
            const std::lock_guard lock(mutex_);
            states_[key].push_back(state);
            if (transition != nullptr) ++transitions_[key];
            changed_.notify_all();
        };
        l.failed = [this](const skills::SkillInstance& skill, const std::string& why) {
            const std::lock_guard lock(mutex_);
            failures_.push_back(CellView::keyOf(skill) + ": " + why);
        };
        return l;
    }
    /// Waits (at most 10 s) until `key` had at least `n` transitions, or any report at all
    /// when `n` is 0.
    bool waitFor(const std::string& key, int n) {
        std::unique_lock lock(mutex_);
        return changed_.wait_for(
            lock, 10s, [&] { return n == 0 ? states_.contains(key) : transitions_[key] >= n; });
    }
    std::optional<skills::SkillState> first(const std::string& key) {
        const std::lock_guard lock(mutex_);
        const auto it = states_.find(key);
        return it == states_.end() || it->second.empty() ? std::nullopt : it->second.front();
    }
    bool heardOf(const std::string& key) {
        const std::lock_guard lock(mutex_);
        return states_.contains(key);
    }
    std::vector<std::string> failures() {
        const std::lock_guard lock(mutex_);
        return failures_;
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::map<std::string, std::vector<std::optional<skills::SkillState>>> states_;
    std::map<std::string, int> transitions_;
    std::vector<std::string> failures_;
};

/// The component's skills as a detector would report them (browsed by a client that then
/// leaves).
std::vector<skills::SkillInstance> detected(test::ClientThread& thread, TwoSkillComponent& c) {
    return thread.run([&]() -> asio::awaitable<std::vector<skills::SkillInstance>> {
        std::vector<skills::SkillInstance> out;
        if ((co_await thread.client().connect(c.url())).isBad()) co_return out;
        skills::RemoteSkillBrowser browser;
        auto found = co_await browser.browse(thread.client());
        (void)co_await thread.client().disconnect();
        if (!found) co_return out;
        for (auto& remote : *found) {
            skills::SkillInstance s;
            static_cast<skills::RemoteSkill&>(s) = std::move(remote);
            s.componentUri = c.uri;
            s.endpointUrl = c.url();
            s.componentStartTime = ua::DateTime{1};
            out.push_back(std::move(s));
        }
        co_return out;
    });
}

TEST(SkillStateFollower, FollowsEverySkillOfAComponentOverOneSession) {
    TwoSkillComponent component;
    test::ClientThread thread;
    const auto skills = detected(thread, component);
    ASSERT_EQ(skills.size(), 2U);
    ASSERT_EQ(component.sessionsBecome(0), 0U);

    Reports reports;
    auto follower = SkillStateFollower::create(thread.io().get_executor(), ua::ClientConfig{},
                                               reports.listeners());
    asio::post(thread.io(), [&] {
        for (const auto& s : skills) follower->add(s);
    });
    for (const auto& s : skills) {
        ASSERT_TRUE(reports.waitFor(CellView::keyOf(s), 0)) << CellView::keyOf(s);
        EXPECT_EQ(reports.first(CellView::keyOf(s)), skills::SkillState::Ready);
    }
    EXPECT_EQ(component.sessions(), 1U);  // not one per skill
    EXPECT_EQ(thread.run([&]() -> asio::awaitable<std::size_t> { co_return follower->sessions(); }),
              1U);
    EXPECT_TRUE(reports.failures().empty());

    // A run of either skill (by another client) comes to the follower as transitions.
    for (const auto& s : skills) {
        auto client = thread.attach(component.url(), s.nodeId);
        ASSERT_TRUE(client);
        EXPECT_TRUE(thread.invoke(client, {}, 5s).ok());
        // Starting, Running, Completing and back to Ready at least: the run is seen.
        EXPECT_TRUE(reports.waitFor(CellView::keyOf(s), 2)) << CellView::keyOf(s);
    }
    thread.run([&]() -> asio::awaitable<int> {
        (void)co_await thread.client().disconnect();
        co_return 0;
    });

    // The session stays while one of its skills is followed, and ends with the last.
    asio::post(thread.io(), [&] { follower->remove(skills[0]); });
    EXPECT_EQ(component.sessionsBecome(1), 1U);
    asio::post(thread.io(), [&] { follower->remove(skills[1]); });
    EXPECT_EQ(component.sessionsBecome(0), 0U);
    EXPECT_EQ(thread.run([&]() -> asio::awaitable<std::size_t> { co_return follower->followed(); }),
              0U);
}

TEST(SkillStateFollower, ASkillRemovedWhileItsSessionOpensIsNeverFollowed) {
    TwoSkillComponent component;
    test::ClientThread thread;
    const auto skills = detected(thread, component);
    ASSERT_EQ(skills.size(), 2U);
    Reports reports;
    auto follower = SkillStateFollower::create(thread.io().get_executor(), ua::ClientConfig{},
                                               reports.listeners());
    // The first skill's session is being opened (the follower started on it when it was
    // added) when the first skill is removed; the other skill stays.
    asio::post(thread.io(), [&] {
        follower->add(skills[0]);
        follower->add(skills[1]);
        asio::post(thread.io(), [&] { follower->remove(skills[0]); });
    });
    ASSERT_TRUE(reports.waitFor(CellView::keyOf(skills[1]), 0));
    EXPECT_FALSE(reports.heardOf(CellView::keyOf(skills[0])));
    EXPECT_EQ(thread.run([&]() -> asio::awaitable<std::size_t> { co_return follower->followed(); }),
              1U);
    EXPECT_EQ(component.sessionsBecome(1), 1U);  // the session opened for the first is closed

    // stop() closes what is followed, and nothing is reported after it.
    asio::post(thread.io(), [&] {
        follower->stop();
        follower->add(skills[0]);
    });
    EXPECT_EQ(component.sessionsBecome(0), 0U);
    EXPECT_FALSE(reports.heardOf(CellView::keyOf(skills[0])));
}

}  // namespace
}  // namespace skillcell::dashboard
