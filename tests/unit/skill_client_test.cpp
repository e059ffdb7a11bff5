// SkillClient against real skills: a whole invocation, and every way one can go wrong:
// Halted with a reason, a refused parameter, a refused Start, a timeout, a cancellation,
// another client halting the run, the server stopping and the server process killed; and a
// run whose end event is lost on the way (a proxy drops the server's Publish responses).
#include <gtest/gtest.h>

#include <asio/co_spawn.hpp>
#include <asio/executor_work_guard.hpp>
#include <asio/use_future.hpp>
#include <atomic>
#include <cstring>
#include <thread>

#include "client_thread.hpp"
#include "component_process.hpp"
#include "running_server.hpp"
#include "skills/noop_behaviour.hpp"
#include "skills/skill_client.hpp"
#include "skills/skill_server.hpp"
#include "tampering_proxy.hpp"

namespace skillcell::skills::skill_client_test {
namespace {

using namespace std::chrono_literals;
using test::ClientThread;
using test::RunningServer;
using ua::NodeId;
using ua::Variant;
namespace status = ua::status;
using Kind = SkillOutcome::Kind;

class FailingBehaviour final : public SkillBehaviour {
public:
    void start(const SkillParameters&, SkillRun run) override { run.failed("gripper jammed"); }
};

/// Runs until halted: a skill that never ends by itself.
class EndlessBehaviour final : public SkillBehaviour {
public:
    void start(const SkillParameters&, SkillRun) override {}
};

/// A server with one skill of each behaviour.
class Cell {
public:
    Cell()
        : server_(RunningServer::defaultConfig(), [this](ua::Server& s) {
              skills_ = SkillServer::create(s, s.executor());
              ASSERT_TRUE(skills_);
              const auto move = skills_->findSkillType("CartesianLinearMoveSkillType");
              const auto grasp = skills_->findSkillType("GraspGripperSkillType");
              ASSERT_TRUE(move && grasp);
              ASSERT_TRUE(
                  skills_->add(*move, "Move", std::make_unique<NoOpBehaviour>(s.executor(), 5ms)));
              ASSERT_TRUE(skills_->add(*grasp, "Grasp", std::make_unique<FailingBehaviour>()));
              ASSERT_TRUE(skills_->add(*move, "Endless", std::make_unique<EndlessBehaviour>()));
              ASSERT_TRUE(skills_->add(*move, "Slow",
                                       std::make_unique<NoOpBehaviour>(s.executor(), 300ms)));
          }) {}
    /// Skills (their behaviours' timers) go before the server's io_context, on its thread.
    ~Cell() {
        server_.inServer([this](ua::Server&) {
            skills_.reset();
            return 0;
        });
    }
    Cell(const Cell&) = delete;
    Cell& operator=(const Cell&) = delete;
    std::string url() const { return server_.url(); }
    std::uint16_t port() const { return server_.port(); }
    SkillState state(const std::string& skill) {
        return server_.inServer([&](ua::Server&) {
            for (const auto& s : skills_->skills()) {
                if (s->name() == skill) return s->state();
            }
            return SkillState::Halted;
        });
    }
    void fault(const std::string& skill, const std::string& reason) {
        server_.inServer([&](ua::Server&) {
            for (const auto& s : skills_->skills()) {
                if (s->name() == skill) s->fault(reason);
            }
            return 0;
        });
    }
    static NodeId id(const std::string& skill) { return NodeId(1, ua::String("Skills/" + skill)); }

private:
    std::unique_ptr<SkillServer> skills_;
    RunningServer server_;
};

TEST(SkillClient, RunsASkillToTheEnd) {
    Cell cell;
    ClientThread t;
    auto move = t.attach(cell.url(), Cell::id("Move"));
    ASSERT_TRUE(move);
    EXPECT_EQ(move->state(), SkillState::Ready);
    EXPECT_EQ(move->parameters().size(), 7u);  // with Reach and ReachCentre, read-only
    for (int i = 0; i < 3; ++i) {              // back to back: each run finds its own end
        const auto outcome = t.invoke(move, {{"MaxVelocity", 0.25}}, 5s);
        EXPECT_EQ(outcome.kind, Kind::Finished) << name(outcome.kind) << " " << outcome.reason;
    }
    EXPECT_EQ(cell.state("Move"), SkillState::Ready);
    // The events came in order: ReadyToRunning, RunningToReady, three times.
    const auto transitions = t.run([&]() -> asio::awaitable<std::deque<SkillTransitionRecord>> {
        co_return move->transitions();
    });
    ASSERT_EQ(transitions.size(), 6u);
    EXPECT_EQ(transitions[0].transition, SkillTransition::ReadyToRunning);
    EXPECT_EQ(transitions[5].transition, SkillTransition::RunningToReady);
}

TEST(SkillClient, ReportsHaltedWithTheReason) {
    Cell cell;
    ClientThread t;
    auto grasp = t.attach(cell.url(), Cell::id("Grasp"));
    ASSERT_TRUE(grasp);
    const auto outcome = t.invoke(grasp, {}, 5s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_EQ(outcome.reason, "gripper jammed");
    EXPECT_EQ(cell.state("Grasp"), SkillState::Halted);
    // Halted refuses Start until Reset.
    const auto again = t.invoke(grasp, {}, 5s);
    EXPECT_EQ(again.kind, Kind::Refused);
    EXPECT_EQ(again.status, status::BadInvalidState);
}

TEST(SkillClient, ReportsARefusedParameter) {
    Cell cell;
    ClientThread t;
    auto move = t.attach(cell.url(), Cell::id("Move"));
    ASSERT_TRUE(move);
    auto outcome = t.invoke(move, {{"MaxVelocity", 99.0}}, 5s);
    EXPECT_EQ(outcome.kind, Kind::Refused);
    EXPECT_EQ(outcome.status, status::BadOutOfRange);
    outcome = t.invoke(move, {{"NoSuchParameter", 1.0}}, 5s);
    EXPECT_EQ(outcome.kind, Kind::Refused);
    EXPECT_EQ(outcome.status, status::BadNoMatch);
    EXPECT_EQ(cell.state("Move"), SkillState::Ready);  // nothing started
}

TEST(SkillClient, WritesItsParametersInOneRequestAndNamesTheOneRefused) {
    Cell cell;
    ClientThread t;
    auto move = t.attach(cell.url(), Cell::id("Move"));
    ASSERT_TRUE(move);
    // Reach is read-only: the server refuses that one of the request's values, not the other.
    auto outcome = t.invoke(move, {{"MaxVelocity", 0.25}, {"Reach", 1.0}}, 5s);
    EXPECT_EQ(outcome.kind, Kind::Refused);
    EXPECT_TRUE(outcome.status.isBad());
    EXPECT_EQ(outcome.reason, "parameter Reach refused");
    EXPECT_EQ(cell.state("Move"), SkillState::Ready);  // nothing started
    outcome = t.invoke(move, {{"MaxVelocity", 0.5}}, 5s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
}

TEST(SkillClient, HaltsTheSkillWhenTheTimeoutExpires) {
    Cell cell;
    ClientThread t;
    auto endless = t.attach(cell.url(), Cell::id("Endless"));
    ASSERT_TRUE(endless);
    const auto outcome = t.invoke(endless, {}, 100ms);
    EXPECT_EQ(outcome.kind, Kind::TimedOut);
    EXPECT_EQ(outcome.status, status::Good);  // the Halt went through
    EXPECT_EQ(cell.state("Endless"), SkillState::Halted);
}

TEST(SkillClient, CancelHaltsTheSkill) {
    Cell cell;
    ClientThread t;
    auto endless = t.attach(cell.url(), Cell::id("Endless"));
    ASSERT_TRUE(endless);
    auto future = asio::co_spawn(
        t.io(),
        [&]() -> asio::awaitable<SkillOutcome> { co_return co_await endless->run({}, 30s); },
        asio::use_future);
    // Cancel once the run is under way (the server says Running).
    for (int i = 0; i < 2000 && cell.state("Endless") != SkillState::Running; ++i) {
        std::this_thread::sleep_for(1ms);
    }
    ASSERT_EQ(cell.state("Endless"), SkillState::Running);
    asio::post(t.io(), [endless] { endless->cancel(); });
    ASSERT_EQ(future.wait_for(5s), std::future_status::ready);
    EXPECT_EQ(future.get().kind, Kind::Cancelled);
    EXPECT_EQ(cell.state("Endless"), SkillState::Halted);
}

TEST(SkillClient, ACancelWhileTheStartIsOnItsWayIsNotLost) {
    Cell cell;
    ClientThread t;
    auto endless = t.attach(cell.url(), Cell::id("Endless"));
    ASSERT_TRUE(endless);
    auto future = asio::co_spawn(
        t.io(),
        [&]() -> asio::awaitable<SkillOutcome> { co_return co_await endless->run({}, 30s); },
        asio::use_future);
    // Runs on the client's thread once run() has sent Start and waits for its answer.
    asio::post(t.io(), [endless] { endless->cancel(); });
    ASSERT_EQ(future.wait_for(10s), std::future_status::ready) << "the cancel was lost";
    EXPECT_EQ(future.get().kind, Kind::Cancelled);
    EXPECT_EQ(cell.state("Endless"), SkillState::Halted);
}

TEST(SkillClient, ReportsAHaltByTheComponentAsFailed) {
    Cell cell;
    ClientThread owner, other;
    auto endless = owner.attach(cell.url(), Cell::id("Endless"));
    ASSERT_TRUE(endless);
    auto future = asio::co_spawn(
        owner.io(),
        [&]() -> asio::awaitable<SkillOutcome> { co_return co_await endless->run({}, 30s); },
        asio::use_future);
    for (int i = 0; i < 2000 && cell.state("Endless") != SkillState::Running; ++i) {
        std::this_thread::sleep_for(1ms);
    }
    // The other client's session cannot halt it (reserved); the component itself can.
    auto view = other.attach(cell.url(), Cell::id("Endless"));
    ASSERT_TRUE(view);
    EXPECT_EQ(other.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await view->call(SkillMethod::Halt);
    }),
              status::BadUserAccessDenied);
    cell.fault("Endless", "light curtain interrupted");
    ASSERT_EQ(future.wait_for(5s), std::future_status::ready);
    const auto outcome = future.get();
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_EQ(outcome.reason, "light curtain interrupted");
}

TEST(SkillClient, ReportsAStoppedServerAsLost) {
    auto cell = std::make_unique<Cell>();
    ClientThread t;
    auto endless = t.attach(cell->url(), Cell::id("Endless"));
    ASSERT_TRUE(endless);
    auto future = asio::co_spawn(
        t.io(),
        [&]() -> asio::awaitable<SkillOutcome> { co_return co_await endless->run({}, 60s); },
        asio::use_future);
    for (int i = 0; i < 2000 && cell->state("Endless") != SkillState::Running; ++i) {
        std::this_thread::sleep_for(1ms);
    }
    cell.reset();  // the server goes away mid-run
    ASSERT_EQ(future.wait_for(10s), std::future_status::ready);
    const auto outcome = future.get();
    EXPECT_EQ(outcome.kind, Kind::Lost) << name(outcome.kind);
    EXPECT_TRUE(outcome.status.isBad());
}

/// A `skillcell server` with one skill that runs for a minute: killed mid-run by the test.
struct ServerProcess : test::ComponentProcess {
    ServerProcess()
        : test::ComponentProcess(SKILLCELL_BINARY,
                                 {"server", "--noop-skill", "JointPtpMoveSkillType=Slow",
                                  "--noop-skill-ms", "60000"}) {}
};

TEST(SkillClient, ReportsAKilledServerProcessAsLost) {
    ServerProcess process;
    ASSERT_FALSE(process.url().empty());
    ClientThread t;
    auto slow = t.attach(process.url(), Cell::id("Slow"));
    ASSERT_TRUE(slow);
    auto future = asio::co_spawn(
        t.io(), [&]() -> asio::awaitable<SkillOutcome> { co_return co_await slow->run({}, 60s); },
        asio::use_future);
    // Kill once the run is under way (the client has seen ReadyToRunning).
    for (int i = 0; i < 2000; ++i) {
        const bool running = t.run(
            [&]() -> asio::awaitable<bool> { co_return slow->state() == SkillState::Running; });
        if (running) break;
        std::this_thread::sleep_for(1ms);
    }
    process.kill();
    ASSERT_EQ(future.wait_for(10s), std::future_status::ready);
    EXPECT_EQ(future.get().kind, Kind::Lost);
}

}  // namespace
}  // namespace skillcell::skills::skill_client_test

namespace skillcell::skills::skill_client_test {
namespace {

/// The server's side of a TamperingProxy that, while `dropping`, loses every Publish and
/// Republish response (so events, and the gaps' second chances, never arrive) and renumbers
/// the channel's sequence numbers after them, as if they had never been sent. SecurityPolicy
/// None only (the chunks are read).
class PublishDropper {
public:
    std::vector<test::TamperingProxy::Frame> operator()(std::size_t,
                                                        test::TamperingProxy::Frame f) {
        if (f.size() < 28 || std::memcmp(f.data(), "MSG", 3) != 0) return {std::move(f)};
        // Body after the header (8), channel id (4), token id (4), sequence number and request
        // id (8): the type's NodeId, FourByte-encoded (0x01, namespace 0, id).
        const unsigned type = f[26] | (f[27] << 8U);
        const bool publish = f[24] == 0x01 && f[25] == 0 && (type == 829 || type == 835);
        if (dropping && publish && f[3] == 'F') {
            ++removed_;
            ++dropped;
            return {};
        }
        std::uint32_t seq = 0;
        std::memcpy(&seq, f.data() + 16, 4);  // little-endian, as this machine
        seq -= removed_;
        std::memcpy(f.data() + 16, &seq, 4);
        return {std::move(f)};
    }

    std::atomic<bool> dropping{false};
    std::atomic<int> dropped{0};

private:
    std::uint32_t removed_ = 0;  // the proxy's server thread only
};

// Reads back race the events: an end read just before its event arrives waits for the event,
// which carries the reason. Reading every millisecond makes the race happen every time.
TEST(SkillClient, AnEndReadBackStillReportsTheReasonItsEventBrings) {
    Cell cell;
    ClientThread t;
    SkillClientOptions eager;
    eager.confirmAfter = 1ms;
    auto grasp = t.attach(cell.url(), Cell::id("Grasp"), eager);
    auto slow = t.attach(cell.url(), Cell::id("Slow"), eager);
    ASSERT_TRUE(grasp && slow);
    for (int i = 0; i < 5; ++i) {
        const auto outcome = t.invoke(grasp, {}, 10s);
        EXPECT_EQ(outcome.kind, Kind::Failed);
        EXPECT_EQ(outcome.reason, "gripper jammed") << "run " << i;
        ASSERT_EQ(t.run([&]() -> asio::awaitable<ua::StatusCode> {
            co_return co_await grasp->call(SkillMethod::Reset);
        }),
                  status::Good);
    }
    const auto finished = t.invoke(slow, {}, 10s);
    EXPECT_EQ(finished.kind, Kind::Finished) << finished.reason;
}

TEST(SkillClient, ARunWhoseEndEventIsLostEndsByReadingTheSkillBack) {
    Cell cell;
    PublishDropper dropper;
    test::TamperingProxy proxy(
        cell.port(),
        [](std::size_t, test::TamperingProxy::Frame f) {
            return std::vector<test::TamperingProxy::Frame>{std::move(f)};
        },
        [&dropper](std::size_t i, test::TamperingProxy::Frame f) {
            return dropper(i, std::move(f));
        });
    const std::string url = "opc.tcp://127.0.0.1:" + std::to_string(proxy.port());
    ClientThread t;
    auto slow = t.attach(url, Cell::id("Slow"));
    auto grasp = t.attach(url, Cell::id("Grasp"));
    ASSERT_TRUE(slow && grasp);

    // From now on no event arrives: the end of a 300 ms run is read back within about a second
    // of quiet, long before the 10 s timeout.
    dropper.dropping = true;
    const auto begin = std::chrono::steady_clock::now();
    const auto outcome = t.invoke(slow, {}, 10s);
    const auto took = std::chrono::steady_clock::now() - begin;
    EXPECT_EQ(outcome.kind, Kind::Finished) << name(outcome.kind) << " " << outcome.reason;
    EXPECT_LT(took, 300ms + 2s);
    EXPECT_GT(dropper.dropped.load(), 0) << "the proxy dropped no Publish response";
    EXPECT_EQ(cell.state("Slow"), SkillState::Ready);

    // An end in Halted, read back, is a failure; its reason stayed with the lost event.
    const auto failed = t.invoke(grasp, {}, 10s);
    EXPECT_EQ(failed.kind, Kind::Failed) << name(failed.kind) << " " << failed.reason;
    EXPECT_NE(failed.reason.find("its event was lost"), std::string::npos) << failed.reason;

    // The proxy passes everything again (the Publish requests whose answers it dropped are
    // sent again only after their timeout): the next run still ends, and the earlier runs'
    // ends, should they arrive late, are not taken for its own.
    dropper.dropping = false;
    const auto again = t.invoke(slow, {}, 10s);
    EXPECT_EQ(again.kind, Kind::Finished) << name(again.kind) << " " << again.reason;
}

}  // namespace
}  // namespace skillcell::skills::skill_client_test
