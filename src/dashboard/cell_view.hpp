#pragma once
// CellView: what the dashboard shows of the cell, kept current from the SkillDetector's
// events and the skills' own transition events, and pushed to the pages as JSON (one
// snapshot on connect, then one event per change, each with a version number so that a
// page can tell order). Everything is under one lock, so a page's snapshot and the events
// it hears after it fit together.
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "dashboard/event_hub.hpp"
#include "skills/skill_client.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::dashboard {

struct ComponentView {
    std::string uri;
    std::string endpoint;
    bool up = false;
    std::string state;        // "connecting", "up", "unreachable", "gone"
    std::string startTime;    // the server's StartTime, ISO 8601
    std::string detectedAt;   // when the dashboard learnt of it, ISO 8601
    double detectionMs = -1;  // detectedAt - startTime: from start to detection
    std::string downReason;   // why it went down (goodbye, expired, disconnected, ...)
    double paperMs = 0;       // the paper's detection time for this part; 0: none
    std::size_t skills = 0;   // skills available now
};

struct SkillView {
    std::string key;  // component URI + " " + node id
    std::string component;
    std::string name;  // browse path
    std::string type;
    std::string endpoint;
    bool available = false;
    std::string state;  // Ready, Running, Halted, ... ("" until known)
    struct Transition {
        std::string at;  // ISO 8601 (the server's clock)
        std::string from;
        std::string to;
    };
    std::deque<Transition> transitions;  // the last kMaxTransitions, newest last
};

/// The world model's scene, as the top view shows it: positions in metres in the cell's
/// frame (rotations are not drawn).
struct SceneView {
    struct Box {
        std::string id;
        std::array<double, 3> position{};
        std::array<double, 3> size{};
        bool terminalBlock = false;
        std::string rail;         // a terminal block's rail; empty when on none
        double railPosition = 0;  // its centre along that rail, m
        friend bool operator==(const Box&, const Box&) = default;
    };
    /// A DIN rail: from its start to its end, which do not move.
    struct Rail {
        std::string id;
        std::array<double, 3> start{};
        std::array<double, 3> end{};
        friend bool operator==(const Rail&, const Rail&) = default;
    };
    struct Dock {
        std::string id;
        std::array<double, 3> position{};
        std::string tool;  // stored in it; empty when empty
        friend bool operator==(const Dock&, const Dock&) = default;
    };
    /// A fuse box's slot: its opening, which does not move, and the fuse seated in it.
    struct FuseSlot {
        std::string id;
        std::array<double, 3> position{};
        std::string fuse;  // empty when none
        friend bool operator==(const FuseSlot&, const FuseSlot&) = default;
    };
    /// A robot: where its base stands, where its flange is, the tool on it and what it holds.
    struct Robot {
        std::string id;
        std::array<double, 3> base{};
        std::array<double, 3> flange{};
        std::string mountedTool;
        std::string graspedObject;
        friend bool operator==(const Robot&, const Robot&) = default;
    };
    std::vector<Robot> robots;
    std::vector<Box> objects;
    std::vector<Dock> docks;
    std::vector<Rail> rails;
    std::vector<FuseSlot> fuseSlots;
    friend bool operator==(const SceneView&, const SceneView&) = default;
};

/// A run of the MES as its journal has it: the steps with their times, for the timeline.
struct RunView {
    struct Step {
        int index = 0;
        int attempt = 1;
        std::string state;
        std::string skillType;  // the type's local name
        std::string component;
        std::int64_t startedMs = 0;  // Unix time
        std::int64_t endedMs = 0;    // 0 while it runs
        std::string reason;
        std::string note;  // why this attempt: a retry, a reset before it
        friend bool operator==(const Step&, const Step&) = default;
    };
    std::int64_t id = 0;
    std::string process;
    std::string state;
    std::string reason;
    std::int64_t startedMs = 0;
    std::int64_t endedMs = 0;
    std::vector<Step> steps;
    int priority = 0;  // of the order
    friend bool operator==(const RunView&, const RunView&) = default;
};

/// A process the knowledge base holds, as the page lists it.
struct ProcessView {
    std::string iri;
    std::vector<std::string> steps;  // each step's skill type (local name), in order
    std::string problem;             // why it cannot be read; empty when it can
    friend bool operator==(const ProcessView&, const ProcessView&) = default;
};

class CellView {
public:
    static constexpr std::size_t kMaxTransitions = 8;

    /// The paper's detection time of a component by its application URI (0: none).
    using PaperFigures = std::function<double(const std::string& applicationUri)>;

    explicit CellView(EventHub& hub, PaperFigures paper = {})
        : hub_(hub), paper_(std::move(paper)) {}

    /// What discovery knows of a component, whether it offers skills or not (an LDS, the
    /// KB, the world model).
    void componentStatus(const skills::ComponentEvent& event);
    void skillAdded(const skills::SkillInstance& skill);
    void skillRemoved(const skills::SkillInstance& skill, skills::RemovalReason reason);
    /// The skill's state as read or as a transition event brought it.
    void skillState(const std::string& key, std::optional<skills::SkillState> state,
                    const skills::SkillTransitionRecord* transition);

    /// The world's scene as last read; published only when it changed.
    void scene(const SceneView& scene);

    /// The last runs of the MES, oldest first; published only when they changed.
    void runs(const std::vector<RunView>& runs);

    /// The processes in the knowledge base; published only when they changed.
    void processes(const std::vector<ProcessView>& processes);

    /// The whole view as the "snapshot" event, and a listener that hears every change after
    /// it, taken together.
    [[nodiscard]] std::pair<std::string, std::shared_ptr<EventHub::Listener>> open();
    [[nodiscard]] static std::string keyOf(const skills::SkillInstance& skill);

    [[nodiscard]] std::map<std::string, ComponentView> components() const;
    [[nodiscard]] std::map<std::string, SkillView> skills() const;

private:
    /// Marks `c` up, with its detection time, unless it is up already (under mutex_).
    void comeUp(ComponentView& c, const std::string& endpoint, ua::DateTime startTime);
    void publishComponent(const ComponentView& c);  // under mutex_
    void publishSkill(const SkillView& s);          // under mutex_

    EventHub& hub_;
    PaperFigures paper_;
    mutable std::mutex mutex_;
    std::uint64_t version_ = 0;
    std::map<std::string, ComponentView> components_;
    std::map<std::string, SkillView> skills_;
    std::optional<SceneView> scene_;
    std::optional<std::vector<RunView>> runs_;
    std::optional<std::vector<ProcessView>> processes_;
};

}  // namespace skillcell::dashboard
