// The server-side Skill through the OPC UA services, as a client sees it: every transition
// of the program state machine with its event and variables, every forbidden method,
// parameter checks on write and on Start, values fixed at Start, reservation by the
// starting session, and two clients racing for one skill.
#include <gtest/gtest.h>

#include <array>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "running_server.hpp"
#include "skills/reservation_client.hpp"
#include "skills/skill_server.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::skills::skill_test {
namespace {

using namespace std::chrono_literals;
using test::RunningServer;
using ua::BlockingClient;
using ua::NodeId;
using ua::QualifiedName;
using ua::StatusCode;
using ua::Variant;
namespace status = ua::status;

/// What the behaviour was told, and the run it holds, shared with the test thread.
struct Probe {
    std::mutex mutex;
    int starts = 0, suspends = 0, resumes = 0, halts = 0, resets = 0;
    SkillRun run;
    SkillParameters parameters;
};

class ProbeBehaviour final : public SkillBehaviour {
public:
    explicit ProbeBehaviour(std::shared_ptr<Probe> probe) : probe_(std::move(probe)) {}
    void start(const SkillParameters& parameters, SkillRun run) override {
        const std::lock_guard lock(probe_->mutex);
        ++probe_->starts;
        probe_->run = run;
        probe_->parameters = parameters;
    }
    void suspend() override { bump(&Probe::suspends); }
    void resume() override { bump(&Probe::resumes); }
    void halt() override { bump(&Probe::halts); }
    void reset() override { bump(&Probe::resets); }

private:
    void bump(int Probe::*counter) {
        const std::lock_guard lock(probe_->mutex);
        ++(*probe_.*counter);
    }
    std::shared_ptr<Probe> probe_;
};

struct ReceivedEvent {
    std::string message;
    NodeId from, to, transition, eventType;
};

/// Collects a skill's transition events on a client's subscription.
class EventLog {
public:
    void add(const std::vector<Variant>& fields) {
        ReceivedEvent e;
        if (const auto* m = fields[0].get<ua::LocalizedText>()) e.message = m->text;
        if (const auto* id = fields[1].get<NodeId>()) e.from = *id;
        if (const auto* id = fields[2].get<NodeId>()) e.to = *id;
        if (const auto* id = fields[3].get<NodeId>()) e.transition = *id;
        if (const auto* id = fields[4].get<NodeId>()) e.eventType = *id;
        const std::lock_guard lock(mutex_);
        events_.push_back(std::move(e));
        cv_.notify_all();
    }
    /// Waits (up to 5 s) for the n-th event (0-based).
    std::optional<ReceivedEvent> at(std::size_t n) {
        std::unique_lock lock(mutex_);
        if (!cv_.wait_for(lock, 5s, [&] { return events_.size() > n; })) return std::nullopt;
        return events_[n];
    }
    std::size_t size() {
        const std::lock_guard lock(mutex_);
        return events_.size();
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    std::vector<ReceivedEvent> events_;
};

ua::EventFilter transitionFilter() {
    ua::EventFilter f;
    auto select = [&f](std::uint32_t type, std::vector<QualifiedName> path) {
        ua::SimpleAttributeOperand op;
        op.typeDefinitionId = NodeId(type);
        op.browsePath = std::move(path);
        f.selectClauses.push_back(std::move(op));
    };
    select(2041, {{0, "Message"}});
    select(2311, {{0, "FromState"}, {0, "Id"}});
    select(2311, {{0, "ToState"}, {0, "Id"}});
    select(2311, {{0, "Transition"}, {0, "Id"}});
    select(2041, {{0, "EventType"}});
    return f;
}

NodeId child(const NodeId& skill, const std::string& path) {
    NodeId id = skill;
    std::size_t begin = 0;
    for (;;) {
        const auto end = path.find('/', begin);
        id = ua::AddressSpace::childNodeId(id, path.substr(begin, end - begin));
        if (end == std::string::npos) return id;
        begin = end + 1;
    }
}

class SkillTest : public ::testing::Test {
protected:
    SkillTest()
        : probe_(std::make_shared<Probe>()),
          server_(RunningServer::defaultConfig(), [this](ua::Server& server) {
              skills_ = SkillServer::create(server, server.executor());
              ASSERT_TRUE(skills_);
              const auto type = skills_->findSkillType("CartesianLinearMoveSkillType");
              ASSERT_TRUE(type);
              auto skill = skills_->add(*type, "Move", std::make_unique<ProbeBehaviour>(probe_));
              ASSERT_TRUE(skill) << ua::statusName(skill.status());
              skill_ = *skill;
              eventType_ = *ua::skillsNodeId(server.addressSpace(),
                                             ua::companion::kSkillTransitionEventType);
          }) {
        EXPECT_EQ(client_.connect(server_.url()), status::Good);
        id_ = skill_->nodeId();
    }

    ~SkillTest() override {
        server_.inServer([this](ua::Server&) {
            skill_.reset();
            skills_.reset();
            return 0;
        });
    }

    StatusCode call(BlockingClient& c, SkillMethod m) {
        auto r = c.call(id_, child(id_, std::string(name(m))), {});
        return r ? StatusCode(status::Good) : r.status();
    }
    StatusCode call(SkillMethod m) { return call(client_, m); }
    SkillState serverState() {
        return server_.inServer([this](ua::Server&) { return skill_->state(); });
    }
    std::string readText(const std::string& path) {
        auto v = client_.readValue(child(id_, path));
        if (!v || v->get<ua::LocalizedText>() == nullptr) return "<none>";
        return v->get<ua::LocalizedText>()->text;
    }
    void subscribe(EventLog& log) {
        auto sub = client_.createSubscription(ua::SubscriptionSettings(20, 300, 10));
        ASSERT_TRUE(sub);
        subscription_ = *sub;
        ASSERT_TRUE(client_.monitorEvents(subscription_, id_, transitionFilter(),
                                          [&log](const std::vector<Variant>& f) { log.add(f); }));
    }
    /// Waits until the server's skill is in `state` (reports are posted to its thread).
    bool awaitState(SkillState state) {
        for (int i = 0; i < 500; ++i) {
            if (serverState() == state) return true;
            std::this_thread::yield();
        }
        return serverState() == state;
    }
    SkillRun currentRun() {
        const std::lock_guard lock(probe_->mutex);
        return probe_->run;
    }

    std::shared_ptr<Probe> probe_;
    std::unique_ptr<SkillServer> skills_;
    std::shared_ptr<Skill> skill_;
    NodeId eventType_;
    RunningServer server_;
    BlockingClient client_;
    std::shared_ptr<ua::Subscription> subscription_;
    NodeId id_;
};

TEST_F(SkillTest, TheObjectIsAnInstanceOfItsType) {
    EXPECT_EQ(readText("CurrentState"), "Ready");
    EXPECT_EQ(client_.readValue(child(id_, "CurrentState/Id"))->get<NodeId>()[0], NodeId(2400));
    EXPECT_EQ(*client_.readValue(child(id_, "CurrentState/Number"))->get<std::uint32_t>(), 12u);
    for (const char* p :
         {"ToolFrame", "MaxVelocity", "MaxAcceleration", "TargetPosition", "AxisBounds"}) {
        EXPECT_TRUE(client_.readValue(child(id_, std::string("ParameterSet/") + p))) << p;
    }
    auto notifier = client_.readAttribute(id_, ua::AttributeId::EventNotifier);
    ASSERT_TRUE(notifier);
    EXPECT_EQ(*notifier->value->get<std::uint8_t>() & 1, 1);
}

TEST_F(SkillTest, EveryTransitionChangesStateAndSendsItsEvent) {
    EventLog log;
    subscribe(log);
    std::size_t n = 0;
    auto expectTransition = [&](SkillTransition t, const std::string& reasonPart = {}) {
        SCOPED_TRACE(std::string(name(t)));
        auto e = log.at(n++);
        ASSERT_TRUE(e);
        EXPECT_EQ(e->from, stateNodeId(fromState(t)));
        EXPECT_EQ(e->to, stateNodeId(toState(t)));
        EXPECT_EQ(e->transition, transitionNodeId(t));
        EXPECT_EQ(e->eventType, eventType_);
        EXPECT_NE(e->message.find(reasonPart), std::string::npos) << e->message;
        ASSERT_TRUE(awaitState(toState(t)));
        EXPECT_EQ(readText("CurrentState"), name(toState(t)));
        EXPECT_EQ(readText("LastTransition"), name(t));
        EXPECT_EQ(*client_.readValue(child(id_, "LastTransition/Id"))->get<NodeId>(),
                  transitionNodeId(t));
        EXPECT_EQ(*client_.readValue(child(id_, "LastTransition/Number"))->get<std::uint32_t>(),
                  static_cast<std::uint32_t>(t));
        EXPECT_TRUE(
            client_.readValue(child(id_, "LastTransition/TransitionTime"))->get<ua::DateTime>());
    };
    using T = SkillTransition;
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    expectTransition(T::ReadyToRunning);
    ASSERT_EQ(call(SkillMethod::Suspend), status::Good);
    expectTransition(T::RunningToSuspended);
    ASSERT_EQ(call(SkillMethod::Resume), status::Good);
    expectTransition(T::SuspendedToRunning);
    currentRun().finished();
    expectTransition(T::RunningToReady);
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    expectTransition(T::ReadyToRunning);
    currentRun().failed("target unreachable");
    expectTransition(T::RunningToHalted, "target unreachable");
    ASSERT_EQ(call(SkillMethod::Reset), status::Good);
    expectTransition(T::HaltedToReady);
    ASSERT_EQ(call(SkillMethod::Halt), status::Good);
    expectTransition(T::ReadyToHalted);
    ASSERT_EQ(call(SkillMethod::Reset), status::Good);
    expectTransition(T::HaltedToReady);
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    expectTransition(T::ReadyToRunning);
    ASSERT_EQ(call(SkillMethod::Suspend), status::Good);
    expectTransition(T::RunningToSuspended);
    currentRun().finished();
    expectTransition(T::SuspendedToReady);
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    expectTransition(T::ReadyToRunning);
    ASSERT_EQ(call(SkillMethod::Suspend), status::Good);
    expectTransition(T::RunningToSuspended);
    ASSERT_EQ(call(SkillMethod::Halt), status::Good);
    expectTransition(T::SuspendedToHalted, "halted");
    ASSERT_EQ(call(SkillMethod::Reset), status::Good);
    expectTransition(T::HaltedToReady);
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    expectTransition(T::ReadyToRunning);
    ASSERT_EQ(call(SkillMethod::Halt), status::Good);
    expectTransition(T::RunningToHalted, "halted");

    const std::lock_guard lock(probe_->mutex);
    EXPECT_EQ(probe_->starts, 5);
    EXPECT_EQ(probe_->suspends, 3);
    EXPECT_EQ(probe_->resumes, 1);
    EXPECT_EQ(probe_->halts, 2);  // only a Halt that stops a run reaches the behaviour
    EXPECT_EQ(probe_->resets, 3);
}

TEST_F(SkillTest, MethodsTheStateForbidsAreBadInvalidState) {
    using M = SkillMethod;
    auto expectRefused = [&](std::initializer_list<M> methods, SkillState state) {
        for (M m : methods) {
            EXPECT_EQ(call(m), status::BadInvalidState) << name(m) << " in " << name(state);
            EXPECT_EQ(serverState(), state);
        }
    };
    expectRefused({M::Suspend, M::Resume, M::Reset}, SkillState::Ready);
    ASSERT_EQ(call(M::Start), status::Good);
    expectRefused({M::Start, M::Resume, M::Reset}, SkillState::Running);
    ASSERT_EQ(call(M::Suspend), status::Good);
    expectRefused({M::Start, M::Suspend, M::Reset}, SkillState::Suspended);
    ASSERT_EQ(call(M::Halt), status::Good);
    expectRefused({M::Start, M::Suspend, M::Resume, M::Halt}, SkillState::Halted);
}

TEST_F(SkillTest, ParametersAreCheckedOnWrite) {
    const NodeId v = child(id_, "ParameterSet/MaxVelocity");  // EURange 0..2 m/s
    EXPECT_EQ(client_.writeValue(v, 1.5), status::Good);
    EXPECT_EQ(client_.writeValue(v, 2.5), status::BadOutOfRange);
    EXPECT_EQ(client_.writeValue(v, -0.1), status::BadOutOfRange);
    EXPECT_EQ(client_.writeValue(v, std::nan("")), status::BadOutOfRange);
    EXPECT_EQ(client_.writeValue(v, "fast"), status::BadTypeMismatch);
    EXPECT_EQ(*client_.readValue(v)->get<double>(), 1.5);
    const NodeId bounds = child(id_, "ParameterSet/AxisBounds");
    EXPECT_EQ(client_.writeValue(bounds, 1.0), status::BadTypeMismatch);  // needs Range[]
}

TEST_F(SkillTest, StartChecksTheParametersAgainAndFixesThem) {
    const NodeId v = child(id_, "ParameterSet/MaxVelocity");
    // Application code bypasses the write check; Start still refuses the value.
    server_.inServer([&](ua::Server& s) { return s.addressSpace().setValue(v, 7.0); });
    EXPECT_EQ(call(SkillMethod::Start), status::BadOutOfRange);
    EXPECT_EQ(serverState(), SkillState::Ready);

    ASSERT_EQ(client_.writeValue(v, 0.5), status::Good);
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    // The session that started the run may prepare the next one; this run keeps 0.5.
    EXPECT_EQ(client_.writeValue(v, 1.0), status::Good);
    const std::lock_guard lock(probe_->mutex);
    EXPECT_EQ(probe_->parameters.get<double>("MaxVelocity"), 0.5);
    EXPECT_TRUE(probe_->parameters.contains("TargetPosition"));
}

TEST_F(SkillTest, TheStartingSessionReservesTheSkill) {
    BlockingClient other;
    ASSERT_EQ(other.connect(server_.url()), status::Good);
    const NodeId v = child(id_, "ParameterSet/MaxVelocity");
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    EXPECT_EQ(call(other, SkillMethod::Start), status::BadInvalidState);
    EXPECT_EQ(call(other, SkillMethod::Suspend), status::BadUserAccessDenied);
    EXPECT_EQ(call(other, SkillMethod::Halt), status::BadUserAccessDenied);
    EXPECT_EQ(other.writeValue(v, 1.0), status::BadUserAccessDenied);
    ASSERT_EQ(call(SkillMethod::Suspend), status::Good);
    EXPECT_EQ(call(other, SkillMethod::Resume), status::BadUserAccessDenied);
    EXPECT_EQ(call(other, SkillMethod::Halt), status::BadUserAccessDenied);
    EXPECT_EQ(serverState(), SkillState::Suspended);

    // The owner's session closes: its reservation no longer protects the run.
    ASSERT_EQ(client_.disconnect(), status::Good);
    EXPECT_EQ(call(other, SkillMethod::Halt), status::Good);
    EXPECT_EQ(serverState(), SkillState::Halted);
    // No reservation outside a run: anyone may reset and write.
    EXPECT_EQ(call(other, SkillMethod::Reset), status::Good);
    EXPECT_EQ(other.writeValue(v, 1.0), status::Good);
}

// What a composite does before it drives a component: a hold, Reserve through its first
// session and Use through the others. Refused, it says why and nothing stays reserved: held
// by another (naming the holder), or Reserve itself refused (naming the status).
TEST_F(SkillTest, AHoldReservesThroughOneSessionBindsTheOthersAndSaysWhyWhenRefused) {
    struct Seen {
        Hold refusedReserve, first, second, afterRelease;
        std::string holderWhileRefused, holderAfterRefusal, holderAtEnd;
        StatusCode released = status::BadInternalError;
    } seen;
    asio::io_context io(1);
    ua::Client a(io.get_executor());
    ua::Client b(io.get_executor());
    ua::Client c(io.get_executor());
    const std::array<ua::Client*, 3> clients{&a, &b, &c};
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            for (ua::Client* x : clients) {
                if ((co_await x->connect(server_.url())).isBad()) co_return;
            }
            // Named arguments: GCC 12 miscompiles a string literal or a braced list passed
            // to a coroutine inside a co_await expression.
            const std::vector<ua::Client*> ab{&a, &b};
            const std::vector<ua::Client*> justC{&c};
            const std::string nobody;
            const std::string composite = "urn:test:composite";
            const std::string another = "urn:test:another";
            // An empty holder names no one: Reserve refuses it, and the hold says so.
            seen.refusedReserve = co_await hold(ab, nobody);
            seen.holderAfterRefusal = co_await reservationHolder(c);
            seen.first = co_await hold(ab, composite);
            seen.second = co_await hold(justC, another);
            seen.holderWhileRefused = co_await reservationHolder(c);
            if (seen.first.token) seen.released = co_await release(a, *seen.first.token);
            seen.afterRelease = co_await hold(justC, another);
            seen.holderAtEnd = co_await reservationHolder(a);
            for (ua::Client* x : clients) (void)co_await x->disconnect();
            done = true;
        },
        asio::detached);
    io.run_for(30s);
    ASSERT_TRUE(done);

    EXPECT_FALSE(seen.refusedReserve.token);
    EXPECT_EQ(seen.refusedReserve.refusal, "its Reserve was refused (BadInvalidArgument)");
    EXPECT_EQ(seen.holderAfterRefusal, "");
    ASSERT_TRUE(seen.first.token);
    EXPECT_EQ(seen.first.refusal, "");
    EXPECT_FALSE(seen.second.token);
    EXPECT_EQ(seen.second.refusal, "reserved by urn:test:composite (BadResourceUnavailable)");
    EXPECT_EQ(seen.holderWhileRefused, "urn:test:composite");
    EXPECT_EQ(seen.released, status::Good);
    ASSERT_TRUE(seen.afterRelease.token);
    EXPECT_GT(*seen.afterRelease.token, *seen.first.token);  // fencing: tokens only grow
    EXPECT_EQ(seen.holderAtEnd, "urn:test:another");
}

// A holder that dies keeps the component until its sessions time out: a hold with patience
// waits for that, one without is refused at once.
TEST_F(SkillTest, AHoldWithPatienceWaitsForAHolderWhoseSessionEnds) {
    struct Seen {
        Hold impatient, patient;
        std::chrono::milliseconds waited{0};
    } seen;
    asio::io_context io(1);
    ua::Client dying(io.get_executor());
    ua::Client next(io.get_executor());
    ua::ClientConfig shortLease;
    shortLease.sessionTimeoutMs = 1'000;  // the server's least
    bool done = false;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            if ((co_await dying.connect(server_.url(), shortLease)).isBad()) co_return;
            if ((co_await next.connect(server_.url())).isBad()) co_return;
            const std::vector<ua::Client*> first{&dying};
            const std::vector<ua::Client*> second{&next};
            const std::string gone = "urn:test:gone";
            const std::string heir = "urn:test:heir";
            if (!(co_await hold(first, gone)).token) co_return;
            // The holder's process dies: its connection drops, its session lives on until it
            // times out (1 s).
            dying.abort();
            seen.impatient = co_await hold(second, heir);
            const auto start = std::chrono::steady_clock::now();
            seen.patient = co_await hold(second, heir, 10s);
            seen.waited = std::chrono::duration_cast<std::chrono::milliseconds>(
                std::chrono::steady_clock::now() - start);
            (void)co_await next.disconnect();
            done = true;
        },
        asio::detached);
    io.run_for(30s);
    ASSERT_TRUE(done);
    EXPECT_FALSE(seen.impatient.token);
    EXPECT_EQ(seen.impatient.refusal, "reserved by urn:test:gone (BadResourceUnavailable)");
    ASSERT_TRUE(seen.patient.token) << seen.patient.refusal;
    EXPECT_LT(seen.waited, 10s);
}

TEST_F(SkillTest, TwoClientsRacingForOneSkillGetItOneAtATime) {
    BlockingClient a, b;
    ASSERT_EQ(a.connect(server_.url()), status::Good);
    ASSERT_EQ(b.connect(server_.url()), status::Good);
    constexpr int kRounds = 25;
    for (int round = 0; round < kRounds; ++round) {
        StatusCode ra, rb;
        std::thread ta([&] { ra = call(a, SkillMethod::Start); });
        std::thread tb([&] { rb = call(b, SkillMethod::Start); });
        ta.join();
        tb.join();
        ASSERT_NE(ra.isGood(), rb.isGood()) << "round " << round;
        ASSERT_EQ(ra.isGood() ? rb : ra, status::BadInvalidState);
        BlockingClient& winner = ra.isGood() ? a : b;
        BlockingClient& loser = ra.isGood() ? b : a;
        EXPECT_EQ(call(loser, SkillMethod::Halt), status::BadUserAccessDenied);
        ASSERT_EQ(call(winner, SkillMethod::Halt), status::Good);
        ASSERT_EQ(call(loser, SkillMethod::Reset), status::Good);
    }
    const std::lock_guard lock(probe_->mutex);
    EXPECT_EQ(probe_->starts, kRounds);
}

TEST_F(SkillTest, ALateReportOfAHaltedRunDoesNotEndTheNextOne) {
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    const SkillRun first = currentRun();
    ASSERT_EQ(call(SkillMethod::Halt), status::Good);
    ASSERT_EQ(call(SkillMethod::Reset), status::Good);
    ASSERT_EQ(call(SkillMethod::Start), status::Good);
    first.finished();
    first.failed("stale");
    currentRun().finished();  // the current run's report, after the stale ones
    ASSERT_TRUE(awaitState(SkillState::Ready));
    // Had a stale report counted, the run would have ended before its own report; the
    // Halt below would then find the skill Ready and go ReadyToHalted — check directly:
    EXPECT_EQ(readText("LastTransition"), "RunningToReady");
}

TEST_F(SkillTest, ADeviceFaultHaltsTheSkillWithItsReason) {
    EventLog log;
    subscribe(log);
    server_.inServer([this](ua::Server&) {
        skill_->fault("emergency stop pressed");
        return 0;
    });
    auto e = log.at(0);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->transition, transitionNodeId(SkillTransition::ReadyToHalted));
    EXPECT_NE(e->message.find("emergency stop pressed"), std::string::npos);
}

TEST(SkillCreation, OnlyConcreteSkillTypesMakeSkills) {
    RunningServer server(RunningServer::defaultConfig(), [](ua::Server& s) {
        auto skills = SkillServer::create(s, s.executor());
        ASSERT_TRUE(skills);
        auto& as = s.addressSpace();
        const auto abstractType =
            ua::findTypeByName(as, ua::companion::kRoboticSkillsUri, "MoveSkillType");
        ASSERT_TRUE(abstractType);
        auto probe = std::make_shared<Probe>();
        EXPECT_EQ(skills->add(*abstractType, "A", std::make_unique<ProbeBehaviour>(probe)).status(),
                  status::BadTypeDefinitionInvalid);
        EXPECT_EQ(skills->add(NodeId(58), "B", std::make_unique<ProbeBehaviour>(probe)).status(),
                  status::BadTypeDefinitionInvalid);  // BaseObjectType: not a skill
        const auto type = skills->findSkillType("GraspGripperSkillType");
        ASSERT_TRUE(type);
        EXPECT_TRUE(skills->add(*type, "Grasp", std::make_unique<ProbeBehaviour>(probe)));
        EXPECT_EQ(skills->add(*type, "Grasp", std::make_unique<ProbeBehaviour>(probe)).status(),
                  status::BadNodeIdExists);
        EXPECT_FALSE(skills->findSkillType("NoSuchSkillType"));
    });
}

}  // namespace
}  // namespace skillcell::skills::skill_test
