#include "mes/step_binding.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kb/component_graph.hpp"
#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::mes {
namespace {

constexpr const char* kUaNamespace = "http://opcfoundation.org/UA/";
constexpr std::uint32_t kFloat = 10;  // ns=0;i=10 (not in ns0_ids.hpp)

bool isNs0(const skills::GlobalNodeId& id, std::uint32_t numeric) {
    const auto* n = std::get_if<std::uint32_t>(&id.identifier);
    return id.namespaceUri == kUaNamespace && n != nullptr && *n == numeric;
}

// A number in the form of the parameter's data type.
kb::Expected<ua::Variant> numberAs(double v, const skills::GlobalNodeId& type,
                                   const std::string& what) {
    namespace ids = ua::ns0;
    if (isNs0(type, ids::Double)) return ua::Variant(v);
    if (isNs0(type, kFloat)) return ua::Variant(static_cast<float>(v));
    const bool integral = std::isfinite(v) && std::floor(v) == v;
    auto fits = [&](auto limits) {
        return integral && v >= static_cast<double>(limits.lowest()) &&
               v <= static_cast<double>(limits.max());
    };
    if (isNs0(type, ids::Int32)) {
        if (!fits(std::numeric_limits<std::int32_t>()))
            return kb::badInput(what + ": not an Int32");
        return ua::Variant(static_cast<std::int32_t>(v));
    }
    if (isNs0(type, ids::UInt32)) {
        if (!fits(std::numeric_limits<std::uint32_t>()))
            return kb::badInput(what + ": not a UInt32");
        return ua::Variant(static_cast<std::uint32_t>(v));
    }
    return kb::badInput(what + ": a number, but the skill's parameter has the data type " +
                        type.toString());
}

kb::Expected<ua::Variant> valueFor(
    const StepParameter& given, const skills::SkillParameter& declared, const std::string& what,
    const std::vector<std::optional<skills::SkillInstance>>& cellMatches) {
    const bool frame = isNs0(declared.dataType, ua::ns0::ThreeDFrame);
    const bool text = isNs0(declared.dataType, ua::ns0::String);
    if (const auto* of = std::get_if<RequirementEndpoint>(&given.value)) {
        if (!text)
            return kb::badInput(what + ": an endpoint, but the skill's parameter is not a String");
        if (of->requirement >= cellMatches.size() || !cellMatches[of->requirement]) {
            return kb::badInput(what + ": no skill meets the requirement whose endpoint it takes");
        }
        return ua::Variant(ua::String(cellMatches[of->requirement]->endpointUrl));
    }
    if (const auto* s = std::get_if<std::string>(&given.value)) {
        if (!text)
            return kb::badInput(what + ": a text, but the skill's parameter is not a String");
        return ua::Variant(ua::String(*s));
    }
    if (const auto* n = std::get_if<double>(&given.value)) {
        return numberAs(*n, declared.dataType, what);
    }
    if (const auto* pose = std::get_if<devices::Pose6>(&given.value)) {
        if (!frame)
            return kb::badInput(what + ": a pose, but the skill's parameter is not a 3DFrame");
        return devices::frameToVariant(devices::toFrame(*pose));
    }
    const auto& from = std::get<DerivationSource>(given.value);
    const std::string source = " <" + from.iri + ">";
    if (frame) {
        // An object goes to its target; a dock (or any placed resource) gives its pose.
        const auto& pose = from.targetPose ? from.targetPose : from.pose;
        if (!pose) return kb::badInput(what + ": a 3DFrame, but" + source + " has no pose");
        return devices::frameToVariant(devices::toFrame(*pose));
    }
    if (text) {
        if (!from.objectId.empty()) return ua::Variant(ua::String(from.objectId));
        if (!from.applicationUri.empty()) return ua::Variant(ua::String(from.applicationUri));
        return kb::badInput(what + ": a String, but" + source +
                            " has neither an object id nor an application URI");
    }
    return kb::badInput(what + ": nothing derives a value of the data type " +
                        declared.dataType.toString() + " from" + source);
}

const skills::SkillParameter* declared(const skills::SkillInstance& skill,
                                       const std::string& name) {
    const auto it = std::find_if(skill.parameters.begin(), skill.parameters.end(),
                                 [&](const auto& p) { return p.browseName.name == name; });
    return it == skill.parameters.end() ? nullptr : &*it;
}

}  // namespace

SkillKey keyOf(const skills::SkillInstance& skill) {
    return {skill.componentUri, skill.nodeId.toString()};
}

TriedKey triedKeyOf(const skills::SkillInstance& skill) {
    return {keyOf(skill), skill.componentStartTime.ticks};
}

std::string where(const skills::SkillInstance& skill) {
    return skill.browsePathString() + " of " + skill.componentUri;
}

bool isOfType(const skills::SkillInstance& skill, const std::string& typeIri) {
    return std::any_of(skill.types.begin(), skill.types.end(),
                       [&](const auto& t) { return kb::skillTypeIri(t) == typeIri; });
}

std::string unsuitability(const ProcessStep& step, const skills::SkillInstance& skill) {
    if (!isOfType(skill, step.skillTypeIri)) return "it is not a " + shortName(step.skillTypeIri);
    for (const auto& p : step.parameters) {
        if (declared(skill, p.name) == nullptr) return "it has no parameter " + p.name;
    }
    return {};
}

std::vector<const skills::SkillInstance*> candidates(const ProcessStep& step,
                                                     const std::vector<skills::SkillInstance>& live,
                                                     const std::set<TriedKey>& excluded) {
    // Sorted by keys made once each, not once per comparison.
    std::vector<std::pair<std::pair<std::string, std::string>, const skills::SkillInstance*>> keyed;
    for (const auto& s : live) {
        if (!excluded.contains(triedKeyOf(s)) && unsuitability(step, s).empty()) {
            keyed.emplace_back(std::pair(s.componentUri, s.browsePathString()), &s);
        }
    }
    std::sort(keyed.begin(), keyed.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<const skills::SkillInstance*> out;
    out.reserve(keyed.size());
    for (const auto& [key, s] : keyed) out.push_back(s);
    return out;
}

kb::Expected<std::map<std::string, ua::Variant>> parameterValues(
    const ProcessStep& step, const skills::SkillInstance& skill,
    const std::vector<std::optional<skills::SkillInstance>>& cellMatches) {
    std::map<std::string, ua::Variant> out;
    for (const auto& p : step.parameters) {
        const auto* d = declared(skill, p.name);
        const std::string what = step.label() + ", parameter " + p.name;
        if (d == nullptr) return kb::badInput(what + ": " + skill.browsePathString() + " lacks it");
        auto v = valueFor(p, *d, what, cellMatches);
        if (!v) return v.failure();
        out.emplace(p.name, std::move(*v));
    }
    return out;
}

}  // namespace skillcell::mes
