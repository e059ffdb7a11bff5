#include "skills/skill_parameters.hpp"

#include <fmt/format.h>
#include <cmath>
#include <type_traits>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/encoding/codec.hpp"

namespace skillcell::skills {
namespace {

std::optional<double> numeric(const ua::Scalar& s) {
    return std::visit(
        [](const auto& v) -> std::optional<double> {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_arithmetic_v<V> && !std::is_same_v<V, bool>) {
                return static_cast<double>(v);
            } else {
                return std::nullopt;
            }
        },
        s);
}

std::optional<ua::Range> rangeProperty(const ua::AddressSpace& as, const ua::NodeId& variable,
                                       const char* name) {
    for (const auto& r : as.find(variable)->references) {
        if (!r.isForward || r.referenceTypeId != ua::NodeId(ua::ns0::HasProperty)) continue;
        const ua::Node* p = as.find(r.target);
        if (p == nullptr || p->browseName.name != name) continue;
        const ua::DataValue dv = as.readValue(*p);
        if (!dv.value) return std::nullopt;
        const auto* eo = dv.value->get<ua::ExtensionObject>();
        ua::Range range;
        if (eo == nullptr || ua::fromExtensionObject(*eo, range).isBad()) return std::nullopt;
        return range;
    }
    return std::nullopt;
}

void explain(std::string* why, std::string text) {
    if (why != nullptr) *why = std::move(text);
}

}  // namespace

std::vector<ParameterDeclaration> declaredParameters(const ua::AddressSpace& as,
                                                     const ua::NodeId& parameterSet) {
    std::vector<ParameterDeclaration> out;
    const ua::Node* set = as.find(parameterSet);
    if (set == nullptr) return out;
    for (const auto& r : set->references) {
        if (!r.isForward || (r.referenceTypeId != ua::NodeId(ua::ns0::HasComponent) &&
                             r.referenceTypeId != ua::NodeId(ua::ns0::HasProperty))) {
            continue;
        }
        const ua::Node* v = as.find(r.target);
        if (v == nullptr || v->nodeClass != ua::NodeClass::Variable) continue;
        ParameterDeclaration d;
        d.name = v->browseName.name;
        d.nodeId = v->nodeId;
        d.dataType = v->dataType;
        d.valueRank = v->valueRank;
        d.arrayDimensions = v->arrayDimensions;
        d.range = rangeProperty(as, v->nodeId, "EURange");
        if (!d.range) d.range = rangeProperty(as, v->nodeId, "InstrumentRange");
        out.push_back(std::move(d));
    }
    return out;
}

ua::StatusCode validateParameter(const ua::AddressSpace& as,
                                 const ParameterDeclaration& declaration, const ua::Variant& value,
                                 std::string* why) {
    const std::string& name = declaration.name;
    if (value.isEmpty()) {
        // A null array is an empty one (OPC 10000-6, 5.2.5): AxisBounds unset means "no
        // bounds". A scalar, or an array of fixed length, must be given.
        const bool fixedLength =
            declaration.arrayDimensions.size() == 1 && declaration.arrayDimensions[0] != 0;
        if (declaration.valueRank >= 0 && !fixedLength) return ua::status::Good;
        explain(why, fmt::format("parameter {} has no value", name));
        return ua::status::BadArgumentsMissing;
    }
    if (!as.valueMatches(value, declaration.dataType, declaration.valueRank)) {
        explain(why, fmt::format("parameter {} needs a value of data type {}{}", name,
                                 declaration.dataType.toString(),
                                 declaration.valueRank >= 0 ? " (array)" : ""));
        return ua::status::BadTypeMismatch;
    }
    if (value.isArray() && declaration.arrayDimensions.size() == 1 &&
        declaration.arrayDimensions[0] != 0 &&
        value.elements().size() != declaration.arrayDimensions[0]) {
        explain(why, fmt::format("parameter {} needs {} elements, not {}", name,
                                 declaration.arrayDimensions[0], value.elements().size()));
        return ua::status::BadOutOfRange;
    }
    auto inRange = [&](const ua::Scalar& s) -> ua::StatusCode {
        const auto x = numeric(s);
        if (!x) return ua::status::Good;  // not a number: the type check above decided
        if (std::isnan(*x)) {
            explain(why, fmt::format("parameter {} is NaN", name));
            return ua::status::BadOutOfRange;
        }
        if (declaration.range && (*x < declaration.range->low || *x > declaration.range->high)) {
            explain(why, fmt::format("parameter {} = {} is outside its range {}..{}", name, *x,
                                     declaration.range->low, declaration.range->high));
            return ua::status::BadOutOfRange;
        }
        return ua::status::Good;
    };
    if (value.isArray()) {
        for (const auto& e : value.elements()) {
            if (const auto s = inRange(e); s.isBad()) return s;
        }
        return ua::status::Good;
    }
    return inRange(value.scalar());
}

const ua::Variant& SkillParameters::value(const std::string& name) const {
    static const ua::Variant kEmpty;
    const auto it = values_.find(name);
    return it == values_.end() ? kEmpty : it->second;
}

std::optional<std::vector<double>> SkillParameters::doubles(const std::string& name) const {
    const ua::Variant& v = value(name);
    if (!v.isArray()) return std::nullopt;
    std::vector<double> out;
    out.reserve(v.elements().size());
    for (const auto& e : v.elements()) {
        const auto x = numeric(e);
        if (!x) return std::nullopt;
        out.push_back(*x);
    }
    return out;
}

}  // namespace skillcell::skills
