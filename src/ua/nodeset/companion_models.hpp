#pragma once
// skillcell's companion models (models/Skillcell.*.NodeSet2.xml, docs/models/): the DI and
// Robotics subsets and the skill specifications layered on them as in the paper's figure 4.
// They are compiled into the library like namespace 0 and loaded at run time, in
// dependency order, by loadCompanionModels.
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "ua/address_space/address_space.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::ua {

/// One companion model: its namespace URI and its embedded file name.
struct CompanionModel {
    std::string_view uri;
    std::string_view fileName;
};

namespace companion {
inline constexpr std::string_view kDiUri = "http://skillcell.dev/UA/DI/";
inline constexpr std::string_view kRoboticsUri = "http://skillcell.dev/UA/Robotics/";
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
inline constexpr std::array<CompanionModel, 8> kCompanionModels{{
    {companion::kDiUri, "Skillcell.DI.NodeSet2.xml"},
    {companion::kRoboticsUri, "Skillcell.Robotics.NodeSet2.xml"},
    {companion::kSkillsUri, "Skillcell.Skills.NodeSet2.xml"},
    {companion::kRoboticSkillsUri, "Skillcell.RoboticSkills.NodeSet2.xml"},
    {companion::kGripperSkillsUri, "Skillcell.GripperSkills.NodeSet2.xml"},
    {companion::kToolChangerSkillsUri, "Skillcell.ToolChangerSkills.NodeSet2.xml"},
    {companion::kCompositeSkillsUri, "Skillcell.CompositeSkills.NodeSet2.xml"},
    {companion::kMesSkillsUri, "Skillcell.MesSkills.NodeSet2.xml"},
}};

/// Loads the embedded companion models that are not loaded yet, in dependency order
/// (namespace 0 must be loaded). Stops at the first error; the status sums the nodes and
/// references added.
[[nodiscard]] NodeSetStatus loadCompanionModels(AddressSpace& as);

/// The type of the Skills model with numeric id `id` (e.g. companion::kSkillType), once
/// that model is loaded.
[[nodiscard]] std::optional<NodeId> skillsNodeId(const AddressSpace& as, std::uint32_t id);

/// The node whose browse name is `name` in namespace `uri` among the types of that
/// namespace (ObjectTypes and DataTypes); nullopt if there is none.
[[nodiscard]] std::optional<NodeId> findTypeByName(const AddressSpace& as, std::string_view uri,
                                                   std::string_view name);

}  // namespace skillcell::ua
