#pragma once
// A skill's parameters: what the type declares for each (ParameterDeclaration), the checks
// a value must pass (validateParameter), and the values a run uses, fixed at Start
// (SkillParameters). docs/skill-parameters.md states the rules.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/messages/data_access.hpp"
#include "ua/types/result.hpp"

namespace skillcell::skills {

/// One variable of a skill's ParameterSet, as the address space declares it.
struct ParameterDeclaration {
    std::string name;  // browse name (without namespace)
    ua::NodeId nodeId;
    ua::NodeId dataType;
    std::int32_t valueRank = -1;
    std::vector<std::uint32_t> arrayDimensions;  // 0 or absent: any length
    /// EURange, else InstrumentRange: bounds for a numeric value or every array element.
    std::optional<ua::Range> range;
};

/// The declarations under `parameterSet` (its forward HasComponent/HasProperty variables),
/// with the EURange/InstrumentRange properties decoded. Properties of the parameters
/// themselves (EngineeringUnits, EURange) are not parameters.
[[nodiscard]] std::vector<ParameterDeclaration> declaredParameters(const ua::AddressSpace& as,
                                                                   const ua::NodeId& parameterSet);

/// Checks a value for a parameter: BadTypeMismatch (data type or value rank),
/// BadOutOfRange (an array of the wrong length, a number outside the range, NaN),
/// BadArgumentsMissing (no value for a scalar or a fixed-length array; a null array of any
/// length counts as empty). `why` (if given) receives a sentence naming the
/// parameter and the rule it breaks.
[[nodiscard]] ua::StatusCode validateParameter(const ua::AddressSpace& as,
                                               const ParameterDeclaration& declaration,
                                               const ua::Variant& value,
                                               std::string* why = nullptr);

/// The values of one run, by parameter name: taken at Start and unchanged until the run
/// ends, whatever clients write meanwhile.
class SkillParameters {
public:
    SkillParameters() = default;
    explicit SkillParameters(std::map<std::string, ua::Variant> values)
        : values_(std::move(values)) {}

    [[nodiscard]] bool contains(const std::string& name) const { return values_.contains(name); }
    /// The value of `name`; the empty Variant if there is no such parameter.
    [[nodiscard]] const ua::Variant& value(const std::string& name) const;
    /// The scalar of type T, or nullopt when the parameter is missing or holds another type.
    template <ua::ScalarType T>
    [[nodiscard]] std::optional<T> get(const std::string& name) const {
        const T* v = value(name).get<T>();
        if (v == nullptr) return std::nullopt;
        return *v;
    }
    /// A numeric array as doubles (Double[], Float[], integer arrays); nullopt otherwise.
    [[nodiscard]] std::optional<std::vector<double>> doubles(const std::string& name) const;
    [[nodiscard]] const std::map<std::string, ua::Variant>& all() const { return values_; }

private:
    std::map<std::string, ua::Variant> values_;
};

}  // namespace skillcell::skills
