#pragma once
// Events (OPC 10000-5, 6.4.2 BaseEventType) and the EventFilter that selects their fields
// and decides which of them a monitored item reports (OPC 10000-4, 7.22.3 and 7.7).
#include <cstdint>
#include <optional>
#include <utility>
#include <variant>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/messages/event_filter.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

/// NodeIds of BaseEventType and its fields (Schema/NodeIds.csv). Kept here rather than in
/// ns0_ids.hpp, which belongs to the address space model.
namespace event_ids {
inline constexpr std::uint32_t BaseEventType = 2041;
inline constexpr std::uint32_t EventId = 2042;
inline constexpr std::uint32_t EventType = 2043;
inline constexpr std::uint32_t SourceNode = 2044;
inline constexpr std::uint32_t SourceName = 2045;
inline constexpr std::uint32_t Time = 2046;
inline constexpr std::uint32_t ReceiveTime = 2047;
inline constexpr std::uint32_t Message = 2050;
inline constexpr std::uint32_t Severity = 2051;
}  // namespace event_ids

/// EventNotifier attribute bit: the node can be subscribed to for events.
inline constexpr std::uint8_t kSubscribeToEvents = 0x01;

/// An event as application code fires it (Server::fireEvent). The server adds EventId,
/// ReceiveTime, Time (if unset) and SourceName (if empty: the source's browse name).
struct Event {
    NodeId eventType{event_ids::BaseEventType};
    NodeId sourceNode;
    String sourceName;
    LocalizedText message;
    std::uint16_t severity = 500;  // 1 (low) .. 1000 (high)
    std::optional<DateTime> time;
    /// Fields of subtypes, by browse path relative to the event type, e.g.
    /// {{{1, "Temperature"}}, Variant(21.5)}.
    std::vector<std::pair<std::vector<QualifiedName>, Variant>> fields;
};

/// An event as delivered: every BaseEventType field known.
struct EventRecord {
    Event event;
    ByteString eventId;
    DateTime time;
    DateTime receiveTime;
};

/// The value of the field at `browsePath` (BaseEventType names in namespace 0, or one of
/// event.fields); empty if the event has no such field.
[[nodiscard]] Variant eventField(const EventRecord& record,
                                 const std::vector<QualifiedName>& browsePath);

/// An EventFilter decoded and checked once, evaluated for every event.
struct CompiledEventFilter {
    using Operand = std::variant<ElementOperand, LiteralOperand, SimpleAttributeOperand>;
    struct Element {
        FilterOperator op = FilterOperator::Equals;
        std::vector<Operand> operands;
    };
    std::vector<SimpleAttributeOperand> select;
    std::vector<StatusCode> selectStatus;  // a Bad clause yields an empty field
    std::vector<Element> where;            // empty: every event passes
};

/// Checks an EventFilter against the address space's event types. Always fills `result`;
/// BadMonitoredItemFilterInvalid when no select clause is valid or the where clause has a
/// Bad element (operators this server does not evaluate: BadFilterOperatorUnsupported).
[[nodiscard]] Result<CompiledEventFilter> compileEventFilter(const AddressSpace& as,
                                                             const EventFilter& filter,
                                                             EventFilterResult& result);

/// The selected fields of `record`, or nullopt when the where clause rejects it.
[[nodiscard]] std::optional<std::vector<Variant>> evaluateEventFilter(
    const AddressSpace& as, const CompiledEventFilter& filter, const EventRecord& record);

}  // namespace skillcell::ua
