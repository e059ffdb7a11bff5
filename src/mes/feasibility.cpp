#include "mes/feasibility.hpp"

#include <algorithm>
#include <set>

#include "mes/step_binding.hpp"

namespace skillcell::mes {

namespace {

bool sameFactValue(const std::string& a, const std::string& b) {
    if (a == b) return true;
    const auto x = parseNumber(a);
    const auto y = parseNumber(b);
    return x && y && *x == *y;
}

/// Whether a step before `index` takes a tool from a resource that holds one with the fact.
bool broughtBefore(const ProcessDescription& process, int index, const FactRequirement& r) {
    for (const auto& step : process.steps) {
        if (step.index >= index) break;
        for (const auto& parameter : step.parameters) {
            const auto* from = std::get_if<DerivationSource>(&parameter.value);
            if (from == nullptr) continue;
            for (const auto& [property, value] : from->held) {
                if (property == r.propertyIri && sameFactValue(value, r.value)) return true;
            }
        }
    }
    return false;
}

}  // namespace

std::vector<std::string> requiredProperties(const ProcessDescription& process) {
    std::set<std::string> out;
    for (const auto& step : process.steps) {
        for (const auto& r : step.requirements) {
            if (!r.propertyIri.empty()) out.insert(r.propertyIri);
        }
    }
    return {out.begin(), out.end()};
}

std::vector<std::string> infeasibility(const ProcessDescription& process,
                                       const std::vector<skills::SkillInstance>& live,
                                       const SkillFacts* facts) {
    std::vector<std::string> out;
    for (const auto& step : process.steps) {
        const bool runnable = std::any_of(live.begin(), live.end(), [&](const auto& s) {
            return unsuitability(step, s).empty();
        });
        if (!runnable) {
            const bool typed = std::any_of(live.begin(), live.end(), [&](const auto& s) {
                return isOfType(s, step.skillTypeIri);
            });
            out.push_back(
                step.label() + ": " +
                (typed ? "no " + shortName(step.skillTypeIri) +
                             " skill in the cell has all its parameters"
                       : "no component in the cell offers a " + shortName(step.skillTypeIri)));
        }
        for (const auto& r : step.requirements) {
            if (r.skillTypeIri.empty()) continue;  // on the step's own skill: checked as it runs
            // A requirement by type alone needs no facts; one on a fact, the KB's.
            if (facts == nullptr && !r.propertyIri.empty()) continue;
            const bool present = std::any_of(live.begin(), live.end(), [&](const auto& s) {
                return isOfType(s, r.skillTypeIri) &&
                       (r.propertyIri.empty() || facts->has(keyOf(s), r));
            });
            if (!present && !broughtBefore(process, step.index, r)) {
                out.push_back(step.label() + " requires " + r.describe() +
                              ": none is in the cell, and no earlier step mounts a tool with it");
            }
        }
    }
    return out;
}

}  // namespace skillcell::mes
