#include "dashboard/cell_view.hpp"

#include <nlohmann/json.hpp>

namespace skillcell::dashboard {
namespace {

using Json = nlohmann::ordered_json;

Json toJson(const ComponentView& c) {
    return {{"uri", c.uri},
            {"endpoint", c.endpoint},
            {"up", c.up},
            {"state", c.state},
            {"startTime", c.startTime},
            {"detectedAt", c.detectedAt},
            {"detectionMs", c.detectionMs},
            {"downReason", c.downReason},
            {"paperMs", c.paperMs},
            {"skills", c.skills}};
}

Json toJson(const SkillView& s) {
    Json transitions = Json::array();
    for (const auto& t : s.transitions) {
        transitions.push_back({{"at", t.at}, {"from", t.from}, {"to", t.to}});
    }
    return {{"key", s.key},           {"component", s.component},
            {"name", s.name},         {"type", s.type},
            {"endpoint", s.endpoint}, {"available", s.available},
            {"state", s.state},       {"transitions", std::move(transitions)}};
}

Json toJson(const SceneView& s) {
    Json objects = Json::array();
    for (const auto& o : s.objects) {
        Json object = {{"id", o.id}, {"position", o.position}, {"size", o.size}};
        if (o.terminalBlock) {
            object["rail"] = o.rail;
            object["railPosition"] = o.railPosition;
        }
        objects.push_back(std::move(object));
    }
    Json rails = Json::array();
    for (const auto& r : s.rails) {
        rails.push_back({{"id", r.id}, {"start", r.start}, {"end", r.end}});
    }
    Json docks = Json::array();
    for (const auto& d : s.docks) {
        docks.push_back({{"id", d.id}, {"position", d.position}, {"tool", d.tool}});
    }
    Json fuseSlots = Json::array();
    for (const auto& f : s.fuseSlots) {
        fuseSlots.push_back({{"id", f.id}, {"position", f.position}, {"fuse", f.fuse}});
    }
    Json robots = Json::array();
    for (const auto& r : s.robots) {
        robots.push_back({{"id", r.id},
                          {"base", r.base},
                          {"flange", r.flange},
                          {"mountedTool", r.mountedTool},
                          {"graspedObject", r.graspedObject}});
    }
    return {{"robots", std::move(robots)},
            {"objects", std::move(objects)},
            {"docks", std::move(docks)},
            {"rails", std::move(rails)},
            {"fuseSlots", std::move(fuseSlots)}};
}

Json toJson(const std::vector<RunView>& runs) {
    Json out = Json::array();
    for (const auto& r : runs) {
        Json steps = Json::array();
        for (const auto& s : r.steps) {
            steps.push_back({{"index", s.index},
                             {"attempt", s.attempt},
                             {"state", s.state},
                             {"skillType", s.skillType},
                             {"component", s.component},
                             {"startedMs", s.startedMs},
                             {"endedMs", s.endedMs},
                             {"reason", s.reason},
                             {"note", s.note}});
        }
        out.push_back({{"id", r.id},
                       {"process", r.process},
                       {"state", r.state},
                       {"reason", r.reason},
                       {"startedMs", r.startedMs},
                       {"endedMs", r.endedMs},
                       {"priority", r.priority},
                       {"steps", std::move(steps)}});
    }
    return out;
}

Json toJson(const std::vector<ProcessView>& processes) {
    Json out = Json::array();
    for (const auto& p : processes) {
        out.push_back({{"iri", p.iri}, {"steps", p.steps}, {"problem", p.problem}});
    }
    return out;
}

// What servers send may be any bytes: replaced where not UTF-8.
std::string text(const Json& j) {
    return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace

std::string CellView::keyOf(const skills::SkillInstance& skill) {
    return skill.componentUri + " " + skill.nodeId.toString();
}

void CellView::comeUp(ComponentView& c, const std::string& endpoint, ua::DateTime startTime) {
    if (!endpoint.empty()) c.endpoint = endpoint;
    if (c.up) return;
    const auto now = ua::DateTime::now();
    c.up = true;
    c.state = "up";
    c.downReason.clear();
    c.detectedAt = now.toIso8601();
    c.startTime = startTime.toIso8601();
    c.paperMs = paper_ ? paper_(c.uri) : 0;
    c.detectionMs =
        startTime.ticks == 0
            ? -1.0
            : static_cast<double>(now.unixNanoseconds() - startTime.unixNanoseconds()) / 1e6;
}

void CellView::componentStatus(const skills::ComponentEvent& event) {
    using State = skills::ComponentStatus::State;
    const auto& st = event.status;
    // The detector names a component without an application URI "key:<source key>".
    if (st.id.empty() || st.id.rfind("key:", 0) == 0) return;
    const std::lock_guard lock(mutex_);
    auto& c = components_[st.id];
    c.uri = st.id;
    if (event.forgotten) {
        if (c.up || c.state != "gone") {
            c.up = false;
            c.state = "gone";
            c.downReason = std::string(skills::toString(event.reason));
        }
    } else if (st.state == State::Connected) {
        comeUp(c, st.endpointUrl, st.startTime);
    } else if (st.state == State::Unreachable) {
        if (c.up) c.downReason = "unreachable: " + std::string(ua::statusName(st.lastError));
        c.up = false;
        c.state = "unreachable";
    } else if (!c.up) {
        c.state = "connecting";
        if (c.endpoint.empty()) c.endpoint = st.endpointUrl;
    }
    publishComponent(c);
}

void CellView::skillAdded(const skills::SkillInstance& skill) {
    const std::lock_guard lock(mutex_);
    auto& c = components_[skill.componentUri];
    c.uri = skill.componentUri;
    // A component's skills come before the detector calls it connected.
    comeUp(c, skill.endpointUrl, skill.componentStartTime);
    auto& s = skills_[keyOf(skill)];
    const bool wasAvailable = s.available;
    s.key = keyOf(skill);
    s.component = skill.componentUri;
    s.name = skill.browsePathString();
    s.type = skill.type().browseName;
    s.endpoint = skill.endpointUrl;
    s.available = true;
    if (!wasAvailable) ++c.skills;
    publishComponent(c);
    publishSkill(s);
}

void CellView::skillRemoved(const skills::SkillInstance& skill, skills::RemovalReason reason) {
    const std::lock_guard lock(mutex_);
    auto it = skills_.find(keyOf(skill));
    if (it == skills_.end() || !it->second.available) return;
    it->second.available = false;
    it->second.state.clear();
    auto& c = components_[skill.componentUri];
    if (c.skills > 0) --c.skills;
    // A restarted component is browsed again and stays up; otherwise the component's status
    // follows (unreachable, or gone), but the skills' reason is the better one to show.
    if (c.skills == 0 && reason != skills::RemovalReason::Restarted && c.up) {
        c.up = false;
        c.state = reason == skills::RemovalReason::Disconnected ||
                          reason == skills::RemovalReason::Timeout
                      ? "unreachable"
                      : "gone";
        c.downReason = std::string(skills::toString(reason));
    }
    publishComponent(c);
    publishSkill(it->second);
}

void CellView::skillState(const std::string& key, std::optional<skills::SkillState> state,
                          const skills::SkillTransitionRecord* transition) {
    const std::lock_guard lock(mutex_);
    auto it = skills_.find(key);
    if (it == skills_.end() || !it->second.available) return;
    auto& s = it->second;
    if (state) s.state = std::string(skills::name(*state));
    if (transition != nullptr) {
        s.transitions.push_back(
            {transition->time.toIso8601(),
             transition->from ? std::string(skills::name(*transition->from)) : "",
             transition->to ? std::string(skills::name(*transition->to)) : ""});
        while (s.transitions.size() > kMaxTransitions) s.transitions.pop_front();
    }
    publishSkill(s);
}

void CellView::publishComponent(const ComponentView& c) {
    hub_.publish(text({{"type", "component"}, {"version", ++version_}, {"component", toJson(c)}}));
}

void CellView::publishSkill(const SkillView& s) {
    hub_.publish(text({{"type", "skill"}, {"version", ++version_}, {"skill", toJson(s)}}));
}

void CellView::scene(const SceneView& scene) {
    const std::lock_guard lock(mutex_);
    if (scene_ && *scene_ == scene) return;
    scene_ = scene;
    hub_.publish(text({{"type", "scene"}, {"version", ++version_}, {"scene", toJson(scene)}}));
}

void CellView::runs(const std::vector<RunView>& runs) {
    const std::lock_guard lock(mutex_);
    if (runs_ && *runs_ == runs) return;
    runs_ = runs;
    hub_.publish(text({{"type", "runs"}, {"version", ++version_}, {"runs", toJson(runs)}}));
}

void CellView::processes(const std::vector<ProcessView>& processes) {
    const std::lock_guard lock(mutex_);
    if (processes_ && *processes_ == processes) return;
    processes_ = processes;
    hub_.publish(
        text({{"type", "processes"}, {"version", ++version_}, {"processes", toJson(processes)}}));
}

std::pair<std::string, std::shared_ptr<EventHub::Listener>> CellView::open() {
    const std::lock_guard lock(mutex_);
    Json components = Json::array();
    for (const auto& [uri, c] : components_) components.push_back(toJson(c));
    Json skills = Json::array();
    for (const auto& [key, s] : skills_) skills.push_back(toJson(s));
    Json snapshot{{"type", "snapshot"},
                  {"version", version_},
                  {"components", std::move(components)},
                  {"skills", std::move(skills)}};
    if (scene_) snapshot["scene"] = toJson(*scene_);
    if (runs_) snapshot["runs"] = toJson(*runs_);
    if (processes_) snapshot["processes"] = toJson(*processes_);
    return {text(snapshot), hub_.subscribe()};
}

std::map<std::string, ComponentView> CellView::components() const {
    const std::lock_guard lock(mutex_);
    return components_;
}

std::map<std::string, SkillView> CellView::skills() const {
    const std::lock_guard lock(mutex_);
    return skills_;
}

}  // namespace skillcell::dashboard
