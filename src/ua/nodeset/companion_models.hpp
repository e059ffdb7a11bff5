#pragma once
// The companion models skillcell servers load: the OPC Foundation's DI (OPC 10000-100), IA
// and Robotics (OPC 40010-1) NodeSets as published (models/opcfoundation/, MIT), and
// skillcell's skill specifications layered on DI (models/Skillcell.*.NodeSet2.xml,
// docs/models/), as in the paper's figure 4. The XML is compiled into the library like
// namespace 0 and parsed at run time, in dependency order, by loadCompanionModels: all of
// them (the knowledge base), or the ones a component's skills need with the models those
// require (a gripper adapter has no use for Robotics, a third of the XML).
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::ua {

/// One companion model: its namespace URI and its embedded file name.
struct CompanionModel {
    std::string_view uri;
    std::string_view fileName;
};

namespace companion {
// The OPC Foundation's models (models/opcfoundation/, their NodeSet2 files as published).
inline constexpr std::string_view kDiUri = "http://opcfoundation.org/UA/DI/";
inline constexpr std::string_view kIaUri = "http://opcfoundation.org/UA/IA/";
inline constexpr std::string_view kRoboticsUri = "http://opcfoundation.org/UA/Robotics/";
// skillcell's own, layered on DI.
inline constexpr std::string_view kSkillsUri = "http://skillcell.dev/UA/Skills/";
inline constexpr std::string_view kRoboticSkillsUri = "http://skillcell.dev/UA/RoboticSkills/";
inline constexpr std::string_view kGripperSkillsUri = "http://skillcell.dev/UA/GripperSkills/";
inline constexpr std::string_view kToolChangerSkillsUri =
    "http://skillcell.dev/UA/ToolChangerSkills/";
inline constexpr std::string_view kCompositeSkillsUri = "http://skillcell.dev/UA/CompositeSkills/";
inline constexpr std::string_view kMesSkillsUri = "http://skillcell.dev/UA/MesSkills/";

/// Numeric ids in the Skills namespace.
inline constexpr std::uint32_t kSkillTransitionEventType = 1001;
inline constexpr std::uint32_t kSkillType = 1002;
inline constexpr std::uint32_t kReservationType = 1003;
}  // namespace companion

/// Every companion model, each after the models it requires.
inline constexpr std::array<CompanionModel, 9> kCompanionModels{{
    {companion::kDiUri, "Opc.Ua.Di.NodeSet2.xml"},
    {companion::kIaUri, "Opc.Ua.IA.NodeSet2.xml"},
    {companion::kRoboticsUri, "Opc.Ua.Robotics.NodeSet2.xml"},
    {companion::kSkillsUri, "Skillcell.Skills.NodeSet2.xml"},
    {companion::kRoboticSkillsUri, "Skillcell.RoboticSkills.NodeSet2.xml"},
    {companion::kGripperSkillsUri, "Skillcell.GripperSkills.NodeSet2.xml"},
    {companion::kToolChangerSkillsUri, "Skillcell.ToolChangerSkills.NodeSet2.xml"},
    {companion::kCompositeSkillsUri, "Skillcell.CompositeSkills.NodeSet2.xml"},
    {companion::kMesSkillsUri, "Skillcell.MesSkills.NodeSet2.xml"},
}};

/// The companion models `uris` require, transitively, with `uris` themselves, in the load
/// order of kCompanionModels; nullopt (and `unknown` set) for an URI of no companion model.
[[nodiscard]] std::optional<std::vector<CompanionModel>> companionModelsFor(
    std::span<const std::string_view> uris, std::string* unknown = nullptr);

/// The namespace URI of the companion model whose file declares a node with the browse name
/// `name` in its own namespace (e.g. "GraspGripperSkillType": GripperSkills); nullopt if none
/// does. Read from the embedded XML without loading it (its NamespaceUris, then a search):
/// for a command line that names a type, to load only the model it comes from.
[[nodiscard]] std::optional<std::string_view> companionModelDeclaring(std::string_view name);

/// The type of the Skills model with numeric id `id` (e.g. companion::kSkillType), once
/// that model is loaded.
[[nodiscard]] std::optional<NodeId> skillsNodeId(const AddressSpace& as, std::uint32_t id);

/// The node whose browse name is `name` in namespace `uri` among the types of that
/// namespace (ObjectTypes and DataTypes); nullopt if there is none.
[[nodiscard]] std::optional<NodeId> findTypeByName(const AddressSpace& as, std::string_view uri,
                                                   std::string_view name);

}  // namespace skillcell::ua
