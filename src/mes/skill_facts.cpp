#include "mes/skill_facts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "kb/component_graph.hpp"
#include "kb/knowledge_base.hpp"

namespace skillcell::mes {
namespace {

std::string proc(const char* local) {
    return std::string(kProcessNs) + local;
}

// Text compares as written; two numbers by value ("0.50" is "0.5").
bool sameValue(const std::string& a, const std::string& b) {
    if (a == b) return true;
    const auto x = parseNumber(a);
    const auto y = parseNumber(b);
    return x && y && *x == *y;
}

// '"parallel", "vacuum"': values as reasons list them.
std::string quoted(const std::vector<std::string>& values) {
    std::string out;
    for (const auto& v : values) out += (out.empty() ? "\"" : ", \"") + v + "\"";
    return out;
}

// The smallest number among `values` (a rating said twice counts at its lower value).
std::optional<double> leastNumber(const std::vector<std::string>& values) {
    std::optional<double> out;
    for (const auto& v : values) {
        if (const auto x = parseNumber(v); x && (!out || *x < *out)) out = x;
    }
    return out;
}

}  // namespace

const DerivationSource* movedObject(const ProcessStep& step) {
    for (const auto& p : step.parameters) {
        const auto* source = std::get_if<DerivationSource>(&p.value);
        if (source != nullptr && !source->objectId.empty() && (source->mass || source->size)) {
            return source;
        }
    }
    return nullptr;
}

std::string cannotHold(const DerivationSource& object, const skills::SkillInstance& skill,
                       const SkillFacts& facts) {
    std::string why;
    const auto payload = leastNumber(facts.values(keyOf(skill), proc("maxPayload")));
    if (object.mass && payload && *object.mass > *payload) {
        why = "it holds at most " + fmt::format("{:g}", *payload) + " kg, and " + object.objectId +
              " weighs " + fmt::format("{:g}", *object.mass) + " kg";
    }
    const auto width = leastNumber(facts.values(keyOf(skill), proc("maxGripWidth")));
    if (object.size && width && *width > 0) {
        // Gripped across the narrower of its horizontal sides, as the pick's planner grips
        // an upright box.
        const double across = std::min((*object.size)[0], (*object.size)[1]);
        if (across > *width) {
            why += std::string(why.empty() ? "it" : "; it") + " grips at most " +
                   fmt::format("{:g}", *width) + " m across, and " + object.objectId + " is " +
                   fmt::format("{:g}", across) + " m across";
        }
    }
    return why;
}

std::vector<StepTarget> stepTargets(const ProcessStep& step) {
    std::vector<StepTarget> out;
    auto add = [&out](std::string what, const devices::Pose6& pose) {
        const bool known = std::any_of(out.begin(), out.end(), [&](const StepTarget& t) {
            return t.x == pose.x && t.y == pose.y && t.z == pose.z;
        });
        if (!known) out.push_back({std::move(what), pose.x, pose.y, pose.z});
    };
    for (const auto& p : step.parameters) {
        if (const auto* pose = std::get_if<devices::Pose6>(&p.value)) {
            if (p.name != "ToolFrame") add(p.name, *pose);
            continue;
        }
        const auto* from = std::get_if<DerivationSource>(&p.value);
        if (from == nullptr) continue;
        const std::string name = from->objectId.empty() ? shortName(from->iri) : from->objectId;
        if (from->pose) add(name, *from->pose);
        if (from->targetPose) add(name + "'s target", *from->targetPose);
    }
    return out;
}

std::string robotOf(const skills::SkillInstance& skill, const SkillFacts& facts) {
    const SkillKey key = keyOf(skill);
    if (!facts.values(key, proc("reach")).empty()) return skill.componentUri;
    const auto on = facts.values(key, proc("onRobot"));
    return on.empty() ? std::string() : on.front();
}

std::string cannotReach(const ProcessStep& step, const skills::SkillInstance& skill,
                        const SkillFacts& facts) {
    if (stepTargets(step).empty()) return {};
    SkillKey key = keyOf(skill);
    if (!facts.recorded(key)) {
        return "the knowledge base has not recorded it yet, so its reach is not known";
    }
    std::string whose = "its";
    if (facts.values(key, proc("reach")).empty()) {
        // A skill on a robot reaches where that robot does.
        const auto on = facts.values(key, proc("onRobot"));
        if (on.empty()) return {};
        const auto robot = facts.skillWith(on.front(), proc("reach"));
        if (!robot) {
            return facts.skillWith(on.front(), proc("available"))
                       ? std::string()  // a robot that does not publish its reach
                       : "the knowledge base has not recorded its robot " + on.front() +
                             " yet, so its reach is not known";
        }
        key = *robot;
        whose = "its robot " + on.front() + "'s";
    }
    const auto reach = leastNumber(facts.values(key, proc("reach")));
    if (!reach || *reach <= 0) return {};
    const auto cx = leastNumber(facts.values(key, proc("reachCentreX")));
    const auto cy = leastNumber(facts.values(key, proc("reachCentreY")));
    const auto cz = leastNumber(facts.values(key, proc("reachCentreZ")));
    const double x0 = cx.value_or(0), y0 = cy.value_or(0), z0 = cz.value_or(0);
    std::string why;
    for (const auto& t : stepTargets(step)) {
        const double d = std::hypot(t.x - x0, t.y - y0, t.z - z0);
        if (d <= *reach) continue;
        why += (why.empty() ? "" : "; ") +
               fmt::format(
                   "{} at ({:g}, {:g}, {:g}) is {:.3f} m from {} reach centre, beyond "
                   "its reach of {:g} m",
                   t.what, t.x, t.y, t.z, d, whose, *reach);
    }
    return why;
}

void SkillFacts::add(const SkillKey& skill, const std::string& propertyIri, std::string value) {
    auto& values = values_[skill][propertyIri];
    if (std::find(values.begin(), values.end(), value) == values.end()) {
        values.push_back(std::move(value));
    }
}

std::vector<std::string> SkillFacts::values(const SkillKey& skill,
                                            const std::string& propertyIri) const {
    const auto s = values_.find(skill);
    if (s == values_.end()) return {};
    const auto p = s->second.find(propertyIri);
    return p == s->second.end() ? std::vector<std::string>{} : p->second;
}

bool SkillFacts::recorded(const SkillKey& skill) const {
    return !values(skill, proc("available")).empty();
}

std::optional<SkillKey> SkillFacts::skillWith(const std::string& componentUri,
                                              const std::string& propertyIri) const {
    for (auto it = values_.lower_bound(SkillKey{componentUri, {}});
         it != values_.end() && it->first.first == componentUri; ++it) {
        if (it->second.contains(propertyIri)) return it->first;
    }
    return std::nullopt;
}

bool SkillFacts::has(const SkillKey& skill, const FactRequirement& requirement) const {
    if (requirement.propertyIri.empty()) return true;  // any instance of the type
    const auto all = values(skill, requirement.propertyIri);
    return std::any_of(all.begin(), all.end(),
                       [&](const std::string& v) { return sameValue(v, requirement.value); });
}

std::vector<std::string> requiredProperties(const ProcessStep& step) {
    std::set<std::string> out{proc("available")};
    for (const auto& r : step.requirements) {
        if (!r.propertyIri.empty()) out.insert(r.propertyIri);
    }
    // A step that moves an object of known mass or size checks the gripper's rating.
    if (!step.requirements.empty() && movedObject(step) != nullptr) {
        out.insert(proc("maxPayload"));
        out.insert(proc("maxGripWidth"));
    }
    // One that names positions checks the manipulator's reach, and of a skill on a robot
    // (a tool changer's) that robot's; one with requirements takes them on one robot.
    if (!stepTargets(step).empty()) {
        for (const char* p : {"reach", "reachCentreX", "reachCentreY", "reachCentreZ"}) {
            out.insert(proc(p));
        }
    }
    if (!stepTargets(step).empty() || !step.requirements.empty()) {
        out.insert(proc("reach"));
        out.insert(proc("onRobot"));
    }
    return {out.begin(), out.end()};
}

kb::Expected<std::string> factQuery(const std::vector<std::string>& propertyIris) {
    if (propertyIris.empty()) {
        return kb::Error{"no property to ask the knowledge base about", kb::ErrorKind::BadInput};
    }
    // Always proc:available too: without it every skill of the answer looks not recorded yet
    // (SkillFacts::recorded), and a wait for the KB to record it never ends before its bound.
    std::vector<std::string> asked = propertyIris;
    if (std::find(asked.begin(), asked.end(), proc("available")) == asked.end()) {
        asked.push_back(proc("available"));
    }
    // One branch per property: VALUES with a variable predicate would do, but plain patterns
    // are what every store gets right (docs/knowledge_base.md on Virtuoso).
    std::string where;
    for (const auto& property : asked) {
        auto ref = kb::sparqlIri(property);
        if (!ref) return ref.failure();
        where += std::string(where.empty() ? "  " : "  UNION ") + "{ ?s " + *ref + " ?v . BIND(" +
                 *ref + " AS ?p) }\n";
    }
    const std::string applicationUri = "<" + proc("applicationUri") + ">";
    const std::string offers = "<" + proc("offers") + ">";
    const std::string nodeId = "<" + proc("skillNodeId") + ">";
    return "CONSTRUCT { ?c " + applicationUri + " ?uri . ?c " + offers + " ?s . ?s " + nodeId +
           " ?id . ?s ?p ?v }\nWHERE {\n  ?c " + applicationUri + " ?uri ; " + offers +
           " ?s .\n  ?s " + nodeId + " ?id .\n" + where + "}";
}

SkillFacts parseFacts(const std::vector<kb::rdf::Triple>& triples) {
    using kb::rdf::Term;
    std::map<Term, std::string> applicationUri;  // component -> its URI
    std::map<Term, Term> offeredBy;              // skill -> component
    std::map<Term, std::string> nodeId;          // skill -> its node id text
    std::vector<const kb::rdf::Triple*> rest;
    for (const auto& t : triples) {
        const auto& p = t.predicate.value;
        if (p == proc("applicationUri")) {
            applicationUri[t.subject] = t.object.value;
        } else if (p == proc("offers")) {
            offeredBy[t.object] = t.subject;
        } else if (p == proc("skillNodeId")) {
            nodeId[t.subject] = t.object.value;
        } else {
            rest.push_back(&t);
        }
    }
    SkillFacts out;
    for (const auto* t : rest) {
        const auto component = offeredBy.find(t->subject);
        const auto id = nodeId.find(t->subject);
        if (component == offeredBy.end() || id == nodeId.end()) continue;
        const auto uri = applicationUri.find(component->second);
        if (uri == applicationUri.end()) continue;
        out.add({uri->second, id->second}, t->predicate.value, t->object.value);
    }
    return out;
}

kb::Expected<SkillFacts> readFacts(kb::SparqlStore& store,
                                   const std::vector<std::string>& propertyIris) {
    auto query = factQuery(propertyIris);
    if (!query) return query.failure();
    auto triples = constructTriples(store, *query);
    if (!triples) return triples.failure();
    return parseFacts(*triples);
}

std::string unmetSkillRequirements(const ProcessStep& step, const skills::SkillInstance& skill,
                                   const SkillFacts& facts, const std::string& robot) {
    std::string out = cannotReach(step, skill, facts);
    for (const auto& r : step.requirements) {
        if (!r.skillTypeIri.empty() || facts.has(keyOf(skill), r)) continue;
        const std::string has = quoted(facts.values(keyOf(skill), r.propertyIri));
        std::string what = "the knowledge base does not give it " + r.describe();
        if (!has.empty()) what += " (it has " + has + ")";
        out += (out.empty() ? "" : "; ") + what;
    }
    const std::string mine = robotOf(skill, facts);
    if (!robot.empty() && !mine.empty() && mine != robot) {
        out += std::string(out.empty() ? "" : "; ") + "it is on robot " + mine +
               ", and the step's other skills on " + robot;
    }
    return out;
}

CellMatch matchCellRequirements(const ProcessStep& step,
                                const std::vector<skills::SkillInstance>& live,
                                const SkillFacts& facts) {
    // The same choice for the same cell, whatever order the detector lists it in.
    std::vector<const skills::SkillInstance*> ordered;
    ordered.reserve(live.size());
    for (const auto& s : live) ordered.push_back(&s);
    std::sort(ordered.begin(), ordered.end(), [](const auto* a, const auto* b) {
        return std::pair(a->componentUri, a->browsePathString()) <
               std::pair(b->componentUri, b->browsePathString());
    });
    CellMatch out;
    out.byRequirement.resize(step.requirements.size());
    const DerivationSource* object = movedObject(step);
    // Each requirement's fitting instances, in order, and why the others do not fit.
    std::vector<std::vector<const skills::SkillInstance*>> fits(step.requirements.size());
    std::vector<std::string> passedOver(step.requirements.size());
    for (std::size_t i = 0; i < step.requirements.size(); ++i) {
        const auto& r = step.requirements[i];
        if (r.skillTypeIri.empty()) continue;
        std::string& offered = passedOver[i];
        for (const auto* s : ordered) {
            if (!isOfType(*s, r.skillTypeIri)) continue;
            if (facts.has(keyOf(*s), r)) {
                std::string why = object ? cannotHold(*object, *s, facts) : "";
                if (const std::string far = cannotReach(step, *s, facts); !far.empty()) {
                    why += (why.empty() ? "" : "; ") + far;
                }
                if (!why.empty()) {
                    offered += (offered.empty() ? "" : "; ") + where(*s) + ": " + why;
                    continue;
                }
                fits[i].push_back(s);
                continue;
            }
            const std::string has = quoted(facts.values(keyOf(*s), r.propertyIri));
            offered += (offered.empty() ? "" : "; ") + where(*s) + " has " +
                       (has.empty() ? "no " + shortName(r.propertyIri) +
                                          " in the knowledge base (not recorded yet?)"
                                    : shortName(r.propertyIri) + " " + has);
        }
        if (!fits[i].empty()) continue;
        std::string what = "the step requires " + r.describe() + ", and ";
        what += offered.empty() ? "none of that type is available"
                                : "the available ones do not fit: " + offered;
        out.unmet += (out.unmet.empty() ? "" : "; ") + what;
    }
    if (!out.unmet.empty()) return out;
    // The first choice in that order that puts them all on one robot (a gripper on the robot
    // that moves it): a search over a few instances per requirement.
    std::vector<const skills::SkillInstance*> pick(step.requirements.size(), nullptr);
    const std::function<bool(std::size_t, const std::string&)> choose =
        [&](std::size_t i, const std::string& robot) -> bool {
        if (i == step.requirements.size()) {
            out.robot = robot;
            return true;
        }
        if (step.requirements[i].skillTypeIri.empty()) return choose(i + 1, robot);
        for (const auto* s : fits[i]) {
            const std::string on = robotOf(*s, facts);
            if (!robot.empty() && !on.empty() && on != robot) continue;
            pick[i] = s;
            if (choose(i + 1, robot.empty() ? on : robot)) return true;
        }
        return false;
    };
    if (!choose(0, {})) {
        std::string each;
        for (std::size_t i = 0; i < step.requirements.size(); ++i) {
            if (step.requirements[i].skillTypeIri.empty()) continue;
            std::string on;
            for (const auto* s : fits[i]) {
                on += (on.empty() ? "" : ", ") + where(*s) + " on " +
                      (robotOf(*s, facts).empty() ? std::string("any robot") : robotOf(*s, facts));
            }
            each += (each.empty() ? "" : "; ") + step.requirements[i].describe() + ": " + on;
        }
        out.unmet = "no robot has all the step requires: " + each;
        return out;
    }
    for (std::size_t i = 0; i < step.requirements.size(); ++i) {
        if (pick[i] == nullptr) continue;
        out.byRequirement[i] = *pick[i];
        std::string skipped = passedOver[i];
        for (const auto* s : fits[i]) {
            if (s == pick[i]) break;
            skipped += (skipped.empty() ? "" : "; ") + where(*s) + ": it is on robot " +
                       robotOf(*s, facts) + ", the step's other skills on " + out.robot;
        }
        out.chosen += (out.chosen.empty() ? "" : "; ") + step.requirements[i].describe() + ": " +
                      where(*pick[i]) + (skipped.empty() ? "" : " (passed over: " + skipped + ")");
    }
    return out;
}

}  // namespace skillcell::mes
