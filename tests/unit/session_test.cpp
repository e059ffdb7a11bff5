// SessionManager on its own, with time points made up by the test (no waiting).
#include <gtest/gtest.h>

#include "ua/server/session_manager.hpp"

namespace session_test {

using namespace skillcell::ua;
using namespace std::chrono_literals;

namespace {

CreateSessionRequest request(double timeoutMs) {
    CreateSessionRequest r;
    r.sessionName = "s";
    r.requestedSessionTimeout = timeoutMs;
    return r;
}

}  // namespace

TEST(SessionManager, TimeoutIsClampedToTheServerLimits) {
    ServerLimits limits;
    limits.minSessionTimeoutMs = 1000;
    limits.maxSessionTimeoutMs = 5000;
    SessionManager m(limits);
    const auto now = SessionManager::Clock::now();
    EXPECT_EQ((*m.create(request(10), 1, now))->timeout(), 1000ms);
    EXPECT_EQ((*m.create(request(1e9), 1, now))->timeout(), 5000ms);
    EXPECT_EQ((*m.create(request(-1), 1, now))->timeout(), 1000ms);
    EXPECT_EQ((*m.create(request(std::numeric_limits<double>::quiet_NaN()), 1, now))->timeout(),
              1000ms);
}

TEST(SessionManager, SessionLimit) {
    ServerLimits limits;
    limits.maxSessions = 2;
    SessionManager m(limits);
    const auto now = SessionManager::Clock::now();
    ASSERT_TRUE(m.create(request(2000), 1, now));
    ASSERT_TRUE(m.create(request(2000), 1, now));
    EXPECT_EQ(m.create(request(2000), 1, now).status(), status::BadTooManySessions);
}

TEST(SessionManager, AuthorizeChecksActivationChannelAndExpiry) {
    ServerLimits limits;
    SessionManager m(limits);
    const auto t0 = SessionManager::Clock::now();
    Session* s = *m.create(request(2000), 7, t0);
    const NodeId token = s->authenticationToken();
    EXPECT_EQ(m.authorize(token, 7, t0).status(), status::BadSessionNotActivated);
    s->activate(7);
    EXPECT_TRUE(m.authorize(token, 7, t0));
    EXPECT_EQ(m.authorize(token, 8, t0).status(), status::BadSecureChannelIdInvalid);
    EXPECT_EQ(m.authorize(NodeId(0, 1234u), 7, t0).status(), status::BadSessionIdInvalid);

    // Each request restarts the timeout.
    EXPECT_TRUE(m.authorize(token, 7, t0 + 1500ms));
    EXPECT_TRUE(m.authorize(token, 7, t0 + 3000ms));
    EXPECT_EQ(m.expire(t0 + 4000ms), 0u);
    EXPECT_EQ(m.authorize(token, 7, t0 + 5001ms).status(), status::BadSessionIdInvalid);
    EXPECT_EQ(m.expire(t0 + 5001ms), 1u);
    EXPECT_EQ(m.size(), 0u);
}

// The server's reaper sleeps until nextExpiry(), and a new session wakes it to look again.
TEST(SessionManager, NextExpiryIsTheFirstSessionsTimeoutAndACreationWakesItsWaiter) {
    ServerLimits limits;
    SessionManager m(limits);
    int wakeups = 0;
    m.setWakeup([&] { ++wakeups; });
    EXPECT_FALSE(m.nextExpiry());
    const auto t0 = SessionManager::Clock::now();
    Session* a = *m.create(request(5000), 1, t0);
    EXPECT_EQ(m.nextExpiry(), t0 + 5000ms);
    (void)*m.create(request(2000), 1, t0 + 1s);
    EXPECT_EQ(wakeups, 2);
    EXPECT_EQ(m.nextExpiry(), t0 + 3000ms);
    EXPECT_EQ(m.expire(t0 + 3000ms), 0u);  // at its deadline still alive
    EXPECT_EQ(m.expire(t0 + 3001ms), 1u);
    a->touch(t0 + 4s);  // used: its deadline moves on
    EXPECT_EQ(m.nextExpiry(), t0 + 9000ms);
    EXPECT_EQ(m.expire(t0 + 9001ms), 1u);
    EXPECT_FALSE(m.nextExpiry());
}

TEST(SessionManager, TokensAreUnpredictableAndDistinct) {
    ServerLimits limits;
    SessionManager m(limits);
    const auto now = SessionManager::Clock::now();
    const NodeId a = (*m.create(request(2000), 1, now))->authenticationToken();
    const NodeId b = (*m.create(request(2000), 1, now))->authenticationToken();
    EXPECT_NE(a, b);
    EXPECT_EQ(a.idType(), NodeId::IdType::Opaque);
    EXPECT_EQ(std::get<ByteString>(a.identifier()).size(), 32u);
}

TEST(SessionManager, CloseRemovesTheSession) {
    ServerLimits limits;
    SessionManager m(limits);
    const auto now = SessionManager::Clock::now();
    Session* s = *m.create(request(2000), 1, now);
    s->activate(1);
    const NodeId token = s->authenticationToken();
    m.close(token);
    EXPECT_EQ(m.authorize(token, 1, now).status(), status::BadSessionIdInvalid);
}

}  // namespace session_test
