// The conformance checker (`skillcell check`) against an in-process server that loads the
// companion models and instantiates skills: a conforming skill passes; a missing method, a
// parameter of the wrong data type, an instance of an abstract type, an invalid
// CurrentState, a LastTransition that does not end in it, a missing EURange each give a
// precise finding; a server without the skill model, or without skills, fails.
// --exercise runs against FakeSkill, a protocol-level skill written here (method callbacks
// that follow the state-machine table, transition events): a conforming one passes, one
// that answers Good in the wrong state, one without events, one whose run never ends each
// fail, and the skill is left in Ready; and against skills::Skill with a NoOpBehaviour (what
// `skillcell server --noop-skill` offers): it passes, also Suspend/Resume during a longer
// run, and fails when a device's own callback answers Good in the wrong state. The
// report's text and JSON forms are checked too.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "running_server.hpp"
#include "skills/conformance_checker.hpp"
#include "skills/conformance_report.hpp"
#include "skills/noop_behaviour.hpp"
#include "skills/skill_server.hpp"
#include "skills/skill_state_machine.hpp"
#include "ua/address_space/instantiate.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace skillcell::skills::conformance_checker_test {
namespace {

using namespace std::chrono_literals;
namespace ns0 = ua::ns0;
namespace cm = ua::companion;

// --- Building skills on the server ----------------------------------------------------

struct SkillSpec {
    std::string uri{cm::kRoboticSkillsUri};
    std::string type = "CartesianLinearMoveSkillType";
    std::string name = "Move";
    std::vector<std::string> optional = {"Start",
                                         "Suspend",
                                         "Resume",
                                         "Halt",
                                         "Reset",
                                         "ParameterSet/MaxVelocity/EURange",
                                         "ParameterSet/MaxAcceleration/EURange",
                                         "ParameterSet/Reach/EURange"};
    bool eventNotifier = true;
};

ua::QualifiedName q0(const char* name) {
    return ua::QualifiedName{0, name};
}

/// The node at `path` (namespace-0 names, then names in any namespace) below `from`.
ua::NodeId childAt(const ua::AddressSpace& as, ua::NodeId from,
                   const std::vector<std::string>& path) {
    for (const auto& name : path) {
        const ua::Node* parent = as.find(from);
        if (parent == nullptr) return {};
        ua::NodeId found;
        for (const auto& ref : parent->references) {
            if (!ref.isForward) continue;
            const ua::Node* child = as.find(ref.target);
            if (child != nullptr && child->browseName.name == name &&
                as.isSubtypeOf(ref.referenceTypeId, ua::NodeId(ns0::HierarchicalReferences))) {
                found = ref.target;
                break;
            }
        }
        if (found.isNull()) return {};
        from = found;
    }
    return from;
}

void setState(ua::AddressSpace& as, const ua::NodeId& skill, SkillState state) {
    ASSERT_TRUE(as.setValue(childAt(as, skill, {"CurrentState"}),
                            ua::LocalizedText{"", std::string(name(state))})
                    .isGood());
    ASSERT_TRUE(
        as.setValue(childAt(as, skill, {"CurrentState", "Id"}), stateNodeId(state)).isGood());
    ASSERT_TRUE(as.setValue(childAt(as, skill, {"CurrentState", "Number"}),
                            static_cast<std::uint32_t>(state))
                    .isGood());
}

/// An instance as a conforming skill server makes it: every method, the optional EURanges,
/// CurrentState Ready with its Id and Number, an event notifier.
ua::NodeId addSkill(ua::AddressSpace& as, const SkillSpec& spec = {}) {
    const auto type = ua::findTypeByName(as, spec.uri, spec.type);
    EXPECT_TRUE(type.has_value()) << spec.type;
    ua::InstantiateOptions options;
    options.nodeId = ua::NodeId(1, "Cell." + spec.name);
    options.optionalChildren = spec.optional;
    auto id = ua::instantiate(as, type.value_or(ua::NodeId()), ua::NodeId(ns0::ObjectsFolder),
                              ua::NodeId(ns0::Organizes), ua::QualifiedName{1, spec.name}, options);
    EXPECT_TRUE(id.ok()) << ua::statusName(id.status());
    if (!id) return {};
    setState(as, *id, SkillState::Ready);
    as.find(*id)->eventNotifier = spec.eventNotifier ? 1 : 0;
    return *id;
}

void loadModels(ua::Server& server) {
    const auto st = ua::loadCompanionModels(server.addressSpace());
    ASSERT_TRUE(st.ok()) << st.error;
}

// --- A skill on the protocol level, for --exercise ------------------------------------

enum class Flaw { None, ResetGoodInReady, NoEvents, RunNeverEnds, WrongToStateId };

/// A skill written as small as the protocol allows: method callbacks that follow the
/// state-machine table, CurrentState and LastTransition kept up to date, a
/// SkillTransitionEventType event per transition, and a run that ends in Ready right after
/// it began. `flaw` breaks one rule on purpose. Lives on the server's thread.
class FakeSkill : public std::enable_shared_from_this<FakeSkill> {
public:
    FakeSkill(ua::Server& server, asio::io_context& io, ua::NodeId node, Flaw flaw)
        : server_(server), io_(io), node_(std::move(node)), flaw_(flaw) {}

    /// Set (from the server's thread) once a method has been called while Halted.
    [[nodiscard]] const std::atomic<bool>& calledInHalted() const { return calledInHalted_; }

    void install() {
        auto& as = server_.addressSpace();
        eventType_ = *ua::skillsNodeId(as, cm::kSkillTransitionEventType);
        for (const auto m : kAllMethods) {
            const ua::NodeId method = childAt(as, node_, {std::string(name(m))});
            ASSERT_FALSE(method.isNull()) << name(m);
            std::weak_ptr<FakeSkill> weak = weak_from_this();
            as.setMethodCallback(
                method, [weak, m](const ua::Caller&, const ua::NodeId&,
                                  std::span<const ua::Variant>, std::vector<ua::Variant>&) {
                    auto self = weak.lock();
                    return self ? self->onMethod(m) : ua::status::BadInternalError;
                });
        }
    }

private:
    ua::StatusCode onMethod(SkillMethod m) {
        if (state_ == SkillState::Halted) calledInHalted_ = true;
        if (flaw_ == Flaw::ResetGoodInReady && m == SkillMethod::Reset &&
            state_ == SkillState::Ready) {
            return ua::status::Good;  // the flaw: accepts Reset where Ready does not allow it
        }
        const auto t = transitionFor(m, state_);
        if (!t) return ua::status::BadInvalidState;
        enter(*t);
        if (*t == SkillTransition::ReadyToRunning && flaw_ != Flaw::RunNeverEnds) {
            // The run "finishes" right after Start returned.
            asio::post(io_, [weak = weak_from_this()] {
                auto self = weak.lock();
                if (self && self->state_ == SkillState::Running) {
                    self->enter(SkillTransition::RunningToReady);
                }
            });
        }
        return ua::status::Good;
    }

    void enter(SkillTransition t) {
        auto& as = server_.addressSpace();
        state_ = toState(t);
        setState(as, node_, state_);
        (void)as.setValue(childAt(as, node_, {"LastTransition"}),
                          ua::LocalizedText{"", std::string(name(t))});
        (void)as.setValue(childAt(as, node_, {"LastTransition", "Id"}), transitionNodeId(t));
        (void)as.setValue(childAt(as, node_, {"LastTransition", "Number"}),
                          static_cast<std::uint32_t>(t));
        (void)as.setValue(childAt(as, node_, {"LastTransition", "TransitionTime"}),
                          ua::DateTime::now());
        if (flaw_ == Flaw::NoEvents) return;
        const SkillState from = fromState(t);
        const SkillState to = toState(t);
        ua::Event e;
        e.eventType = eventType_;
        e.sourceNode = node_;
        e.message = {"", std::string(name(t))};
        auto text = [](std::string_view s) {
            return ua::Variant(ua::LocalizedText{"", std::string(s)});
        };
        e.fields = {
            {{q0("Transition")}, text(name(t))},
            {{q0("Transition"), q0("Id")}, ua::Variant(transitionNodeId(t))},
            {{q0("FromState")}, text(name(from))},
            {{q0("FromState"), q0("Id")}, ua::Variant(stateNodeId(from))},
            {{q0("ToState")}, text(name(to))},
            {{q0("ToState"), q0("Id")},
             ua::Variant(flaw_ == Flaw::WrongToStateId ? stateNodeId(from) : stateNodeId(to))},
        };
        server_.fireEvent(std::move(e));
    }

    ua::Server& server_;
    asio::io_context& io_;
    ua::NodeId node_;
    Flaw flaw_;
    ua::NodeId eventType_;
    SkillState state_ = SkillState::Ready;
    std::atomic<bool> calledInHalted_{false};
};

// --- Running the checker --------------------------------------------------------------

asio::awaitable<void> connectAndCheck(ua::Client& client, std::string url, CheckOptions options,
                                      ConformanceReport& report, ua::StatusCode& connected) {
    connected = co_await client.connect(url);
    if (connected.isBad()) co_return;
    co_await checkConformance(client, std::move(options), report);
    (void)co_await client.disconnect();
}

ConformanceReport check(const std::string& url, CheckOptions options = {}) {
    asio::io_context io(1);
    ua::Client client(io.get_executor());
    ConformanceReport report(url);
    ua::StatusCode connected = ua::status::BadInternalError;
    asio::co_spawn(io, connectAndCheck(client, url, std::move(options), report, connected),
                   asio::detached);
    io.run_for(60s);
    EXPECT_TRUE(connected.isGood()) << ua::statusName(connected);
    return report;
}

std::string dump(const ConformanceReport& report) {
    std::string s;
    for (const auto& f : report.findings()) s += formatFinding(f) + "\n";
    return s;
}

/// The findings of `verdict` for `check` (any subject).
std::vector<Finding> findings(const ConformanceReport& report, Verdict verdict,
                              const std::string& checkName) {
    std::vector<Finding> out;
    for (const auto& f : report.findings()) {
        if (f.verdict == verdict && f.check == checkName) out.push_back(f);
    }
    return out;
}

class ConformanceChecker : public ::testing::Test {
protected:
    /// A server with the companion models and whatever `build` adds.
    void start(const std::function<void(ua::AddressSpace&)>& build) {
        server_ = std::make_unique<test::RunningServer>(test::RunningServer::defaultConfig(),
                                                        [&build](ua::Server& server) {
                                                            loadModels(server);
                                                            build(server.addressSpace());
                                                        });
    }
    ConformanceReport run(CheckOptions options = {}) { return check(server_->url(), options); }

    std::unique_ptr<test::RunningServer> server_;
};

// --- Static checks --------------------------------------------------------------------

TEST_F(ConformanceChecker, ConformingSkillPasses) {
    start([](ua::AddressSpace& as) { addSkill(as); });
    const auto report = run();
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    EXPECT_EQ(report.count(Verdict::Warn), 0u) << dump(report);
    EXPECT_TRUE(report.passed(/*strict=*/true));
    EXPECT_EQ(report.exitCode(), 0);
    ASSERT_EQ(report.skills().size(), 1u);
    EXPECT_EQ(report.skills()[0].path, "Objects/Move");
    EXPECT_EQ(report.skills()[0].nodeId, "ns=1;s=Cell.Move");
    EXPECT_NE(report.skills()[0].type.find("CartesianLinearMoveSkillType"), std::string::npos);
    // The checks a device maker relies on were made, not skipped.
    for (const char* checkName : {"type",
                                  "CurrentState",
                                  "CurrentState/Id",
                                  "CurrentState/Number",
                                  "CurrentState value",
                                  "LastTransition",
                                  "LastTransition value",
                                  "LastTransition/TransitionTime",
                                  "ParameterSet",
                                  "ParameterSet/ToolFrame",
                                  "ParameterSet/TargetPosition/CartesianCoordinates/X",
                                  "ParameterSet/MaxVelocity",
                                  "ParameterSet/MaxVelocity/EngineeringUnits",
                                  "ParameterSet/MaxVelocity in EURange",
                                  "ParameterSet/AxisBounds",
                                  "Start",
                                  "Suspend",
                                  "Resume",
                                  "Halt",
                                  "Reset",
                                  "events"}) {
        EXPECT_EQ(findings(report, Verdict::Pass, checkName).size(), 1u) << checkName << "\n"
                                                                         << dump(report);
    }
    const auto state = findings(report, Verdict::Pass, "CurrentState value");
    ASSERT_EQ(state.size(), 1u);
    EXPECT_EQ(state[0].found, "Ready (Id i=2400, Number 12)");
    const auto type = findings(report, Verdict::Pass, "type");
    ASSERT_EQ(type.size(), 1u);
    EXPECT_NE(type[0].found.find("SkillType -> ProgramStateMachineType"), std::string::npos)
        << type[0].found;
}

TEST_F(ConformanceChecker, EverySkillOfEveryModelIsFound) {
    start([](ua::AddressSpace& as) {
        SkillSpec grasp;
        grasp.uri = cm::kGripperSkillsUri;
        grasp.type = "GraspGripperSkillType";
        grasp.name = "Grasp";
        grasp.optional = {"Start", "Suspend", "Resume", "Halt", "Reset"};
        addSkill(as, grasp);
        SkillSpec process;
        process.uri = cm::kMesSkillsUri;
        process.type = "ExecuteProcessSkillType";
        process.name = "Process";
        process.optional = grasp.optional;
        addSkill(as, process);
        addSkill(as);
    });
    const auto report = run();
    EXPECT_EQ(report.skills().size(), 3u) << dump(report);
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
}

TEST_F(ConformanceChecker, MissingMethodFails) {
    start([](ua::AddressSpace& as) {
        SkillSpec spec;
        std::erase(spec.optional, "Suspend");
        addSkill(as, spec);
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "Suspend");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].subject, "Objects/Move");
    EXPECT_EQ(f[0].expected,
              "Method (required by the skill model; OptionalPlaceholder in namespace 0)");
    EXPECT_EQ(f[0].found, "nothing");
    EXPECT_EQ(report.count(Verdict::Fail), 1u) << dump(report);
    EXPECT_EQ(report.exitCode(), 1);
}

TEST_F(ConformanceChecker, ParameterOfTheWrongDataTypeFails) {
    start([](ua::AddressSpace& as) {
        const auto skill = addSkill(as);
        const auto velocity = childAt(as, skill, {"ParameterSet", "MaxVelocity"});
        as.find(velocity)->dataType = ua::NodeId(ns0::String);
        ASSERT_TRUE(as.setValue(velocity, ua::Variant("fast")).isGood());
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "ParameterSet/MaxVelocity");
    ASSERT_GE(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "DataType Double (i=11) or a subtype");
    EXPECT_EQ(f[0].found, "String (i=12)");
    // The value is checked against the declaration too.
    ASSERT_EQ(f.size(), 2u) << dump(report);
    EXPECT_EQ(f[1].found, "a String");
}

TEST_F(ConformanceChecker, ParameterOfTheWrongValueRankFails) {
    start([](ua::AddressSpace& as) {
        const auto skill = addSkill(as);
        const auto joints = childAt(as, skill, {"ParameterSet", "AxisBounds"});
        as.find(joints)->valueRank = ua::value_rank::kScalar;
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "ParameterSet/AxisBounds");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "ValueRank 1 (one dimension)");
    EXPECT_EQ(f[0].found, "-1 (scalar)");
}

TEST_F(ConformanceChecker, InstanceOfAnAbstractTypeFails) {
    start([](ua::AddressSpace& as) {
        const auto move = ua::findTypeByName(as, cm::kRoboticSkillsUri, "MoveSkillType");
        ASSERT_TRUE(move.has_value());
        ASSERT_TRUE(as.addObject(ua::NodeId(ns0::ObjectsFolder), ua::NodeId(1, "Cell.Abstract"),
                                 "Abstract", *move, ua::NodeId(ns0::Organizes))
                        .ok());
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "type");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].subject, "Objects/Abstract");
    EXPECT_EQ(f[0].expected, "a concrete (not abstract) subtype of SkillType");
    EXPECT_NE(f[0].found.find("MoveSkillType"), std::string::npos);
    EXPECT_NE(f[0].found.find("abstract"), std::string::npos);
    // And every mandatory child is missing.
    EXPECT_EQ(findings(report, Verdict::Fail, "CurrentState").size(), 1u);
    EXPECT_EQ(findings(report, Verdict::Fail, "ParameterSet").size(), 1u);
}

TEST_F(ConformanceChecker, InvalidCurrentStateFails) {
    start([](ua::AddressSpace& as) {
        const auto skill = addSkill(as);
        ASSERT_TRUE(as.setValue(childAt(as, skill, {"CurrentState"}), ua::LocalizedText{"", "Idle"})
                        .isGood());
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "CurrentState value");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "one of Halted, Ready, Running, Suspended");
    EXPECT_EQ(f[0].found, "'Idle'");
}

TEST_F(ConformanceChecker, UnreadableValueFails) {
    start([](ua::AddressSpace& as) {
        const auto skill = addSkill(as);
        const auto velocity = childAt(as, skill, {"ParameterSet", "MaxVelocity"});
        ASSERT_TRUE(as.setValueSource(velocity, [] {
                          return ua::DataValue::withStatus(ua::status::BadNotReadable);
                      }).isGood());
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "ParameterSet/MaxVelocity");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "a readable value");
    EXPECT_EQ(f[0].found, "BadNotReadable");
}

TEST_F(ConformanceChecker, ChildOfTheWrongNodeClassFails) {
    start([](ua::AddressSpace& as) {
        SkillSpec spec;
        std::erase(spec.optional, "Start");
        const auto skill = addSkill(as, spec);
        auto start = as.addVariable(skill, ua::NodeId(1, "Cell.Move/Start"), "Start",
                                    ua::NodeId(ns0::Boolean), ua::Variant(true));
        ASSERT_TRUE(start.ok());
        (*start)->browseName = q0("Start");
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "Start");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "Method");
    EXPECT_EQ(f[0].found, "a Variable ns=1;s=Cell.Move/Start");
}

TEST_F(ConformanceChecker, CurrentStateIdAndNumberMustMatchItsName) {
    start([](ua::AddressSpace& as) {
        const auto skill = addSkill(as);
        ASSERT_TRUE(as.setValue(childAt(as, skill, {"CurrentState", "Id"}),
                                stateNodeId(SkillState::Running))
                        .isGood());
        ASSERT_TRUE(
            as.setValue(childAt(as, skill, {"CurrentState", "Number"}), std::uint32_t{7}).isGood());
    });
    const auto report = run();
    const auto id = findings(report, Verdict::Fail, "CurrentState/Id value");
    ASSERT_EQ(id.size(), 1u) << dump(report);
    EXPECT_EQ(id[0].expected, "i=2400 (Ready of ProgramStateMachineType)");
    EXPECT_EQ(id[0].found, "i=2402");
    const auto number = findings(report, Verdict::Fail, "CurrentState/Number value");
    ASSERT_EQ(number.size(), 1u);
    EXPECT_EQ(number[0].expected, "12");
    EXPECT_EQ(number[0].found, "7");
}

TEST_F(ConformanceChecker, LastTransitionMustLeadIntoCurrentState) {
    start([](ua::AddressSpace& as) {
        const auto skill = addSkill(as);
        const auto t = SkillTransition::ReadyToRunning;
        ASSERT_TRUE(as.setValue(childAt(as, skill, {"LastTransition"}),
                                ua::LocalizedText{"", std::string(name(t))})
                        .isGood());
        ASSERT_TRUE(as.setValue(childAt(as, skill, {"LastTransition", "Id"}), transitionNodeId(t))
                        .isGood());
        ASSERT_TRUE(as.setValue(childAt(as, skill, {"LastTransition", "Number"}),
                                static_cast<std::uint32_t>(t))
                        .isGood());
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "LastTransition value");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "a transition into Ready (CurrentState)");
    EXPECT_EQ(f[0].found, "ReadyToRunning");
}

TEST_F(ConformanceChecker, MissingEURangeAndValueOutsideItWarn) {
    start([](ua::AddressSpace& as) {
        SkillSpec spec;
        std::erase(spec.optional, "ParameterSet/MaxAcceleration/EURange");
        const auto skill = addSkill(as, spec);
        ASSERT_TRUE(as.setValue(childAt(as, skill, {"ParameterSet", "MaxVelocity"}), 5.0).isGood());
    });
    const auto report = run();
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    const auto missing = findings(report, Verdict::Warn, "ParameterSet/MaxAcceleration/EURange");
    ASSERT_EQ(missing.size(), 1u) << dump(report);
    EXPECT_EQ(missing[0].found, "none");
    const auto outside = findings(report, Verdict::Warn, "ParameterSet/MaxVelocity in EURange");
    ASSERT_EQ(outside.size(), 1u) << dump(report);
    EXPECT_EQ(outside[0].expected, "a value inside [0, 2]");
    EXPECT_TRUE(report.passed());
    EXPECT_FALSE(report.passed(/*strict=*/true));
}

TEST_F(ConformanceChecker, SkillThatIsNoEventNotifierWarns) {
    start([](ua::AddressSpace& as) {
        SkillSpec spec;
        spec.eventNotifier = false;
        addSkill(as, spec);
    });
    const auto report = run();
    const auto f = findings(report, Verdict::Warn, "events");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_NE(f[0].found.find("EventNotifier 0"), std::string::npos);
}

TEST_F(ConformanceChecker, ServerWithoutTheSkillModelFails) {
    server_ = std::make_unique<test::RunningServer>(test::RunningServer::defaultConfig());
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "Skills namespace");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].subject, "server");
    EXPECT_EQ(report.exitCode(), 1);
}

TEST_F(ConformanceChecker, ServerWithoutSkillsFails) {
    start([](ua::AddressSpace&) {});
    const auto report = run();
    const auto f = findings(report, Verdict::Fail, "skills");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected,
              "at least one object below Objects whose type is a subtype of SkillType");
    EXPECT_EQ(report.skills().size(), 0u);
}

TEST_F(ConformanceChecker, SearchStopsAtTheObjectLimit) {
    start([](ua::AddressSpace& as) { addSkill(as); });
    CheckOptions options;
    options.maxObjects = 1;
    const auto report = run(options);
    EXPECT_EQ(findings(report, Verdict::Warn, "search for skills").size(), 1u) << dump(report);
}

// --- --exercise -------------------------------------------------------------------------

class ConformanceExercise : public ConformanceChecker {
protected:
    void startWithFake(Flaw flaw, bool eventNotifier = true) {
        ua::NodeId skill;
        start([&skill, eventNotifier](ua::AddressSpace& as) {
            SkillSpec spec;
            spec.eventNotifier = eventNotifier;
            skill = addSkill(as, spec);
        });
        auto& srv = *server_;
        fake_ = srv.inServer([&srv, &skill, flaw](ua::Server& s) {
            auto fake = std::make_shared<FakeSkill>(s, srv.io(), skill, flaw);
            fake->install();
            return fake;
        });
        skill_ = skill;
    }
    static CheckOptions exercise() {
        CheckOptions options;
        options.exercise = true;
        options.eventTimeout = 1s;
        options.runTimeout = 1s;
        return options;
    }
    /// Calls one of the skill's methods from a client of its own (someone else).
    void callAsAnotherClient(const std::string& method) {
        const ua::NodeId id = server_->inServer(
            [this, &method](ua::Server& s) { return childAt(s.addressSpace(), skill_, {method}); });
        asio::io_context io(1);
        ua::Client client(io.get_executor());
        asio::co_spawn(
            io,
            [](ua::Client& c, std::string url, ua::NodeId skill,
               ua::NodeId methodId) -> asio::awaitable<void> {
                if ((co_await c.connect(url)).isBad()) co_return;
                std::vector<ua::Variant> inputs;
                (void)co_await c.call(skill, methodId, std::move(inputs));
                (void)co_await c.disconnect();
            }(client, server_->url(), skill_, id),
            asio::detached);
        io.run_for(10s);
    }
    /// CurrentState's text on the server now.
    std::string currentState() {
        return server_->inServer([this](ua::Server& s) {
            const auto& as = s.addressSpace();
            const ua::Node* n = as.find(childAt(as, skill_, {"CurrentState"}));
            const auto* lt = n->value.value ? n->value.value->get<ua::LocalizedText>() : nullptr;
            return lt != nullptr ? lt->text : std::string();
        });
    }

    std::shared_ptr<FakeSkill> fake_;
    ua::NodeId skill_;
};

TEST_F(ConformanceExercise, ConformingSkillPasses) {
    startWithFake(Flaw::None);
    const auto report = run(exercise());
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    EXPECT_EQ(report.count(Verdict::Warn), 0u) << dump(report);
    for (const char* checkName :
         {"Suspend in Ready", "Resume in Ready", "Reset in Ready", "Halt in Ready",
          "Start in Halted", "Suspend in Halted", "Resume in Halted", "Halt in Halted",
          "Reset in Halted", "Start in Ready", "run", "exercise end"}) {
        EXPECT_EQ(findings(report, Verdict::Pass, checkName).size(), 1u) << checkName << "\n"
                                                                         << dump(report);
    }
    EXPECT_EQ(findings(report, Verdict::Pass, "Halt in Ready")[0].found,
              "Good, event ReadyToHalted, CurrentState Halted");
    EXPECT_EQ(currentState(), "Ready");
}

TEST_F(ConformanceExercise, EventsThroughTheServerObjectAreFound) {
    startWithFake(Flaw::None, /*eventNotifier=*/false);
    const auto report = run(exercise());
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    const auto f = findings(report, Verdict::Pass, "event subscription");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].found, "on the Server object");
}

TEST_F(ConformanceExercise, GoodAnswerInTheWrongStateFails) {
    startWithFake(Flaw::ResetGoodInReady);
    const auto report = run(exercise());
    const auto f = findings(report, Verdict::Fail, "Reset in Ready");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "BadInvalidState (Ready does not allow Reset)");
    EXPECT_EQ(f[0].found, "Good");
    EXPECT_EQ(report.count(Verdict::Fail), 1u) << dump(report);
    EXPECT_EQ(currentState(), "Ready");
}

TEST_F(ConformanceExercise, MissingEventsFail) {
    startWithFake(Flaw::NoEvents);
    const auto report = run(exercise());
    const auto f = findings(report, Verdict::Fail, "event ReadyToHalted");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "the event within 1000 ms");
    EXPECT_EQ(f[0].found, "none");
    EXPECT_EQ(currentState(), "Ready") << "restored by Reset";
}

TEST_F(ConformanceExercise, InconsistentEventFieldsFail) {
    startWithFake(Flaw::WrongToStateId);
    const auto report = run(exercise());
    const auto f = findings(report, Verdict::Fail, "event ReadyToHalted");
    ASSERT_GE(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "ToState Halted (i=2406)");
    EXPECT_EQ(f[0].found, "'Halted' (i=2400)");
}

TEST_F(ConformanceExercise, RunThatNeverEndsFailsAndIsHalted) {
    startWithFake(Flaw::RunNeverEnds);
    const auto report = run(exercise());
    const auto f = findings(report, Verdict::Fail, "run");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "RunningToReady or RunningToHalted within 1000 ms");
    EXPECT_EQ(f[0].found, "no event; CurrentState Running");
    EXPECT_EQ(findings(report, Verdict::Pass, "exercise end").size(), 1u) << dump(report);
    EXPECT_EQ(currentState(), "Ready");
}

TEST_F(ConformanceExercise, StopRequestedLeavesTheSkillReady) {
    startWithFake(Flaw::None);
    auto options = exercise();
    // As if Ctrl-C came once the skill was Halted: the exercise ends, and Resets it.
    options.stopRequested = [fake = fake_] { return fake->calledInHalted().load(); };
    const auto report = run(options);
    const auto f = findings(report, Verdict::Fail, "exercise");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].found, "interrupted: the remaining steps were skipped");
    EXPECT_EQ(findings(report, Verdict::Pass, "Start in Ready").size(), 0u) << dump(report);
    EXPECT_EQ(findings(report, Verdict::Pass, "exercise end").size(), 1u) << dump(report);
    EXPECT_EQ(report.exitCode(), 1);
    EXPECT_EQ(currentState(), "Ready");
}

TEST_F(ConformanceExercise, HaltedSkillIsResetFirst) {
    startWithFake(Flaw::None);
    callAsAnotherClient("Halt");  // Halted through the protocol, as a client would leave it
    ASSERT_EQ(currentState(), "Halted");
    const auto report = run(exercise());
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    EXPECT_EQ(findings(report, Verdict::Pass, "Reset in Halted").size(), 2u) << dump(report);
    EXPECT_EQ(currentState(), "Ready");
}

TEST_F(ConformanceExercise, SkillInUseIsLeftAlone) {
    startWithFake(Flaw::RunNeverEnds);
    callAsAnotherClient("Start");  // someone else's run
    ASSERT_EQ(currentState(), "Running");
    const auto report = run(exercise());
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    const auto f = findings(report, Verdict::Warn, "exercise");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].found, "Running (in use by someone else?): not exercised");
    EXPECT_EQ(currentState(), "Running") << "not halted by the checker";
}

// --- --exercise against skills::Skill, the component side of the skill layer ------------

class ConformanceOfSkill : public ConformanceChecker {
protected:
    /// A server whose SkillServer offers a CartesianLinearMoveSkillType with a no-op run of
    /// `runMs` (the same skill `skillcell server --noop-skill` offers).
    std::shared_ptr<Skill> startSkillServer(int runMs) {
        server_ = std::make_unique<test::RunningServer>(test::RunningServer::defaultConfig());
        auto& srv = *server_;
        return srv.inServer([&srv, this, runMs](ua::Server& s) -> std::shared_ptr<Skill> {
            std::string error;
            skillServer_ = SkillServer::create(s, srv.io().get_executor(), &error);
            if (!skillServer_) {
                ADD_FAILURE() << error;
                return nullptr;
            }
            auto type = skillServer_->findSkillType("CartesianLinearMoveSkillType");
            if (!type) return nullptr;
            auto skill =
                skillServer_->add(*type, "Move",
                                  std::make_unique<NoOpBehaviour>(
                                      srv.io().get_executor(), std::chrono::milliseconds(runMs)));
            return skill ? *skill : nullptr;
        });
    }
    static CheckOptions exercise() {
        CheckOptions options;
        options.exercise = true;
        options.eventTimeout = 2s;
        options.runTimeout = 5s;
        return options;
    }

    std::unique_ptr<SkillServer> skillServer_;
};

TEST_F(ConformanceOfSkill, InstantNoOpSkillPasses) {
    const auto skill = startSkillServer(0);
    ASSERT_NE(skill, nullptr);
    const auto report = run(exercise());
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    EXPECT_EQ(report.count(Verdict::Warn), 0u) << dump(report);
    ASSERT_EQ(report.skills().size(), 1u);
    EXPECT_EQ(report.skills()[0].path, "Objects/Skills/Move");
    EXPECT_EQ(findings(report, Verdict::Pass, "run").size(), 1u) << dump(report);
    EXPECT_EQ(findings(report, Verdict::Pass, "exercise end").size(), 1u) << dump(report);
    EXPECT_EQ(skill->state(), SkillState::Ready);
}

TEST_F(ConformanceOfSkill, RunLongEnoughIsSuspendedAndResumed) {
    const auto skill = startSkillServer(400);
    ASSERT_NE(skill, nullptr);
    const auto report = run(exercise());
    EXPECT_EQ(report.count(Verdict::Fail), 0u) << dump(report);
    for (const char* checkName :
         {"Suspend in Running", "Start in Suspended", "Suspend in Suspended", "Reset in Suspended",
          "Resume in Suspended", "run"}) {
        EXPECT_EQ(findings(report, Verdict::Pass, checkName).size(), 1u) << checkName << "\n"
                                                                         << dump(report);
    }
    EXPECT_EQ(skill->state(), SkillState::Ready);
}

TEST_F(ConformanceOfSkill, HaltAnsweredGoodInHaltedFails) {
    const auto skill = startSkillServer(0);
    ASSERT_NE(skill, nullptr);
    // A device maker's mistake on top of a correct skill: its own Halt callback that says
    // Good where the state machine does not allow Halt.
    server_->inServer([&skill](ua::Server& s) {
        auto& as = s.addressSpace();
        const ua::NodeId halt = childAt(as, skill->nodeId(), {"Halt"});
        ASSERT_FALSE(halt.isNull());
        std::weak_ptr<Skill> weak = skill;
        as.setMethodCallback(halt, [weak](const ua::Caller& caller, const ua::NodeId&,
                                          std::span<const ua::Variant>, std::vector<ua::Variant>&) {
            auto self = weak.lock();
            if (!self) return ua::status::BadInternalError;
            if (self->state() == SkillState::Halted) return ua::status::Good;
            return self->invoke(SkillMethod::Halt, caller);
        });
    });
    const auto report = run(exercise());
    const auto f = findings(report, Verdict::Fail, "Halt in Halted");
    ASSERT_EQ(f.size(), 1u) << dump(report);
    EXPECT_EQ(f[0].expected, "BadInvalidState (Halted does not allow Halt)");
    EXPECT_EQ(f[0].found, "Good");
    EXPECT_EQ(report.count(Verdict::Fail), 1u) << dump(report);
    EXPECT_EQ(report.exitCode(), 1);
    EXPECT_EQ(skill->state(), SkillState::Ready);
}

// --- The report -------------------------------------------------------------------------

TEST(ConformanceReport, LinesSummaryAndExitCode) {
    ConformanceReport report("opc.tcp://x:4840");
    std::vector<std::string> heard;
    report.setListener([&heard](const Finding& f) { heard.push_back(formatFinding(f)); });
    report.addSkill({"Objects/Move", "ns=1;s=Move", "MoveType (ns=2;i=1)"});
    report.pass("Objects/Move", "type", "MoveType, concrete");
    report.warn("Objects/Move", "events", "an event notifier", "EventNotifier 0");
    EXPECT_EQ(report.exitCode(), 0);
    EXPECT_EQ(report.exitCode(/*strict=*/true), 1);
    report.fail("Objects/Move", "Suspend", "Method", "nothing");
    EXPECT_EQ(report.exitCode(), 1);
    ASSERT_EQ(heard.size(), 3u);
    EXPECT_EQ(heard[0], "PASS  Objects/Move  type: MoveType, concrete");
    EXPECT_EQ(heard[2], "FAIL  Objects/Move  Suspend: expected Method, found nothing");
    EXPECT_EQ(formatSummary(report),
              "1 skill, 3 checks: 1 passed, 1 warning, 1 failed\nRESULT: FAIL");
}

TEST(ConformanceReport, JsonEscapesWhatServersSend) {
    ConformanceReport report("opc.tcp://x:4840");
    report.fail("Objects/\"Odd\"\\Name", "CurrentState", "one of Halted, ...", "'a\nb\x01'");
    report.fail("Objects/X", "BrowseName", "UTF-8", std::string("\xff\xfe"));
    const std::string json = toJson(report);
    EXPECT_NE(json.find(R"("subject": "Objects/\"Odd\"\\Name")"), std::string::npos) << json;
    EXPECT_NE(json.find(R"("found": "'a\nb\u0001'")"), std::string::npos) << json;
    // Read back by another parser: one document with every field.
    const auto j = nlohmann::json::parse(json);
    EXPECT_EQ(j["endpoint"], "opc.tcp://x:4840");
    EXPECT_EQ(j["result"], "FAIL");
    EXPECT_EQ(j["counts"], nlohmann::json({{"pass", 0}, {"warn", 0}, {"fail", 2}}));
    EXPECT_TRUE(j["skills"].is_array() && j["skills"].empty());
    ASSERT_EQ(j["findings"].size(), 2U);
    EXPECT_EQ(j["findings"][0]["found"], "'a\nb\x01'");
    // Bytes that are not UTF-8 become U+FFFD rather than an exception.
    EXPECT_EQ(j["findings"][1]["found"], "\xef\xbf\xbd\xef\xbf\xbd");
}

}  // namespace
}  // namespace skillcell::skills::conformance_checker_test
