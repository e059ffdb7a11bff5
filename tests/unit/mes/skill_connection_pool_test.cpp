// SkillConnectionPool: a session given back after a step is taken again by the next step on
// that skill (no new session at the server); a connection whose component went away meanwhile
// is not handed out; with no keeping time, every connection is closed when given back; the
// taker's own first requests prove a kept session, and run again on a new one when it did not
// answer.
#include "mes/skill_connection_pool.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "client_thread.hpp"
#include "noop_component.hpp"

namespace skillcell::mes {
namespace {

using namespace std::chrono_literals;

skills::SkillInstance moveOf(const test::NoOpComponent& c) {
    skills::SkillInstance s;
    s.componentUri = c.uri;
    s.endpointUrl = c.url();
    s.nodeId = test::NoOpComponent::moveSkill();
    return s;
}

// How many sessions the component's server has now.
std::size_t sessionsAt(test::NoOpComponent& c) {
    return c.server->inServer([](ua::Server& s) { return s.sessionCount(); });
}

class SkillConnectionPoolTest : public testing::Test {
protected:
    test::ClientThread thread_;
    std::unique_ptr<SkillConnectionPool> pool_;

    void makePool(std::chrono::milliseconds keep) {
        pool_ = std::make_unique<SkillConnectionPool>(
            thread_.io().get_executor(), ua::ClientConfig{}, skills::SkillClientOptions{}, keep);
    }
    // Takes a connection to `skill`, runs the skill once through it, gives it back.
    bool runOnce(const skills::SkillInstance& skill, std::string* why) {
        return thread_.run([&]() -> asio::awaitable<bool> {
            auto c = co_await pool_->take(skill, why);
            if (!c) co_return false;
            const auto outcome = co_await (*c)->skill().run({}, 5s);
            co_await pool_->giveBack(skill, std::move(*c));
            co_return outcome.ok();
        });
    }
    // A pool keeping its connections 30 s, and one connection kept in it: to `component`'s
    // Move, after a run through it.
    skills::SkillInstance keepOneTo(const test::NoOpComponent& component) {
        makePool(30s);
        auto skill = moveOf(component);
        std::string why;
        EXPECT_TRUE(runOnce(skill, &why)) << why;
        EXPECT_EQ(pool_->idleCount(), 1U);
        return skill;
    }
    void TearDown() override {
        thread_.run([&]() -> asio::awaitable<int> {
            co_await pool_->closeAll();
            co_return 0;
        });
    }
};

TEST_F(SkillConnectionPoolTest, ASkillGivenBackIsTakenAgainWithoutANewSession) {
    test::NoOpComponent component("urn:skillcell:test:pool", 0ms);
    makePool(30s);
    const auto skill = moveOf(component);
    std::string why;
    ASSERT_TRUE(runOnce(skill, &why)) << why;
    EXPECT_EQ(pool_->idleCount(), 1U);
    EXPECT_EQ(sessionsAt(component), 1U);
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(runOnce(skill, &why)) << why;
    EXPECT_EQ(pool_->opened(), 1U);
    EXPECT_EQ(pool_->reused(), 3U);
    EXPECT_EQ(sessionsAt(component), 1U) << "every run on the one session";
}

TEST_F(SkillConnectionPoolTest, AConnectionWhoseComponentWentAwayIsNotHandedOut) {
    auto component = std::make_unique<test::NoOpComponent>("urn:skillcell:test:pool", 0ms);
    makePool(30s);
    const auto skill = moveOf(*component);
    std::string why;
    ASSERT_TRUE(runOnce(skill, &why)) << why;
    ASSERT_EQ(pool_->idleCount(), 1U);
    component.reset();  // the component leaves; its port refuses from now on
    const bool taken = thread_.run([&]() -> asio::awaitable<bool> {
        auto c = co_await pool_->take(skill, &why);
        co_return static_cast<bool>(c);
    });
    EXPECT_FALSE(taken) << "a dead session was handed out";
    EXPECT_EQ(pool_->reused(), 0U);
    EXPECT_EQ(pool_->opened(), 2U) << "a new connection was tried instead";
    EXPECT_EQ(pool_->idleCount(), 0U);
    EXPECT_NE(why.find("cannot connect"), std::string::npos) << why;
}

TEST_F(SkillConnectionPoolTest, WithoutKeepingTimeEveryConnectionIsClosedWhenGivenBack) {
    test::NoOpComponent component("urn:skillcell:test:pool", 0ms);
    makePool(0ms);
    const auto skill = moveOf(component);
    std::string why;
    ASSERT_TRUE(runOnce(skill, &why)) << why;
    ASSERT_TRUE(runOnce(skill, &why)) << why;
    EXPECT_EQ(pool_->idleCount(), 0U);
    EXPECT_EQ(pool_->opened(), 2U);
    EXPECT_EQ(sessionsAt(component), 0U);
}

TEST_F(SkillConnectionPoolTest, AKeptSessionIsProvenByTheTakersOwnFirstRequests) {
    test::NoOpComponent component("urn:skillcell:test:pool", 0ms);
    const auto skill = keepOneTo(component);
    std::string why;
    int runs = 0;
    bool read = false;
    const bool taken = thread_.run([&]() -> asio::awaitable<bool> {
        auto first = [&runs, &read](skills::SkillConnection& c) -> asio::awaitable<bool> {
            ++runs;
            read = (co_await c.lastTransitionTime()).ok();
            co_return read;
        };
        auto c = co_await pool_->take(skill, &why, first);
        if (!c) co_return false;
        co_await pool_->giveBack(skill, std::move(*c));
        co_return true;
    });
    ASSERT_TRUE(taken) << why;
    EXPECT_EQ(runs, 1) << "the taker's requests ran once, and no probe of the pool's own";
    EXPECT_TRUE(read);
    EXPECT_EQ(pool_->reused(), 1U);
    EXPECT_EQ(pool_->opened(), 1U);
}

TEST_F(SkillConnectionPoolTest, AKeptSessionThatDidNotAnswerIsReplacedAndTheRequestsRunAgain) {
    test::NoOpComponent component("urn:skillcell:test:pool", 0ms);
    const auto skill = keepOneTo(component);
    std::string why;
    std::vector<bool> answers{false, true};  // the kept session's, then the new one's
    std::size_t runs = 0;
    const bool taken = thread_.run([&]() -> asio::awaitable<bool> {
        auto first = [&](skills::SkillConnection&) -> asio::awaitable<bool> {
            co_return answers.at(runs++);
        };
        auto c = co_await pool_->take(skill, &why, first);
        if (!c) co_return false;
        const auto outcome = co_await (*c)->skill().run({}, 5s);
        co_await pool_->giveBack(skill, std::move(*c));
        co_return outcome.ok();
    });
    ASSERT_TRUE(taken) << why;
    EXPECT_EQ(runs, 2U) << "run on the kept session, then on the new one";
    EXPECT_EQ(pool_->reused(), 0U);
    EXPECT_EQ(pool_->opened(), 2U);
    EXPECT_EQ(sessionsAt(component), 1U) << "the kept session that did not answer was closed";
}

}  // namespace
}  // namespace skillcell::mes
