// The dashboard's model and its event queues: what a page hears, in which order, and that a
// page which stops reading cannot hold the server's memory.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "dashboard/cell_view.hpp"
#include "dashboard/event_hub.hpp"

namespace skillcell::dashboard {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

skills::SkillInstance skill(const std::string& component, const std::string& name) {
    skills::SkillInstance s;
    s.componentUri = component;
    s.endpointUrl = "opc.tcp://198.18.0.2:4840";
    s.nodeId = ua::NodeId(2, ua::String("Skills/" + name));
    s.browsePath = {{component, "Skills"}, {component, name}};
    s.types = {
        {skills::GlobalNodeId(std::string_view("http://skillcell.dev/UA/GripperSkills/"), 1002),
         "GraspGripperSkillType"}};
    s.componentStartTime = ua::DateTime::now();
    return s;
}

TEST(EventHub, EveryListenerHearsEveryEventInOrder) {
    EventHub hub;
    auto a = hub.subscribe();
    auto b = hub.subscribe();
    hub.publish("1");
    hub.publish("2");
    EXPECT_EQ(a->next(0ms), "1");
    EXPECT_EQ(a->next(0ms), "2");
    EXPECT_EQ(b->next(0ms), "1");
    EXPECT_EQ(b->next(0ms), "2");
    EXPECT_EQ(a->next(10ms), std::nullopt);  // nothing more: a bounded wait
    EXPECT_FALSE(a->closed());
    b.reset();  // a page that went away is forgotten
    hub.publish("3");
    EXPECT_EQ(hub.listeners(), 1U);
}

TEST(EventHub, AWaitingReaderWakesAtOnce) {
    EventHub hub;
    auto l = hub.subscribe();
    std::thread writer([&hub] { hub.publish("late"); });
    EXPECT_EQ(l->next(10s), "late");
    writer.join();
}

TEST(EventHub, AReaderThatFallsBehindIsDroppedAndCloseEndsEveryone) {
    EventHub hub;
    auto slow = hub.subscribe();
    auto fast = hub.subscribe();
    for (std::size_t i = 0; i <= EventHub::kMaxQueued; ++i) {
        hub.publish(std::to_string(i));
        ASSERT_TRUE(fast->next(0ms));
    }
    EXPECT_TRUE(slow->closed());
    EXPECT_EQ(slow->next(0ms), std::nullopt);
    EXPECT_FALSE(fast->closed());
    hub.close();
    EXPECT_TRUE(fast->closed());
    EXPECT_TRUE(hub.subscribe()->closed());  // after close, nobody listens
}

TEST(CellView, ASnapshotAndTheChangesAfterItTellTheWholeStory) {
    EventHub hub;
    CellView view(hub,
                  [](const std::string& uri) { return uri == "urn:test:gripper" ? 253.0 : 0.0; });
    view.skillAdded(skill("urn:test:gripper", "Grasp"));
    auto [snapshot, listener] = view.open();
    const auto s = json::parse(snapshot);
    EXPECT_EQ(s["type"], "snapshot");
    ASSERT_EQ(s["components"].size(), 1U);
    EXPECT_EQ(s["components"][0]["uri"], "urn:test:gripper");
    EXPECT_EQ(s["components"][0]["up"], true);
    EXPECT_GE(s["components"][0]["detectionMs"].get<double>(), 0.0);
    EXPECT_EQ(s["components"][0]["paperMs"], 253.0);  // beside the paper's figure
    ASSERT_EQ(s["skills"].size(), 1U);
    EXPECT_EQ(s["skills"][0]["name"], "Skills/Grasp");
    EXPECT_EQ(s["skills"][0]["type"], "GraspGripperSkillType");
    const auto version = s["version"].get<std::uint64_t>();

    const std::string key = CellView::keyOf(skill("urn:test:gripper", "Grasp"));
    skills::SkillTransitionRecord t;
    t.time = ua::DateTime::now();
    t.from = skills::SkillState::Ready;
    t.to = skills::SkillState::Running;
    view.skillState(key, t.to, &t);
    auto e = json::parse(*listener->next(1s));
    EXPECT_EQ(e["type"], "skill");
    EXPECT_GT(e["version"].get<std::uint64_t>(), version);
    EXPECT_EQ(e["skill"]["state"], "Running");
    ASSERT_EQ(e["skill"]["transitions"].size(), 1U);
    EXPECT_EQ(e["skill"]["transitions"][0]["from"], "Ready");
    EXPECT_EQ(e["skill"]["transitions"][0]["to"], "Running");

    // Only the last kMaxTransitions are kept.
    for (std::size_t i = 0; i < CellView::kMaxTransitions + 3; ++i) view.skillState(key, t.to, &t);
    EXPECT_EQ(view.skills().at(key).transitions.size(), CellView::kMaxTransitions);

    view.skillRemoved(skill("urn:test:gripper", "Grasp"), skills::RemovalReason::Goodbye);
    EXPECT_FALSE(view.components().at("urn:test:gripper").up);
    EXPECT_EQ(view.components().at("urn:test:gripper").downReason, "goodbye");
    EXPECT_FALSE(view.skills().at(key).available);
    // A state for a skill that is gone changes nothing.
    view.skillState(key, skills::SkillState::Ready, nullptr);
    EXPECT_EQ(view.skills().at(key).state, "");
}

TEST(CellView, ComponentsWithoutSkillsComeAndGoByTheirStatus) {
    using State = skills::ComponentStatus::State;
    EventHub hub;
    CellView view(hub);
    skills::ComponentEvent e;
    e.status.id = "urn:test:lds";
    e.status.endpointUrl = "opc.tcp://198.18.0.1:4840";
    e.status.state = State::Connecting;
    view.componentStatus(e);
    EXPECT_EQ(view.components().at("urn:test:lds").state, "connecting");
    EXPECT_FALSE(view.components().at("urn:test:lds").up);

    e.status.state = State::Connected;
    e.status.startTime = ua::DateTime::now();
    view.componentStatus(e);
    auto lds = view.components().at("urn:test:lds");
    EXPECT_TRUE(lds.up);
    EXPECT_EQ(lds.state, "up");
    EXPECT_EQ(lds.skills, 0U);
    EXPECT_EQ(lds.endpoint, "opc.tcp://198.18.0.1:4840");
    EXPECT_GE(lds.detectionMs, 0.0);

    e.status.state = State::Unreachable;
    e.status.lastError = ua::status::BadConnectionClosed;
    view.componentStatus(e);
    EXPECT_FALSE(view.components().at("urn:test:lds").up);
    EXPECT_EQ(view.components().at("urn:test:lds").downReason, "unreachable: BadConnectionClosed");

    e.forgotten = true;
    e.reason = skills::RemovalReason::Expired;
    view.componentStatus(e);
    EXPECT_EQ(view.components().at("urn:test:lds").state, "gone");
    EXPECT_EQ(view.components().at("urn:test:lds").downReason, "expired");

    // A component whose skills went with a restart stays up; one whose skills were lost does
    // not, and says why.
    view.skillAdded(skill("urn:test:gripper", "Grasp"));
    view.skillRemoved(skill("urn:test:gripper", "Grasp"), skills::RemovalReason::Restarted);
    EXPECT_TRUE(view.components().at("urn:test:gripper").up);
    view.skillAdded(skill("urn:test:gripper", "Grasp"));
    view.skillRemoved(skill("urn:test:gripper", "Grasp"), skills::RemovalReason::Timeout);
    EXPECT_EQ(view.components().at("urn:test:gripper").state, "unreachable");
    EXPECT_EQ(view.components().at("urn:test:gripper").downReason, "timeout");
}

TEST(CellView, TheSceneIsPushedWhenItChangesAndOnlyThen) {
    EventHub hub;
    CellView view(hub);
    auto [before, listener] = view.open();
    EXPECT_FALSE(json::parse(before).contains("scene"));  // no world: no picture
    SceneView scene;
    scene.robots = {{"ur5", {0, 0, 0}, {0.3, -0.45, 0.35}, "parallel", ""}};
    scene.objects = {{"boxA", {0.45, 0.15, 0.025}, {0.04, 0.1, 0.05}, false, "", 0}};
    scene.docks = {{"dockP", {0.3, -0.45, 0.35}, ""}};
    view.scene(scene);
    view.scene(scene);  // the same again: nothing to say
    auto e = json::parse(*listener->next(1s));
    EXPECT_EQ(e["type"], "scene");
    EXPECT_EQ(e["scene"]["robots"][0]["mountedTool"], "parallel");
    EXPECT_EQ(e["scene"]["robots"][0]["id"], "ur5");
    EXPECT_EQ(e["scene"]["objects"][0]["id"], "boxA");
    EXPECT_DOUBLE_EQ(e["scene"]["objects"][0]["position"][0].get<double>(), 0.45);
    EXPECT_EQ(e["scene"]["docks"][0]["tool"], "");
    EXPECT_EQ(listener->next(10ms), std::nullopt);
    scene.objects[0].position = {0.5, -0.2, 0.025};  // the box was moved
    view.scene(scene);
    EXPECT_DOUBLE_EQ(
        json::parse(*listener->next(1s))["scene"]["objects"][0]["position"][1].get<double>(), -0.2);
    auto [after, again] = view.open();
    EXPECT_EQ(json::parse(after)["scene"]["objects"][0]["position"][0], 0.5);
}

TEST(CellView, TheKnowledgeBasesProcessesArePushedWhenTheyChange) {
    EventHub hub;
    CellView view(hub);
    auto [before, listener] = view.open();
    EXPECT_FALSE(json::parse(before).contains("processes"));  // no KB: no list
    std::vector<ProcessView> processes{
        {"http://skillcell.dev/processes#Sort",
         {"ChangeToolSkillType", "PickAndPlaceSkillType"},
         ""},
        {"http://skillcell.dev/processes#Broken", {}, "step 2 has no skill type"}};
    view.processes(processes);
    view.processes(processes);  // unchanged: nothing to say
    auto e = json::parse(*listener->next(1s));
    EXPECT_EQ(e["type"], "processes");
    ASSERT_EQ(e["processes"].size(), 2U);
    EXPECT_EQ(e["processes"][0]["steps"][1], "PickAndPlaceSkillType");
    EXPECT_EQ(e["processes"][1]["problem"], "step 2 has no skill type");
    EXPECT_EQ(listener->next(10ms), std::nullopt);
    auto [after, again] = view.open();
    EXPECT_EQ(json::parse(after)["processes"][0]["iri"], "http://skillcell.dev/processes#Sort");
}

TEST(CellView, NamesThatAreNotUtf8DoNotBreakTheJson) {
    EventHub hub;
    CellView view(hub);
    view.skillAdded(skill("urn:test:\xff", "Gr\xfe"));
    auto [snapshot, listener] = view.open();
    const auto s = json::parse(snapshot);  // throws if it were not valid JSON
    EXPECT_EQ(s["skills"].size(), 1U);
}

}  // namespace
}  // namespace skillcell::dashboard
