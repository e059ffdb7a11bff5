#include "skills/skill_transition_event.hpp"

#include <array>
#include <string_view>

#include "skills/skill_state_machine.hpp"
#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::skills {
namespace {

struct FieldRow {
    TransitionEventField field;
    std::uint32_t eventType;               // the type that declares the field
    std::array<std::string_view, 2> path;  // browse names in namespace 0; "" ends the path
};

using F = TransitionEventField;
constexpr std::array<FieldRow, static_cast<std::size_t>(F::Count)> kRows = {{
    {F::EventId, ua::ns0::BaseEventType, {"EventId", ""}},
    {F::EventType, ua::ns0::BaseEventType, {"EventType", ""}},
    {F::SourceNode, ua::ns0::BaseEventType, {"SourceNode", ""}},
    {F::Time, ua::ns0::BaseEventType, {"Time", ""}},
    {F::Transition, ua::ns0::TransitionEventType, {"Transition", ""}},
    {F::TransitionId, ua::ns0::TransitionEventType, {"Transition", "Id"}},
    {F::FromState, ua::ns0::TransitionEventType, {"FromState", ""}},
    {F::FromStateId, ua::ns0::TransitionEventType, {"FromState", "Id"}},
    {F::ToState, ua::ns0::TransitionEventType, {"ToState", ""}},
    {F::ToStateId, ua::ns0::TransitionEventType, {"ToState", "Id"}},
}};

template <class T>
void take(const std::vector<ua::Variant>& fields, TransitionEventField field, T& out,
          std::vector<std::string>& missing) {
    const auto i = static_cast<std::size_t>(field);
    if (i < fields.size()) {
        if (const T* v = fields[i].get<T>()) {
            out = *v;
            return;
        }
    }
    missing.push_back(fieldName(field));
}

}  // namespace

std::string fieldName(TransitionEventField field) {
    const auto& row = kRows.at(static_cast<std::size_t>(field));
    std::string s(row.path[0]);
    if (!row.path[1].empty()) (s += '/') += row.path[1];
    return s;
}

ua::EventFilter transitionEventFilter() {
    ua::EventFilter filter;
    for (const auto& row : kRows) {
        ua::SimpleAttributeOperand op;
        op.typeDefinitionId = ua::NodeId(row.eventType);
        for (const auto name : row.path) {
            if (!name.empty()) op.browsePath.push_back(ua::QualifiedName{0, std::string(name)});
        }
        op.attributeId = static_cast<std::uint32_t>(ua::AttributeId::Value);
        filter.selectClauses.push_back(std::move(op));
    }
    return filter;
}

TransitionEvent parseTransitionEvent(const std::vector<ua::Variant>& fields) {
    TransitionEvent e;
    take(fields, F::EventId, e.eventId, e.missing);
    take(fields, F::EventType, e.eventType, e.missing);
    take(fields, F::SourceNode, e.sourceNode, e.missing);
    take(fields, F::Time, e.time, e.missing);
    take(fields, F::Transition, e.transition, e.missing);
    take(fields, F::TransitionId, e.transitionId, e.missing);
    take(fields, F::FromState, e.fromState, e.missing);
    take(fields, F::FromStateId, e.fromStateId, e.missing);
    take(fields, F::ToState, e.toState, e.missing);
    take(fields, F::ToStateId, e.toStateId, e.missing);
    return e;
}

}  // namespace skillcell::skills
