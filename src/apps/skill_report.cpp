#include "skill_report.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "ua/types/to_string.hpp"

namespace skillcell::apps {

namespace {

/// `"key":value` pairs of one skill instance (no braces).
std::string jsonFields(const skills::SkillInstance& s) {
    std::string types;
    std::string typeNames;
    for (const auto& t : s.types) {
        types += (types.empty() ? "" : ",") + ua::jsonQuoted(t.id.toString());
        typeNames += (typeNames.empty() ? "" : ",") + ua::jsonQuoted(t.browseName);
    }
    std::string parameters;
    for (const auto& p : s.parameters) {
        parameters += std::string(parameters.empty() ? "" : ",") +
                      "{\"name\":" + ua::jsonQuoted(p.browseName.name) +
                      ",\"namespace\":" + ua::jsonQuoted(p.browseName.namespaceUri) +
                      ",\"dataType\":" + ua::jsonQuoted(p.dataType.toString()) +
                      ",\"valueRank\":" + std::to_string(p.valueRank) + "}";
    }
    return "\"type\":" + ua::jsonQuoted(s.type().browseName) +
           ",\"typeId\":" + ua::jsonQuoted(s.type().id.toString()) + ",\"types\":[" + types +
           "],\"typeNames\":[" + typeNames + "],\"component\":" + ua::jsonQuoted(s.componentUri) +
           ",\"endpoint\":" + ua::jsonQuoted(s.endpointUrl) +
           ",\"nodeId\":" + ua::jsonQuoted(s.nodeId.toString()) +
           ",\"browsePath\":" + ua::jsonQuoted(s.browsePathString()) +
           ",\"startTime\":" + ua::jsonQuoted(s.componentStartTime.toIso8601()) +
           ",\"parameters\":[" + parameters + "]";
}

std::string textFields(const skills::SkillInstance& s) {
    return s.type().browseName + " " + s.componentUri + " " + s.endpointUrl;
}

}  // namespace

void printSkillEvent(std::ostream& out, const skills::SkillEvent& event, bool json) {
    const auto& s = event.instance;
    const bool added = event.kind == skills::SkillEvent::Kind::Added;
    if (json) {
        out << "{\"event\":" << (added ? "\"added\"" : "\"removed\"");
        if (!added) out << ",\"reason\":" << ua::jsonQuoted(skills::toString(event.reason));
        out << "," << jsonFields(s) << "}\n";
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
            out << "{\"event\":\"skill\"," << jsonFields(s) << "}\n";
        } else {
            out << "SKILL " << textFields(s) << " " << s.nodeId.toString() << "\n";
        }
    }
    if (json) {
        out << "{\"event\":\"end\",\"count\":" << instances.size() << "}\n";
    } else {
        out << "END\n";
    }
    out.flush();
}

}  // namespace skillcell::apps
