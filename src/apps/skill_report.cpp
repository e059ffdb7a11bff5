#include "skill_report.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace skillcell::apps {

namespace {

std::string quoted(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\r':
                out += "\\r";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char escaped[8];
                    std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
                    out += escaped;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

/// `"key":value` pairs of one skill instance (no braces).
std::string jsonFields(const skills::SkillInstance& s) {
    std::string types;
    std::string typeNames;
    for (const auto& t : s.types) {
        types += (types.empty() ? "" : ",") + quoted(t.id.toString());
        typeNames += (typeNames.empty() ? "" : ",") + quoted(t.browseName);
    }
    std::string parameters;
    for (const auto& p : s.parameters) {
        parameters += std::string(parameters.empty() ? "" : ",") +
                      "{\"name\":" + quoted(p.browseName.name) +
                      ",\"namespace\":" + quoted(p.browseName.namespaceUri) +
                      ",\"dataType\":" + quoted(p.dataType.toString()) +
                      ",\"valueRank\":" + std::to_string(p.valueRank) + "}";
    }
    return "\"type\":" + quoted(s.type().browseName) +
           ",\"typeId\":" + quoted(s.type().id.toString()) + ",\"types\":[" + types +
           "],\"typeNames\":[" + typeNames + "],\"component\":" + quoted(s.componentUri) +
           ",\"endpoint\":" + quoted(s.endpointUrl) + ",\"nodeId\":" + quoted(s.nodeId.toString()) +
           ",\"browsePath\":" + quoted(s.browsePathString()) +
           ",\"startTime\":" + quoted(s.componentStartTime.toIso8601()) + ",\"parameters\":[" +
           parameters + "]";
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
        if (!added) out << ",\"reason\":" << quoted(skills::toString(event.reason));
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
