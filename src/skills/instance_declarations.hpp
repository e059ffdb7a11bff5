#pragma once
// The instance declarations of a remote type (OPC 10000-3, 6.4): the children an instance
// of the type must have (Mandatory) or may have (Optional, placeholders), collected from
// the remote server by browsing the type, its supertypes, and recursively the declarations'
// own children and type definitions.
//
// The rules are those ua::instantiate() applies when it builds an instance (see
// src/ua/address_space/instantiate.hpp), read here from the other side of the wire:
// - a declaration is a child (Aggregates: HasComponent, HasProperty, ...) with a
//   HasModellingRule; children without a rule (a state machine's states) belong to the type;
// - a subtype's declaration overrides its supertype's with the same browse name;
// - the children of declaration D are D's own declarations over those of D's type
//   definition and its supertypes (D's win).
// The conformance checker compares a live instance with this list.
#include <cstdint>
#include <string>
#include <vector>

#include <asio/awaitable.hpp>

#include "skills/remote_address_space.hpp"

namespace skillcell::skills {

/// Modelling rules of namespace 0 (OPC 10000-3, 6.4.4).
namespace modelling_rule {
inline constexpr std::uint32_t Mandatory = 78;
inline constexpr std::uint32_t Optional = 80;
inline constexpr std::uint32_t ExposesItsArray = 83;
inline constexpr std::uint32_t OptionalPlaceholder = 11508;
inline constexpr std::uint32_t MandatoryPlaceholder = 11510;
}  // namespace modelling_rule

struct InstanceDeclaration {
    /// Browse names from the type down to this declaration ({0:CurrentState, 0:Id}).
    std::vector<ua::QualifiedName> path;
    ua::NodeId nodeId;  // the declaration node, in a type
    ua::NodeClass nodeClass = ua::NodeClass::Unspecified;
    ua::NodeId referenceType;   // from its parent
    ua::NodeId typeDefinition;  // Objects and Variables
    ua::NodeId modellingRule;
    ua::NodeId dataType;  // Variables
    std::int32_t valueRank = -1;

    [[nodiscard]] bool isMandatory() const {
        return modellingRule == ua::NodeId(modelling_rule::Mandatory);
    }
    [[nodiscard]] bool isPlaceholder() const {
        return modellingRule == ua::NodeId(modelling_rule::OptionalPlaceholder) ||
               modellingRule == ua::NodeId(modelling_rule::MandatoryPlaceholder);
    }
    /// "ParameterSet/MaxVelocity" (names without namespace indices, for people).
    [[nodiscard]] std::string pathText() const;
};

/// "Mandatory", "Optional", "OptionalPlaceholder", ... or the rule's NodeId.
[[nodiscard]] std::string modellingRuleName(const ua::NodeId& rule);
/// Browse names joined by '/'.
[[nodiscard]] std::string pathText(const std::vector<ua::QualifiedName>& path);

/// Every instance declaration of `type`, parents before their children, at most `maxDepth`
/// levels deep. Placeholders are listed but not descended into (they stand for children
/// an application names itself). Errors are those of the server's answers.
asio::awaitable<ua::Result<std::vector<InstanceDeclaration>>> instanceDeclarations(
    RemoteAddressSpace& remote, ua::NodeId type, std::size_t maxDepth = 6);

}  // namespace skillcell::skills
