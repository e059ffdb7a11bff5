#pragma once
// Node: one node of the address space (OPC 10000-3, 5). All eight node classes share one
// struct; `nodeClass` says which of the class-specific attributes are meaningful (see
// hasAttribute). One flat struct keeps lookups, loading and attribute reads free of casts,
// and the address spaces skillcell serves are small enough that the unused fields cost
// nothing that matters.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "ua/address_space/dynamic_structure.hpp"
#include "ua/address_space/role.hpp"
#include "ua/messages/common.hpp"
#include "ua/types/variant.hpp"

namespace skillcell::ua {

/// AccessLevel bits (OPC 10000-3, 8.57).
namespace access_level {
inline constexpr std::uint8_t kCurrentRead = 0x01;
inline constexpr std::uint8_t kCurrentWrite = 0x02;
inline constexpr std::uint8_t kHistoryRead = 0x04;
inline constexpr std::uint8_t kHistoryWrite = 0x08;
inline constexpr std::uint8_t kReadWrite = kCurrentRead | kCurrentWrite;
}  // namespace access_level

/// ValueRank special values (OPC 10000-3, 5.6.2).
namespace value_rank {
inline constexpr std::int32_t kScalarOrOneDimension = -3;
inline constexpr std::int32_t kAny = -2;
inline constexpr std::int32_t kScalar = -1;
inline constexpr std::int32_t kOneOrMoreDimensions = 0;
inline constexpr std::int32_t kOneDimension = 1;
}  // namespace value_rank

/// A reference as stored at one end. Both ends store it (isForward true at the source,
/// false at the target) so that Browse in either direction is a scan of one vector.
struct Reference {
    NodeId referenceTypeId;
    NodeId target;
    bool isForward = true;
    friend bool operator==(const Reference&, const Reference&) = default;
};

/// Who asked for a write or a method call: the session the request came on (null for
/// application code). Callbacks use it for per-session rules such as a skill's
/// reservation by the session that started it.
struct Caller {
    NodeId sessionId;
    /// What the caller may do. Application code calling in directly acts with every right;
    /// the services pass the session user's roles.
    RoleSet roles{Role::Admin};
};

/// Produces the current value of a variable on every read (Value attribute).
using ValueSource = std::function<DataValue()>;
/// Receives a value written by a client; a Bad status refuses the write.
using ValueSink = std::function<StatusCode(const Caller& caller, const DataValue&)>;
/// Runs a method. `outputs` is empty on entry; fill it in OutputArguments order.
using MethodCallback =
    std::function<StatusCode(const Caller& caller, const NodeId& objectId,
                             std::span<const Variant> inputs, std::vector<Variant>& outputs)>;

/// A method's input `i` if it is a scalar of type T, else nullptr (then the callback answers
/// BadInvalidArgument).
template <ScalarType T>
[[nodiscard]] const T* methodInput(std::span<const Variant> inputs, std::size_t i) {
    return i < inputs.size() ? inputs[i].get<T>() : nullptr;
}

struct Node {
    // Base attributes: every node class.
    NodeId nodeId;
    NodeClass nodeClass = NodeClass::Object;
    QualifiedName browseName;
    LocalizedText displayName;
    LocalizedText description;
    std::uint32_t writeMask = 0;
    std::uint32_t userWriteMask = 0;

    // Types (ObjectType, VariableType, ReferenceType, DataType).
    bool isAbstract = false;
    // ReferenceType.
    bool symmetric = false;
    LocalizedText inverseName;
    // View.
    bool containsNoLoops = false;
    // Object, View.
    std::uint8_t eventNotifier = 0;

    // Variable, VariableType.
    DataValue value;      // the stored value, used when no ValueSource is installed
    NodeId dataType{24};  // BaseDataType
    std::int32_t valueRank = value_rank::kScalar;
    std::vector<std::uint32_t> arrayDimensions;
    // Variable.
    std::uint8_t accessLevel = access_level::kCurrentRead;
    std::uint8_t userAccessLevel = access_level::kCurrentRead;
    double minimumSamplingInterval = 0;
    bool historizing = false;
    ValueSource valueSource;
    ValueSink valueSink;

    // Method.
    bool executable = true;
    bool userExecutable = true;
    MethodCallback method;

    // Variable (writing its value), Method (calling it): the least role that may. Skill
    // methods and parameters act on the plant: Operator. Configuration (the cell's layout,
    // a device's setup): Engineer.
    Role requiredRole = Role::Operator;

    // DataType: the DataTypeDefinition attribute (structure fields or enumeration values),
    // read from the NodeSet2 <Definition>; monostate for types without one.
    StructureOrEnumDefinition definition;

    /// Both directions, in insertion order (Browse returns them in this order).
    std::vector<Reference> references;
    /// The supertype (inverse HasSubtype target) of a type node, cached when the
    /// HasSubtype reference is added: subtype checks walk this chain, not the references.
    NodeId superType;
};

/// True when nodes of `nodeClass` have attribute `attributeId` (OPC 10000-3, Table 8
/// onwards). Optional attributes skillcell does not keep (RolePermissions,
/// UserRolePermissions, AccessRestrictions, DataTypeDefinition) count as absent.
/// DataTypeDefinition is per node, not per class: the Read service answers it for the
/// DataType nodes whose `definition` is set (structures and enumerations).
[[nodiscard]] bool hasAttribute(NodeClass nodeClass, std::uint32_t attributeId);

}  // namespace skillcell::ua
