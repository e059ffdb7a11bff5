#pragma once
// The IRI of an OPC UA node, stable across servers because namespace URIs are:
//   - a type (ObjectType, VariableType, DataType, ReferenceType) with a plain browse name:
//     <namespace URI><BrowseName>, e.g.
//     http://skillcell.dev/UA/GripperSkills/GraspGripperSkillType, so that process models and
//     queries can name types readably;
//   - any other node: <namespace URI><identifier>, e.g. http://skillcell.dev/UA/Skills/i=6001
//     (instance declarations share browse names, so only the id is unique).
// A namespace URI that does not end in '/' or '#' gets a '#'.
#include <string>
#include <string_view>

#include "ua/address_space/node.hpp"

namespace skillcell::kb::owl {

/// The IRI of the node `id` of class `nodeClass` named `browseName` in `namespaceUri`.
[[nodiscard]] std::string nodeIri(std::string_view namespaceUri, const ua::NodeId& id,
                                  ua::NodeClass nodeClass, std::string_view browseName);

/// "nsu=<uri>;i=5002": the node id with its namespace URI (OPC 10000-6, 5.3.1.11).
[[nodiscard]] std::string expandedNodeIdText(std::string_view namespaceUri, const ua::NodeId& id);

}  // namespace skillcell::kb::owl
