#include "skill_report.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace skillcell::apps {

// At namespace scope, as in the other commands: in a unity batch, an alias in an anonymous
// namespace would shadow theirs.
using Json = nlohmann::ordered_json;

namespace {

/// One skill instance's fields, after `event` (and `reason`) in `j`.
void addFields(Json& j, const skills::SkillInstance& s) {
    Json types = Json::array();
    Json typeNames = Json::array();
    for (const auto& t : s.types) {
        types.push_back(t.id.toString());
        typeNames.push_back(t.browseName);
    }
    Json parameters = Json::array();
    for (const auto& p : s.parameters) {
        parameters.push_back({{"name", p.browseName.name},
                              {"namespace", p.browseName.namespaceUri},
                              {"dataType", p.dataType.toString()},
                              {"valueRank", p.valueRank}});
    }
    j["type"] = s.type().browseName;
    j["typeId"] = s.type().id.toString();
    j["types"] = std::move(types);
    j["typeNames"] = std::move(typeNames);
    j["component"] = s.componentUri;
    j["endpoint"] = s.endpointUrl;
    j["nodeId"] = s.nodeId.toString();
    j["browsePath"] = s.browsePathString();
    j["startTime"] = s.componentStartTime.toIso8601();
    j["parameters"] = std::move(parameters);
}

/// One line of JSON; servers send any bytes, and what is not UTF-8 is replaced.
void printLine(std::ostream& out, const Json& j) {
    out << j.dump(-1, ' ', false, Json::error_handler_t::replace) << "\n";
}

std::string textFields(const skills::SkillInstance& s) {
    return s.type().browseName + " " + s.componentUri + " " + s.endpointUrl;
}

}  // namespace

void printSkillEvent(std::ostream& out, const skills::SkillEvent& event, bool json) {
    const auto& s = event.instance;
    const bool added = event.kind == skills::SkillEvent::Kind::Added;
    if (json) {
        Json j;
        j["event"] = added ? "added" : "removed";
        if (!added) j["reason"] = skills::toString(event.reason);
        addFields(j, s);
        printLine(out, j);
    } else if (added) {
        out << "SKILL ADDED " << textFields(s) << " " << s.nodeId.toString() << "\n";
    } else {
        out << "SKILL REMOVED " << textFields(s) << " " << skills::toString(event.reason) << " "
            << s.nodeId.toString() << "\n";
    }
    out.flush();
}

void printSkillSnapshot(std::ostream& out, std::vector<skills::SkillInstance> instances,
                        bool json) {
    std::sort(instances.begin(), instances.end(), [](const auto& a, const auto& b) {
        return std::tie(a.componentUri, a.nodeId) < std::tie(b.componentUri, b.nodeId);
    });
    if (!json) out << "SNAPSHOT " << instances.size() << "\n";
    for (const auto& s : instances) {
        if (json) {
            Json j;
            j["event"] = "skill";
            addFields(j, s);
            printLine(out, j);
        } else {
            out << "SKILL " << textFields(s) << " " << s.nodeId.toString() << "\n";
        }
    }
    if (json) {
        printLine(out, Json{{"event", "end"}, {"count", instances.size()}});
    } else {
        out << "END\n";
    }
    out.flush();
}

}  // namespace skillcell::apps
