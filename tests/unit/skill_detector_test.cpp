// The SkillDetector against real servers on loopback: skill servers built from the companion
// models, the detector fed "appeared"/"gone" directly (no multicast). Lookup by supertype,
// types resolved through each server's own hierarchy and namespace array, declared
// parameters, removal on gone / disconnect / connect timeout / keep-alive timeout, re-browse
// on a new StartTime, listeners, and the LDS registration source. The RemoteSkillBrowser
// under continuation points.
//
// Every wait is on a condition with a deadline; servers are frozen (not slept) to provoke
// timeouts. The detector runs on a thread of the test, its queries are called from the test
// thread (these tests also run under ThreadSanitizer, preset "tsan").
#include <gtest/gtest.h>

#include <algorithm>
#include <asio.hpp>
#include <condition_variable>
#include <functional>
#include <future>
#include <mutex>
#include <set>
#include <thread>

#include "running_server.hpp"
#include "skills/skill_detector.hpp"
#include "ua/address_space/instantiate.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace skillcell::skills::skill_detector_test {
namespace {

using namespace std::chrono_literals;
namespace cm = ua::companion;
namespace ns0 = ua::ns0;
using ua::NodeId;
using ua::QualifiedName;

constexpr auto kDeadline = 10s;  // for things that take milliseconds: only a hang reaches it

/// The companion models as a reference: the ids every detector lookup uses.
const ua::AddressSpace& referenceModels() {
    static const ua::AddressSpace as = [] {
        ua::AddressSpace a("urn:test:reference");
        EXPECT_TRUE(ua::loadBaseNodeSet(a).ok());
        EXPECT_TRUE(ua::loadCompanionModels(a).ok());
        return a;
    }();
    return as;
}

GlobalNodeId typeId(std::string_view uri, std::string_view name) {
    const auto& as = referenceModels();
    const auto id = ua::findTypeByName(as, uri, name);
    EXPECT_TRUE(id.has_value()) << name;
    return GlobalNodeId::from(as.namespaces(), id.value_or(NodeId())).value_or(GlobalNodeId());
}

GlobalNodeId robotic(std::string_view name) {
    return typeId(cm::kRoboticSkillsUri, name);
}
GlobalNodeId gripper(std::string_view name) {
    return typeId(cm::kGripperSkillsUri, name);
}

/// A skill to put on a server: type (namespace URI, browse name) and instance name.
struct SkillSpec {
    std::string_view uri;
    std::string_view type;
    std::string name;
};

/// Loads the companion models and instantiates `skills` under Objects/<folder>, in the
/// server's namespace 1 ("ns=1;s=<folder>/<name>").
void addSkills(ua::Server& server, const std::vector<SkillSpec>& skills,
               const std::string& folder = "Robot") {
    auto& as = server.addressSpace();
    if (!as.namespaceIndex(cm::kSkillsUri)) {
        const auto loaded = ua::loadCompanionModels(as);
        ASSERT_TRUE(loaded.ok()) << loaded.error;
    }
    const NodeId parent(1, folder);
    if (as.find(parent) == nullptr) {
        ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), parent, folder).ok());
    }
    for (const auto& s : skills) {
        const auto type = ua::findTypeByName(as, s.uri, s.type);
        ASSERT_TRUE(type.has_value()) << s.type;
        auto id =
            ua::instantiate(as, *type, parent, NodeId(ns0::HasComponent), QualifiedName{1, s.name});
        ASSERT_TRUE(id.ok()) << s.name << ": " << ua::statusName(id.status());
    }
}

ua::ServerConfig serverConfig(const std::string& uri, std::uint16_t port = 0) {
    auto config = test::RunningServer::defaultConfig();
    config.description.applicationUri = uri;
    config.description.port = port;
    return config;
}

std::unique_ptr<test::RunningServer> skillServer(const std::string& uri,
                                                 const std::vector<SkillSpec>& skills,
                                                 std::uint16_t port = 0) {
    return std::make_unique<test::RunningServer>(serverConfig(uri, port),
                                                 [&](ua::Server& s) { addSkills(s, skills); });
}

ua::ApplicationDescription app(const std::string& uri) {
    ua::ApplicationDescription a;
    a.applicationUri = uri;
    return a;
}

const std::vector<SkillSpec> kRobotSkills = {
    {cm::kRoboticSkillsUri, "CartesianLinearMoveSkillType", "Move"},
    {cm::kRoboticSkillsUri, "JointPtpMoveSkillType", "Ptp"},
};
const std::vector<SkillSpec> kGripperSkills = {
    {cm::kGripperSkillsUri, "GraspGripperSkillType", "Grasp"},
    {cm::kGripperSkillsUri, "ReleaseGripperSkillType", "Release"},
};

std::set<std::string> namesOf(const std::vector<SkillInstance>& skills) {
    std::set<std::string> out;
    for (const auto& s : skills) out.insert(s.componentUri + " " + s.browsePathString());
    return out;
}

/// Records the detector's events (called on the detector's thread) for the test thread.
class EventLog {
public:
    void record(const SkillEvent& e) {
        {
            std::lock_guard lock(mutex_);
            events_.push_back(e);
        }
        changed_.notify_all();
    }
    /// Waits until `condition` holds (re-evaluated on every event and every 20 ms, since
    /// some conditions read the detector's state); false at the deadline.
    bool waitUntil(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        std::unique_lock lock(mutex_);
        while (true) {
            lock.unlock();
            const bool done = condition();
            lock.lock();
            if (done) return true;
            if (std::chrono::steady_clock::now() >= deadline) return false;
            changed_.wait_for(lock, 20ms);
        }
    }
    [[nodiscard]] std::vector<SkillEvent> events() const {
        std::lock_guard lock(mutex_);
        return events_;
    }
    /// "added|removed:<reason> <component> <path>" per event, in order.
    [[nodiscard]] std::vector<std::string> lines() const {
        std::vector<std::string> out;
        for (const auto& e : events()) {
            out.push_back((e.kind == SkillEvent::Kind::Added
                               ? std::string("added")
                               : "removed:" + std::string(toString(e.reason))) +
                          " " + e.instance.componentUri + " " + e.instance.browsePathString());
        }
        return out;
    }
    [[nodiscard]] std::size_t count(SkillEvent::Kind kind,
                                    std::optional<RemovalReason> reason = {}) const {
        const auto all = events();
        return static_cast<std::size_t>(std::count_if(all.begin(), all.end(), [&](const auto& e) {
            return e.kind == kind && (!reason || e.reason == *reason);
        }));
    }

private:
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    std::vector<SkillEvent> events_;
};

SkillDetectorConfig fastConfig() {
    SkillDetectorConfig c;
    c.connectTimeout = 2s;
    c.requestTimeout = 2s;
    c.keepAlivePeriod = 200ms;
    c.retryDelay = 50ms;
    c.maxRetryDelay = 200ms;
    return c;
}

/// A detector on an io_context thread of its own, with an EventLog subscribed.
class DetectorHarness {
public:
    explicit DetectorHarness(SkillDetectorConfig config = fastConfig())
        : work_(asio::make_work_guard(io_)) {
        detector_ = SkillDetector::create(io_.get_executor(), std::move(config));
        thread_ = std::thread([this] { io_.run(); });
        onDetector([this](SkillDetector& d) {
            listener_ = d.subscribe([this](const SkillEvent& e) { log_.record(e); });
        });
    }
    DetectorHarness(const DetectorHarness&) = delete;
    DetectorHarness& operator=(const DetectorHarness&) = delete;
    ~DetectorHarness() {
        onDetector([](SkillDetector& d) { d.stop(); });
        work_.reset();
        thread_.join();  // returns once every connection of the detector has ended
    }

    /// The detector's shutdown(grace), awaited on its thread.
    void shutdown(std::chrono::milliseconds grace) {
        asio::co_spawn(io_, detector_->shutdown(grace), asio::use_future).get();
    }

    /// Runs `f` on the detector's thread and waits for it.
    void onDetector(const std::function<void(SkillDetector&)>& f) {
        std::packaged_task<void()> task([&] { f(*detector_); });
        auto done = task.get_future();
        asio::post(io_, [&task] { task(); });
        done.get();
    }
    void appeared(const std::string& key, const std::string& uri, const std::string& url) {
        onDetector([&](SkillDetector& d) { d.appeared(key, app(uri), url); });
    }
    void gone(const std::string& key, GoneReason reason) {
        onDetector([&](SkillDetector& d) { d.gone(key, reason); });
    }

    SkillDetector& detector() { return *detector_; }
    EventLog& log() { return log_; }
    /// Waits until the detector holds `n` instances, and its listeners have heard of them
    /// (they are told after the map changed, in the same handler).
    bool waitForSkills(std::size_t n, std::chrono::milliseconds timeout = kDeadline) {
        const bool ok = log_.waitUntil([&] { return detector_->instances().size() == n; }, timeout);
        onDetector([](SkillDetector&) {});
        return ok;
    }
    bool waitForState(const std::string& id, ComponentStatus::State state) {
        return log_.waitUntil(
            [&] {
                auto c = component(id);
                return c && c->state == state;
            },
            kDeadline);
    }
    std::optional<ComponentStatus> component(const std::string& id) {
        for (auto& c : detector_->components()) {
            if (c.id == id) return c;
        }
        return std::nullopt;
    }

private:
    asio::io_context io_{1};
    asio::executor_work_guard<asio::io_context::executor_type> work_;
    std::shared_ptr<SkillDetector> detector_;
    std::thread thread_;
    EventLog log_;
    std::size_t listener_ = 0;
};

// ---------------------------------------------------------------------------------------------

TEST(SkillDetector, FindsSkillsByTheirTypeAndEverySupertype) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    auto hand = skillServer("urn:test:gripper", kGripperSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    h.appeared("mdns:gripper", "urn:test:gripper", hand->url());
    ASSERT_TRUE(h.waitForSkills(4)) << h.detector().instances().size();
    auto& d = h.detector();

    EXPECT_EQ(
        namesOf(d.find(skillTypeId())),
        (std::set<std::string>{"urn:test:robot Robot/Move", "urn:test:robot Robot/Ptp",
                               "urn:test:gripper Robot/Grasp", "urn:test:gripper Robot/Release"}));
    EXPECT_EQ(namesOf(d.find(robotic("MoveSkillType"))),
              (std::set<std::string>{"urn:test:robot Robot/Move", "urn:test:robot Robot/Ptp"}));
    EXPECT_EQ(namesOf(d.find(robotic("LinearMoveSkillType"))),
              (std::set<std::string>{"urn:test:robot Robot/Move"}));
    EXPECT_EQ(namesOf(d.find(robotic("CartesianLinearMoveSkillType"))),
              (std::set<std::string>{"urn:test:robot Robot/Move"}));
    EXPECT_EQ(namesOf(d.find(robotic("PtpMoveSkillType"))),
              (std::set<std::string>{"urn:test:robot Robot/Ptp"}));
    EXPECT_EQ(
        namesOf(d.find(gripper("GripperSkillType"))),
        (std::set<std::string>{"urn:test:gripper Robot/Grasp", "urn:test:gripper Robot/Release"}));
    EXPECT_TRUE(d.find(robotic("CartesianPtpMoveSkillType")).empty());
    EXPECT_TRUE(d.find(GlobalNodeId("http://opcfoundation.org/UA/", ns0::BaseObjectType)).empty());

    const auto moves = d.find(robotic("CartesianLinearMoveSkillType"));
    ASSERT_EQ(moves.size(), 1u);
    const SkillInstance& move = moves.front();
    EXPECT_EQ(move.componentUri, "urn:test:robot");
    EXPECT_EQ(move.endpointUrl, robot->url());
    EXPECT_EQ(move.nodeId, NodeId(1, "Robot/Move"));
    ASSERT_EQ(move.browsePath.size(), 2u);
    EXPECT_EQ(move.browsePath[1], (GlobalName{"urn:test:robot", "Move"}));
    std::vector<std::string> chain;
    for (const auto& t : move.types) chain.push_back(t.browseName);
    EXPECT_EQ(chain,
              (std::vector<std::string>{"CartesianLinearMoveSkillType", "LinearMoveSkillType",
                                        "MoveSkillType", "SkillType"}));
    EXPECT_EQ(move.type().id, robotic("CartesianLinearMoveSkillType"));
    EXPECT_EQ(move.types.back().id, skillTypeId());
    EXPECT_TRUE(move.isA(robotic("MoveSkillType")));
    EXPECT_FALSE(move.isA(robotic("PtpMoveSkillType")));
    EXPECT_NE(move.componentStartTime.ticks, 0);

    ASSERT_TRUE(h.waitForState("urn:test:robot", ComponentStatus::State::Connected));
    auto status = h.component("urn:test:robot");
    ASSERT_TRUE(status.has_value());
    EXPECT_EQ(status->skills, 2u);
    EXPECT_EQ(status->browses, 1u);
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Added), 4u);
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed), 0u);
}

TEST(SkillDetector, ReportsTheDeclaredParametersAsTheServerDefinesThem) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(2));

    for (const auto& skill : h.detector().instances()) {
        // What the server itself holds, read on its thread.
        struct Expected {
            std::string name;
            NodeId dataType;
            std::int32_t valueRank;
        };
        auto expected = robot->inServer([&](ua::Server& s) {
            auto& as = s.addressSpace();
            std::vector<Expected> out;
            const ua::Node* set = as.findChild(
                skill.nodeId, QualifiedName{*as.namespaceIndex(cm::kDiUri), "ParameterSet"});
            if (set == nullptr) return out;
            for (const auto& ref : set->references) {
                const ua::Node* p = ref.isForward ? as.find(ref.target) : nullptr;
                if (p != nullptr && p->nodeClass == ua::NodeClass::Variable)
                    out.push_back({p->browseName.name, p->dataType, p->valueRank});
            }
            return out;
        });
        ASSERT_FALSE(expected.empty()) << skill.browsePathString();
        ASSERT_EQ(skill.parameters.size(), expected.size()) << skill.browsePathString();
        for (const auto& e : expected) {
            auto p = std::find_if(skill.parameters.begin(), skill.parameters.end(),
                                  [&](const auto& q) { return q.browseName.name == e.name; });
            ASSERT_NE(p, skill.parameters.end()) << e.name;
            EXPECT_EQ(p->dataTypeId, e.dataType) << e.name;
            EXPECT_EQ(p->valueRank, e.valueRank) << e.name;
            EXPECT_EQ(p->browseName.namespaceUri, cm::kRoboticSkillsUri) << e.name;
        }
    }
    // Spot checks against the model (docs/models/RoboticSkills.md).
    const auto ptp = h.detector().find(robotic("JointPtpMoveSkillType"));
    ASSERT_EQ(ptp.size(), 1u);
    auto target =
        std::find_if(ptp[0].parameters.begin(), ptp[0].parameters.end(),
                     [](const auto& p) { return p.browseName.name == "TargetJointPosition"; });
    ASSERT_NE(target, ptp[0].parameters.end());
    EXPECT_EQ(target->dataType, GlobalNodeId("http://opcfoundation.org/UA/", ns0::Double));
    EXPECT_EQ(target->valueRank, 1);
    auto maxVelocity =
        std::find_if(ptp[0].parameters.begin(), ptp[0].parameters.end(),
                     [](const auto& p) { return p.browseName.name == "MaxVelocity"; });
    ASSERT_NE(maxVelocity, ptp[0].parameters.end());
    EXPECT_EQ(maxVelocity->valueRank, -1);
}

TEST(SkillDetector, ResolvesTypesThroughTheServersOwnHierarchyAndNamespaces) {
    // Namespace indices differ from the reference: two namespaces of its own come first.
    // A type of its own, "Widget", derives from GraspGripperSkillType: a skill. Another,
    // misleadingly named "CartesianLinearMoveSkillType", derives from BaseObjectType: not one.
    auto server = std::make_unique<test::RunningServer>(serverConfig("urn:test:odd"), [](ua::Server&
                                                                                             s) {
        auto& as = s.addressSpace();
        as.registerNamespace("urn:test:first");
        const std::uint16_t own = as.registerNamespace("urn:test:own-types");
        ASSERT_TRUE(ua::loadCompanionModels(as).ok());
        const auto addType = [&](std::uint32_t id, const std::string& name, const NodeId& super) {
            ua::Node type;
            type.nodeId = NodeId(own, id);
            type.nodeClass = ua::NodeClass::ObjectType;
            type.browseName = {own, name};
            type.displayName = {"", name};
            ASSERT_TRUE(as.addNode(std::move(type)).ok());
            ASSERT_EQ(as.addReference(super, NodeId(ns0::HasSubtype), NodeId(own, id)),
                      ua::status::Good);
        };
        const auto grasp = ua::findTypeByName(as, cm::kGripperSkillsUri, "GraspGripperSkillType");
        ASSERT_TRUE(grasp.has_value());
        addType(1, "Widget", *grasp);
        addType(2, "CartesianLinearMoveSkillType", NodeId(ns0::BaseObjectType));
        ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "Cell"), "Cell").ok());
        ASSERT_TRUE(ua::instantiate(as, NodeId(own, 1), NodeId(1, "Cell"),
                                    NodeId(ns0::HasComponent), QualifiedName{1, "Hand"})
                        .ok());
        ASSERT_TRUE(
            as.addObject(NodeId(1, "Cell"), NodeId(1, "Cell/Fake"), "Fake", NodeId(own, 2)).ok());
    });
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:odd", "urn:test:odd", server->url());
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(3));
    auto& d = h.detector();

    EXPECT_EQ(namesOf(d.find(skillTypeId())),
              (std::set<std::string>{"urn:test:odd Cell/Hand", "urn:test:robot Robot/Move",
                                     "urn:test:robot Robot/Ptp"}));
    EXPECT_EQ(namesOf(d.find(gripper("GraspGripperSkillType"))),
              (std::set<std::string>{"urn:test:odd Cell/Hand"}));
    EXPECT_EQ(namesOf(d.find(gripper("GripperSkillType"))),
              (std::set<std::string>{"urn:test:odd Cell/Hand"}));
    EXPECT_EQ(namesOf(d.find(robotic("CartesianLinearMoveSkillType"))),
              (std::set<std::string>{"urn:test:robot Robot/Move"}))
        << "the fake type's name must not count";
    const auto hands = d.find(GlobalNodeId("urn:test:own-types", 1u));
    ASSERT_EQ(hands.size(), 1u);
    std::vector<std::string> chain;
    for (const auto& t : hands[0].types) chain.push_back(t.browseName);
    EXPECT_EQ(chain, (std::vector<std::string>{"Widget", "GraspGripperSkillType",
                                               "GripperSkillType", "SkillType"}));
    EXPECT_EQ(hands[0].types[0].id.toString(), "nsu=urn:test:own-types;i=1");
    // GripPointOffset, GripPointType, MaxPayload, MaxGripWidth, RobotUri
    EXPECT_EQ(hands[0].parameters.size(), 5u);
}

TEST(SkillDetector, ServerWithoutSkillsIsConnectedWithNone) {
    test::RunningServer plain(serverConfig("urn:test:plain"));
    DetectorHarness h;
    h.appeared("mdns:plain", "urn:test:plain", plain.url());
    ASSERT_TRUE(h.log().waitUntil(
        [&] {
            auto c = h.component("urn:test:plain");
            return c && c->state == ComponentStatus::State::Connected;
        },
        kDeadline));
    EXPECT_TRUE(h.detector().instances().empty());
    EXPECT_EQ(h.component("urn:test:plain")->browses, 1u);
}

TEST(SkillDetector, ComponentListenersHearComponentsWithoutSkillsComeAndGo) {
    test::RunningServer plain(serverConfig("urn:test:plain"));
    DetectorHarness h;
    std::mutex m;
    std::vector<std::string> heard;  // "state id" or "forgotten:reason id"
    std::size_t id = 0;
    h.onDetector([&](SkillDetector& d) {
        id = d.subscribeComponents([&](const ComponentEvent& e) {
            const std::lock_guard lock(m);
            if (e.forgotten) {
                heard.push_back("forgotten:" + std::string(toString(e.reason)) + " " + e.status.id);
            } else if (e.status.state == ComponentStatus::State::Connected) {
                heard.push_back("connected " + e.status.id);
            }
        });
    });
    h.appeared("mdns:plain", "urn:test:plain", plain.url());
    ASSERT_TRUE(h.waitForState("urn:test:plain", ComponentStatus::State::Connected));
    h.onDetector([](SkillDetector&) {});  // the listeners have been told
    {
        const std::lock_guard lock(m);
        EXPECT_EQ(heard, (std::vector<std::string>{"connected urn:test:plain"}));
    }

    // A late listener hears what is known at once.
    std::vector<ComponentEvent> late;
    std::size_t lateId = 0;
    h.onDetector([&](SkillDetector& d) {
        lateId = d.subscribeComponents([&](const ComponentEvent& e) { late.push_back(e); });
    });
    ASSERT_EQ(late.size(), 1u);
    EXPECT_EQ(late[0].status.id, "urn:test:plain");
    EXPECT_EQ(late[0].status.state, ComponentStatus::State::Connected);
    EXPECT_FALSE(late[0].forgotten);
    h.onDetector([&](SkillDetector& d) { d.unsubscribe(lateId); });

    h.gone("mdns:plain", GoneReason::Goodbye);
    {
        const std::lock_guard lock(m);
        EXPECT_EQ(heard, (std::vector<std::string>{"connected urn:test:plain",
                                                   "forgotten:goodbye urn:test:plain"}));
    }
    EXPECT_EQ(late.size(), 1u) << "nothing after unsubscribe";
    h.onDetector([&](SkillDetector& d) { d.unsubscribe(id); });
}

TEST(SkillDetector, RemovesSkillsWhenTheirComponentIsGone) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    auto hand = skillServer("urn:test:gripper", kGripperSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    h.appeared("mdns:gripper", "urn:test:gripper", hand->url());
    ASSERT_TRUE(h.waitForSkills(4));
    // The shared list is made once per change: the same one until the skills change.
    const auto before = h.detector().snapshot();
    EXPECT_EQ(before->size(), 4u);
    EXPECT_EQ(h.detector().snapshot(), before);

    h.gone("mdns:robot", GoneReason::Goodbye);
    const auto after = h.detector().snapshot();
    EXPECT_NE(after, before);
    EXPECT_EQ(after->size(), 2u);
    EXPECT_EQ(before->size(), 4u) << "a snapshot taken earlier does not change";
    // At once, on the detector's thread: no waiting needed.
    EXPECT_EQ(
        namesOf(h.detector().instances()),
        (std::set<std::string>{"urn:test:gripper Robot/Grasp", "urn:test:gripper Robot/Release"}));
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed, RemovalReason::Goodbye), 2u);
    EXPECT_FALSE(h.component("urn:test:robot").has_value());

    h.gone("mdns:gripper", GoneReason::Expired);
    EXPECT_TRUE(h.detector().instances().empty());
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed, RemovalReason::Expired), 2u);
    EXPECT_TRUE(h.detector().find(skillTypeId()).empty());

    // Announced again: found again.
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(2));
}

TEST(SkillDetector, TwoSourcesListingOneServerMakeOneComponent) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    h.appeared("lds:urn:test:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(2));
    EXPECT_EQ(h.detector().components().size(), 1u);

    h.gone("mdns:robot", GoneReason::Goodbye);
    EXPECT_EQ(h.detector().instances().size(), 2u) << "the LDS still lists it";
    h.gone("lds:urn:test:robot", GoneReason::Unregistered);
    EXPECT_TRUE(h.detector().instances().empty());
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed, RemovalReason::Unregistered), 2u);
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Added), 2u) << "no duplicates";
}

TEST(SkillDetector, RemovesSkillsOnDisconnectAndBrowsesARestartedServerAgain) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    const std::uint16_t port = robot->port();
    const std::string url = robot->url();
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", url);
    ASSERT_TRUE(h.waitForSkills(2));
    const ua::DateTime firstStart = h.detector().instances().front().componentStartTime;

    robot.reset();  // the process ends: its connections close
    ASSERT_TRUE(h.waitForSkills(0));
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed, RemovalReason::Disconnected), 2u);
    ASSERT_TRUE(h.log().waitUntil(
        [&] {
            auto c = h.component("urn:test:robot");
            return c && c->state == ComponentStatus::State::Unreachable;
        },
        kDeadline));

    // Restarted at the same address, with one more skill: the detector, still retrying
    // while the source lists it, connects and browses the new run.
    robot = skillServer("urn:test:robot",
                        {kRobotSkills[0],
                         kRobotSkills[1],
                         {cm::kGripperSkillsUri, "MoveGripperSkillType", "Fingers"}},
                        port);
    ASSERT_TRUE(h.waitForSkills(3));
    const auto all = h.detector().instances();
    EXPECT_TRUE(std::all_of(all.begin(), all.end(),
                            [&](const auto& s) { return s.componentStartTime > firstStart; }));
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Added), 5u);
}

TEST(SkillDetector, FollowsARestartedServerToItsNewAddress) {
    // Killed and started again on another port (another mDNS name): the old sighting lingers
    // until its TTL, the new one is where the component is now.
    auto first = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:robot-a", "urn:test:robot", first->url());
    ASSERT_TRUE(h.waitForSkills(2));
    first.reset();
    ASSERT_TRUE(h.waitForSkills(0));

    auto second = skillServer("urn:test:robot", kRobotSkills);
    h.appeared("mdns:robot-b", "urn:test:robot", second->url());
    ASSERT_TRUE(h.log().waitUntil(
        [&] {
            const auto all = h.detector().instances();
            return all.size() == 2 && all.front().endpointUrl == second->url();
        },
        kDeadline));
    h.gone("mdns:robot-a", GoneReason::Expired);
    EXPECT_EQ(h.detector().instances().size(), 2u) << "still listed as robot-b";
    EXPECT_EQ(h.detector().components().size(), 1u);
}

TEST(SkillDetector, ANewStartTimeOnALiveConnectionMeansABrowseAgain) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(2));

    // Seen again with nothing changed: checked, not browsed again.
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    h.appeared("lds:urn:test:robot", "urn:test:robot", robot->url());
    EXPECT_EQ(h.component("urn:test:robot")->browses, 1u);

    // The server reports a new start (as a gateway would after its backend restarted) and
    // has a new skill: the monitored StartTime makes the detector browse again.
    robot->inServer([](ua::Server& s) {
        addSkills(s, {{cm::kGripperSkillsUri, "GraspGripperSkillType", "Grasp"}});
        const ua::DateTime later{ua::DateTime::now().ticks + 1};
        return s.addressSpace().setValueSource(NodeId(ns0::Server_ServerStatus_StartTime), [later] {
            ua::DataValue dv;
            dv.value = ua::Variant(later);
            return dv;
        });
    });
    ASSERT_TRUE(h.waitForSkills(3));
    EXPECT_EQ(h.component("urn:test:robot")->browses, 2u);
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed, RemovalReason::Restarted), 2u)
        << "the instances of the earlier run are replaced";
}

// A process stops its io_context right after shutdown(): by then every session is closed
// politely and no connection is half way (a request in flight would leak its connection).
TEST(SkillDetector, ShutdownReturnsOnceEverySessionIsClosed) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    auto hand = skillServer("urn:test:gripper", kGripperSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    h.appeared("mdns:gripper", "urn:test:gripper", hand->url());
    ASSERT_TRUE(h.waitForSkills(4));
    // Watching (idle): a connection still browsing or subscribing would be cut, not closed.
    ASSERT_TRUE(h.waitForState("urn:test:robot", ComponentStatus::State::Connected));
    ASSERT_TRUE(h.waitForState("urn:test:gripper", ComponentStatus::State::Connected));
    EXPECT_EQ(robot->inServer([](ua::Server& s) { return s.sessionCount(); }), 1u);
    h.shutdown(kDeadline);
    EXPECT_EQ(robot->inServer([](ua::Server& s) { return s.sessionCount(); }), 0u);
    EXPECT_EQ(hand->inServer([](ua::Server& s) { return s.sessionCount(); }), 0u);
    EXPECT_TRUE(h.detector().instances().empty());
}

TEST(SkillDetector, AServerThatNeverAnswersTimesOut) {
    // Listens (the kernel accepts the TCP connection) but never answers Hello.
    asio::io_context silentIo;
    asio::ip::tcp::acceptor silent(silentIo, {asio::ip::make_address("127.0.0.1"), 0});
    const std::string url = "opc.tcp://127.0.0.1:" + std::to_string(silent.local_endpoint().port());
    auto config = fastConfig();
    config.connectTimeout = 300ms;
    DetectorHarness h(config);
    const auto start = std::chrono::steady_clock::now();
    h.appeared("mdns:silent", "urn:test:silent", url);
    ASSERT_TRUE(h.log().waitUntil(
        [&] {
            auto c = h.component("urn:test:silent");
            return c && c->state == ComponentStatus::State::Unreachable;
        },
        kDeadline));
    EXPECT_GE(std::chrono::steady_clock::now() - start, 300ms);
    EXPECT_EQ(h.component("urn:test:silent")->lastError, ua::status::BadTimeout);
    EXPECT_TRUE(h.detector().instances().empty());
    h.gone("mdns:silent", GoneReason::Expired);
    EXPECT_TRUE(h.detector().components().empty());
}

TEST(SkillDetector, ComponentsTakeTurnsToConnectAndOneThatNeverAnswersHoldsOnlyItsOwn) {
    // Listens (the kernel accepts the TCP connection) but never answers Hello.
    asio::io_context silentIo;
    asio::ip::tcp::acceptor silent(silentIo, {asio::ip::make_address("127.0.0.1"), 0});
    const std::string silentUrl =
        "opc.tcp://127.0.0.1:" + std::to_string(silent.local_endpoint().port());
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    auto config = fastConfig();
    config.maxConcurrentConnects = 1;
    config.connectTimeout = 30s;  // the silent one keeps the only turn until it goes
    DetectorHarness h(config);
    h.appeared("mdns:silent", "urn:test:silent", silentUrl);
    ASSERT_TRUE(h.waitForState("urn:test:silent", ComponentStatus::State::Connecting));
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForState("urn:test:robot", ComponentStatus::State::Waiting));
    EXPECT_TRUE(h.detector().instances().empty());
    // Its source forgets the silent one: the turn passes on, and the robot is browsed.
    h.gone("mdns:silent", GoneReason::Expired);
    ASSERT_TRUE(h.waitForSkills(2));
    ASSERT_TRUE(h.waitForState("urn:test:robot", ComponentStatus::State::Connected));

    // Five more with two turns: each waits its turn, and all are found.
    std::vector<std::unique_ptr<test::RunningServer>> more;
    DetectorHarness two([] {
        auto c = fastConfig();
        c.maxConcurrentConnects = 2;
        return c;
    }());
    for (int i = 0; i < 5; ++i) {
        const std::string uri = "urn:test:gripper" + std::to_string(i);
        more.push_back(skillServer(uri, kGripperSkills));
        two.appeared("mdns:" + uri, uri, more.back()->url());
    }
    ASSERT_TRUE(two.waitForSkills(10)) << two.detector().instances().size();
    for (int i = 0; i < 5; ++i) {
        EXPECT_TRUE(two.waitForState("urn:test:gripper" + std::to_string(i),
                                     ComponentStatus::State::Connected));
    }
}

TEST(SkillDetector, AComponentThatStopsAnsweringTimesOutAndComesBack) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(2));
    ASSERT_TRUE(h.waitForState("urn:test:robot", ComponentStatus::State::Connected));

    // Freeze the server's only thread: no keep-alive arrives any more.
    std::promise<void> thaw;
    std::shared_future<void> thawed = thaw.get_future().share();
    asio::post(robot->io(), [thawed] { thawed.wait(); });
    const auto frozen = std::chrono::steady_clock::now();
    ASSERT_TRUE(h.waitForSkills(0));
    const auto noticed = std::chrono::steady_clock::now() - frozen;
    EXPECT_EQ(h.log().count(SkillEvent::Kind::Removed, RemovalReason::Timeout), 2u);
    EXPECT_LT(noticed, 2s) << "1.5 keep-alive periods + 100 ms, and some slack";
    thaw.set_value();
    ASSERT_TRUE(h.waitForSkills(2));  // the detector reconnects while the source lists it
}

TEST(SkillDetector, ListenersHearEveryChangeAndLateOnesTheCurrentSkills) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    DetectorHarness h;
    h.appeared("mdns:robot", "urn:test:robot", robot->url());
    ASSERT_TRUE(h.waitForSkills(2));
    EXPECT_EQ(h.log().lines(), (std::vector<std::string>{"added urn:test:robot Robot/Move",
                                                         "added urn:test:robot Robot/Ptp"}));

    EventLog late;
    std::size_t id = 0;
    h.onDetector(
        [&](SkillDetector& d) { id = d.subscribe([&](const SkillEvent& e) { late.record(e); }); });
    EXPECT_EQ(late.lines(), h.log().lines()) << "a late listener hears what is known";

    h.onDetector([&](SkillDetector& d) { d.unsubscribe(id); });
    h.gone("mdns:robot", GoneReason::Goodbye);
    EXPECT_EQ(late.events().size(), 2u) << "nothing after unsubscribe";
    EXPECT_EQ(h.log().lines().back(), "removed:goodbye urn:test:robot Robot/Ptp");
}

TEST(SkillDetector, QueriesFromOtherThreadsWhileComponentsComeAndGo) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    auto hand = skillServer("urn:test:gripper", kGripperSkills);
    DetectorHarness h;
    std::atomic<bool> done{false};
    std::atomic<std::size_t> reads{0};
    std::thread reader([&] {
        while (!done) {
            const auto all = h.detector().find(skillTypeId());
            const auto moves = h.detector().find(robotic("MoveSkillType"));
            EXPECT_LE(moves.size(), all.size() + 2);  // (a change may fall in between)
            (void)h.detector().components();
            ++reads;
        }
    });
    for (int round = 0; round < 3; ++round) {
        h.appeared("mdns:robot", "urn:test:robot", robot->url());
        h.appeared("mdns:gripper", "urn:test:gripper", hand->url());
        ASSERT_TRUE(h.waitForSkills(4));
        h.gone("mdns:robot", GoneReason::Goodbye);
        h.gone("mdns:gripper", GoneReason::Goodbye);
        ASSERT_TRUE(h.waitForSkills(0));
    }
    done = true;
    reader.join();
    EXPECT_GT(reads.load(), 0u);
}

// The LDS registration source, with the detector on the LDS's own thread.
TEST(SkillDetector, FollowsTheRegistrationsOfAnLdsInTheSameProcess) {
    auto robot = skillServer("urn:test:robot", kRobotSkills);
    auto ldsConfig = serverConfig("urn:test:lds");
    ldsConfig.description.applicationType = ua::ApplicationType::DiscoveryServer;
    test::RunningServer ldsServer(ldsConfig);
    EventLog log;
    std::shared_ptr<ua::lds::LocalDiscoveryServer> lds;
    std::shared_ptr<SkillDetector> detector;
    ldsServer.inServer([&](ua::Server& s) {
        ua::lds::LdsConfig lc;
        lc.registrationTimeout = 1s;
        lds = ua::lds::LocalDiscoveryServer::create(s, nullptr, lc);
        lds->start(ldsServer.io().get_executor());
        detector = SkillDetector::create(ldsServer.io().get_executor(), fastConfig());
        detector->subscribe([&log](const SkillEvent& e) { log.record(e); });
        attachLds(detector, *lds);
        return 0;
    });

    // Listeners are told in the handler that changed the map: one more handler after it
    // and the log has caught up.
    const auto settled = [&] { ldsServer.inServer([](ua::Server&) { return 0; }); };
    ua::BlockingClient client;
    ua::ClientConfig channelOnly;
    channelOnly.createSession = false;
    ASSERT_EQ(client.connect(ldsServer.url(), channelOnly), ua::status::Good);
    ua::RegisterServerRequest reg;
    reg.server.serverUri = "urn:test:robot";
    reg.server.serverNames = {{"en", "Robot"}};
    reg.server.discoveryUrls = {robot->url()};
    ASSERT_TRUE((client.request<ua::RegisterServerRequest, ua::RegisterServerResponse>(reg).ok()));
    ASSERT_TRUE(log.waitUntil([&] { return detector->instances().size() == 2; }, kDeadline));
    EXPECT_EQ(detector->instances().front().componentUri, "urn:test:robot");

    reg.server.isOnline = false;
    ASSERT_TRUE((client.request<ua::RegisterServerRequest, ua::RegisterServerResponse>(reg).ok()));
    ASSERT_TRUE(log.waitUntil([&] { return detector->instances().empty(); }, kDeadline));
    settled();
    EXPECT_EQ(log.count(SkillEvent::Kind::Removed, RemovalReason::Unregistered), 2u);

    // Registered again, then not renewed: the registration expires (1 s here).
    reg.server.isOnline = true;
    ASSERT_TRUE((client.request<ua::RegisterServerRequest, ua::RegisterServerResponse>(reg).ok()));
    ASSERT_TRUE(log.waitUntil([&] { return detector->instances().size() == 2; }, kDeadline));
    ASSERT_TRUE(log.waitUntil([&] { return detector->instances().empty(); }, kDeadline));
    settled();
    EXPECT_EQ(log.count(SkillEvent::Kind::Removed, RemovalReason::Expired), 2u);

    client.disconnect();
    ldsServer.inServer([&](ua::Server&) {
        detector->stop();
        lds->stop();
        return 0;
    });
}

// The browser alone, against a server that pages references and has one continuation point
// per session: every node is still walked.
TEST(RemoteSkillBrowser, WalksEverythingThroughContinuationPoints) {
    auto config = serverConfig("urn:test:many");
    config.limits.maxReferencesPerBrowse = 3;
    config.limits.maxBrowseContinuationPoints = 1;
    test::RunningServer server(config, [](ua::Server& s) {
        for (const char* folder : {"A", "B", "C"}) {
            std::vector<SkillSpec> skills;
            for (int i = 0; i < 7; ++i) {
                skills.push_back({cm::kGripperSkillsUri, "GraspGripperSkillType",
                                  std::string(folder) + std::to_string(i)});
            }
            addSkills(s, skills, folder);
        }
    });
    asio::io_context io{1};
    ua::Client client(io.get_executor());
    RemoteSkillBrowser browser;
    ua::Result<std::vector<RemoteSkill>> found = ua::status::BadInternalError;
    std::size_t cachedAfterFirst = 0;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            const std::string url = server.url();
            if ((co_await client.connect(url)).isBad()) co_return;
            found = co_await browser.browse(client);
            cachedAfterFirst = browser.cachedTypes();
            auto again = co_await browser.browse(client);
            EXPECT_TRUE(again.ok());
            EXPECT_EQ(browser.cachedTypes(), cachedAfterFirst) << "types come from the cache";
            co_await client.disconnect();
        },
        asio::detached);
    io.run();
    ASSERT_TRUE(found.ok()) << ua::statusName(found.status());
    EXPECT_EQ(found->size(), 21u);
    for (const auto& skill : *found)
        EXPECT_EQ(skill.parameters.size(), 5u) << skill.browsePathString();  // the grip's
    EXPECT_GT(cachedAfterFirst, 0u);
}

// A deep branch beside the skills (an arm's Robotics model nests eight levels): the climb of
// the skills' types rides in the walk's Browse requests, so the walk's depth, not its depth
// plus the type hierarchy's, is what the browse costs in round trips.
TEST(RemoteSkillBrowser, ClimbsTheTypesWhileItWalksNotAfter) {
    constexpr int kDeep = 10;
    test::RunningServer server(serverConfig("urn:test:deep"), [](ua::Server& s) {
        addSkills(s, {{cm::kGripperSkillsUri, "GraspGripperSkillType", "Grasp"}});
        auto& as = s.addressSpace();
        ua::NodeId parent(ua::ns0::ObjectsFolder);
        for (int i = 0; i < kDeep; ++i) {
            const ua::NodeId id(1, ua::String("Deep" + std::to_string(i)));
            ASSERT_TRUE(as.addFolder(parent, id, "Deep" + std::to_string(i)));
            parent = id;
        }
    });
    asio::io_context io{1};
    ua::Client client(io.get_executor());
    RemoteSkillBrowser browser;
    ua::Result<std::vector<RemoteSkill>> found = ua::status::BadInternalError;
    std::uint64_t requests = 0;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            const std::string url = server.url();
            if ((co_await client.connect(url)).isBad()) co_return;
            const auto before = client.requestsSent();
            found = co_await browser.browse(client);
            requests = client.requestsSent() - before;
            co_await client.disconnect();
        },
        asio::detached);
    io.run();
    ASSERT_TRUE(found.ok()) << ua::statusName(found.status());
    ASSERT_EQ(found->size(), 1u);
    const auto& grasp = found->front();
    ASSERT_GE(grasp.types.size(), 2u);
    EXPECT_EQ(grasp.types.front().browseName, "GraspGripperSkillType");
    EXPECT_EQ(grasp.types.back().browseName, "SkillType");
    EXPECT_EQ(grasp.parameters.size(), 5u);
    // The NamespaceArray, a Browse per level (the Objects folder, the ten folders, the
    // last one's empty answer), and one Read for the parameters and the type's name.
    EXPECT_EQ(requests, 1u + (kDeep + 1) + 1u);
}

TEST(GlobalNodeId, NamesANodeByNamespaceUri) {
    const std::vector<std::string> namespaces{"http://opcfoundation.org/UA/", "urn:app",
                                              std::string(cm::kSkillsUri)};
    EXPECT_EQ(skillTypeId().toString(), "nsu=http://skillcell.dev/UA/Skills/;i=1002");
    EXPECT_EQ(skillTypeId().toNodeId(namespaces), NodeId(2, cm::kSkillType));
    EXPECT_EQ(GlobalNodeId::from(namespaces, NodeId(2, 1002)), skillTypeId());
    EXPECT_EQ(GlobalNodeId::from(namespaces, NodeId(1, "x")),
              GlobalNodeId("urn:app", ua::String("x")));
    EXPECT_FALSE(GlobalNodeId::from(namespaces, NodeId(3, 1)).has_value());
    EXPECT_FALSE(GlobalNodeId("urn:other", 1u).toNodeId(namespaces).has_value());
}

}  // namespace
}  // namespace skillcell::skills::skill_detector_test
