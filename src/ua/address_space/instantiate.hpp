#pragma once
// Instantiation of ObjectTypes and VariableTypes (OPC 10000-3, 6.4): creates an instance with
// the children its type declares, so that a skill (a ProgramStateMachineType subtype) or a
// 3D frame variable exists in the address space exactly as its NodeSet2 model says.
//
// Rules implemented:
// - Instance declarations are the children (HasChild subtypes other than HasSubtype) of a
//   type that carry a HasModellingRule. Children without a rule (the states and transitions
//   of a state machine type) belong to the type and are not copied.
// - The declarations of a type are those of the type and of all its supertypes; a subtype's
//   declaration overrides its supertype's with the same browse name.
// - A child created from declaration D gets D's own children as declarations first, then
//   those of D's type definition and its supertypes (D's override its type's).
// - Mandatory children are always created, Optional ones only when asked for by browse path
//   ("LastTransition/TransitionTime"; asking for a path implies its optional ancestors).
//   An OptionalPlaceholder is created only when asked for by its browse name too (OPC
//   10000-10 1.05 declares ProgramStateMachineType's Start..Reset methods so).
//   MandatoryPlaceholder and ExposesItsArray children are never created: they stand for
//   instances the application adds under names of its own.
// - Attributes and values are copied from the declaration (DisplayName, Description,
//   DataType, ValueRank, ArrayDimensions, AccessLevel, Value, ...), the reference from the
//   parent has the declaration's reference type, and HasTypeDefinition points at the
//   declaration's type. HasModellingRule is not copied: instances have no modelling rule.
//   Other non-hierarchical references of a declaration are copied, retargeted to the
//   instance when they point at another declaration that was instantiated.
// - Methods are copied: every instance gets its own Method node (and its argument
//   properties). The spec also allows an instance to reference the type's Method node, but
//   a node of its own lets an application install a callback per instance
//   (AddressSpace::setMethodCallback) and lets Browse of the instance show only its own
//   parents. The copy starts with the declaration's callback, so a callback installed on
//   the type's method (dispatching on the object id) serves every instance.
// - NodeIds are deterministic and readable: the instance gets options.nodeId or
//   AddressSpace::childNodeId(parent, browse name); each child childNodeId(its parent,
//   its browse name), e.g. "ns=1;s=Cell.Move/CurrentState/Id".
//
// All ids are checked before the first node is added: on error nothing has changed.
#include <string>
#include <vector>

#include "ua/address_space/address_space.hpp"

namespace skillcell::ua {

struct InstantiateOptions {
    /// The new node's id; null: AddressSpace::childNodeId(parent, browseName.name).
    NodeId nodeId;
    /// Optional children to create, as browse-name paths relative to the new node
    /// ("LastTransition", "CurrentState/Number"). Names are matched without namespace.
    std::vector<std::string> optionalChildren;
    /// The new node's DisplayName; empty: its browse name.
    LocalizedText displayName;
};

/// Creates an instance of `typeDefinition` (an ObjectType or VariableType, not abstract)
/// under `parent`, referenced by `referenceType` (null: HasComponent). Returns the new
/// node's id. BadNodeIdUnknown for an unknown parent, BadTypeDefinitionInvalid for an
/// unknown or abstract type or one that is not an ObjectType/VariableType,
/// BadReferenceTypeIdInvalid, BadNodeIdExists when an id the instance needs is taken.
[[nodiscard]] Result<NodeId> instantiate(AddressSpace& as, const NodeId& typeDefinition,
                                         const NodeId& parent, const NodeId& referenceType,
                                         const QualifiedName& browseName,
                                         const InstantiateOptions& options = {});

/// The modelling rule (HasModellingRule target) of a node; null if it has none.
[[nodiscard]] NodeId modellingRuleOf(const Node& node);

}  // namespace skillcell::ua
