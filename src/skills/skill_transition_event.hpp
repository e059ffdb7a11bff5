#pragma once
// A skill's transition event as a client receives it: the EventFilter that selects the
// fields of TransitionEventType (i=2311) a skill client needs, and the decoding of the
// delivered field list into a struct. SkillTransitionEventType (Skills model) is a subtype
// of ProgramTransitionEventType (i=2378), itself a TransitionEventType, so these browse
// paths are valid for every skill event, whoever made the server.
#include <cstddef>
#include <string>
#include <vector>

#include "ua/messages/event_filter.hpp"
#include "ua/types/variant.hpp"

namespace skillcell::skills {

/// The select clauses of transitionEventFilter(), in order.
enum class TransitionEventField : std::size_t {
    EventId,
    EventType,
    SourceNode,
    Time,
    Transition,    // LocalizedText, e.g. "ReadyToRunning"
    TransitionId,  // Transition/Id: the transition's NodeId (namespace 0 for a skill)
    FromState,
    FromStateId,
    ToState,
    ToStateId,
    Count
};

/// The browse path of a field, e.g. "FromState/Id" (for messages).
[[nodiscard]] std::string fieldName(TransitionEventField field);

/// EventId, EventType, SourceNode, Time of BaseEventType; Transition, FromState, ToState and
/// their Id properties of TransitionEventType. No where clause: the caller filters by source.
[[nodiscard]] ua::EventFilter transitionEventFilter();

struct TransitionEvent {
    ua::ByteString eventId;
    ua::NodeId eventType;
    ua::NodeId sourceNode;
    ua::DateTime time;
    ua::LocalizedText transition;
    ua::NodeId transitionId;
    ua::LocalizedText fromState;
    ua::NodeId fromStateId;
    ua::LocalizedText toState;
    ua::NodeId toStateId;
    /// Fields that were missing or of the wrong type, by name.
    std::vector<std::string> missing;
};

/// Decodes the fields delivered for transitionEventFilter(). A field that is absent or
/// has another type is left empty and named in `missing`.
[[nodiscard]] TransitionEvent parseTransitionEvent(const std::vector<ua::Variant>& fields);

}  // namespace skillcell::skills
