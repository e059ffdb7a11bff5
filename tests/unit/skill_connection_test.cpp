// SkillConnection: a second skill of the same component goes over the first one's session
// (alongside): one session at the server for both, each skill runs through its own
// SkillClient, the session stays while either is open and ends with the last close; a type
// the component does not offer is refused with its name, and the session is unharmed.
#include "skills/skill_connection.hpp"

#include <gtest/gtest.h>

#include "client_thread.hpp"
#include "noop_component.hpp"

namespace skillcell::skills::skill_connection_test {
namespace {

using namespace std::chrono_literals;

std::size_t sessionsAt(test::NoOpComponent& c) {
    return c.server->inServer([](ua::Server& s) { return s.sessionCount(); });
}

TEST(SkillConnection, AnotherSkillOfTheComponentSharesTheSessionUntilTheLastCloses) {
    test::NoOpComponent component("urn:skillcell:test:alongside", 0ms);
    component.server->inServer([&](ua::Server& s) {
        const auto type = component.skills->findSkillType("CartesianPtpMoveSkillType");
        EXPECT_TRUE(type);
        if (type) {
            (void)component.skills->add(*type, "Ptp",
                                        std::make_unique<NoOpBehaviour>(s.executor(), 0ms));
        }
        return 0;
    });
    test::ClientThread thread;
    std::unique_ptr<SkillConnection> linear;
    std::unique_ptr<SkillConnection> ptp;
    std::string why;
    ASSERT_TRUE(thread.run([&]() -> asio::awaitable<bool> {
        auto opened = co_await SkillConnection::open(thread.io().get_executor(), component.url(),
                                                     "CartesianLinearMoveSkillType",
                                                     ua::ClientConfig{}, &why);
        if (!opened) co_return false;
        linear = std::move(*opened);
        auto other = co_await linear->alongside("CartesianPtpMoveSkillType", &why);
        if (!other) co_return false;
        ptp = std::move(*other);
        co_return true;
    })) << why;
    EXPECT_EQ(sessionsAt(component), 1U);
    EXPECT_EQ(ptp->description().browsePathString(), "Skills/Ptp");
    EXPECT_EQ(&ptp->client(), &linear->client());

    // A type it does not offer: refused by name; the shared session goes on.
    ua::StatusCode missing;
    thread.run([&]() -> asio::awaitable<int> {
        auto none = co_await linear->alongside("GraspGripperSkillType", &why);
        missing = none.status();
        co_return 0;
    });
    EXPECT_EQ(missing, ua::status::BadNotFound);
    EXPECT_NE(why.find("offers no GraspGripperSkillType"), std::string::npos) << why;

    const auto runs = [&](SkillConnection& c) {
        return thread.run(
            [&]() -> asio::awaitable<bool> { co_return (co_await c.skill().run({}, 5s)).ok(); });
    };
    EXPECT_TRUE(runs(*linear));
    EXPECT_TRUE(runs(*ptp));
    thread.run([&]() -> asio::awaitable<int> {
        co_await ptp->close();
        co_return 0;
    });
    EXPECT_EQ(sessionsAt(component), 1U);  // the linear move still uses it
    EXPECT_TRUE(runs(*linear));
    thread.run([&]() -> asio::awaitable<int> {
        co_await linear->close();
        co_await linear->close();  // a second close does nothing
        co_return 0;
    });
    EXPECT_EQ(sessionsAt(component), 0U);
}

}  // namespace
}  // namespace skillcell::skills::skill_connection_test
