#pragma once
// The skill state machine of OPC 10000-10 (ProgramStateMachineType) as pure data: states,
// transitions, which method causes which transition, and the NodeIds of the state and
// transition nodes of namespace 0. Every other part of the skill layer (the server-side
// Skill, the SkillClient, the conformance checker) asks this table instead of spelling the
// rules out again.
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "ua/types/node_id.hpp"

namespace skillcell::skills {

/// State numbers are the StateNumber values of namespace 0's state objects.
enum class SkillState : std::uint32_t { Halted = 11, Ready = 12, Running = 13, Suspended = 14 };

/// Transition numbers are the TransitionNumber values of namespace 0's transition objects.
enum class SkillTransition : std::uint32_t {
    HaltedToReady = 1,
    ReadyToRunning = 2,
    RunningToHalted = 3,
    RunningToReady = 4,
    RunningToSuspended = 5,
    SuspendedToRunning = 6,
    SuspendedToHalted = 7,
    SuspendedToReady = 8,
    ReadyToHalted = 9,
};

/// The methods of a skill, in the order ProgramStateMachineType declares them.
enum class SkillMethod : std::uint8_t { Start, Suspend, Resume, Halt, Reset };

inline constexpr std::array kAllStates = {SkillState::Halted, SkillState::Ready,
                                          SkillState::Running, SkillState::Suspended};
inline constexpr std::array kAllTransitions = {
    SkillTransition::HaltedToReady,      SkillTransition::ReadyToRunning,
    SkillTransition::RunningToHalted,    SkillTransition::RunningToReady,
    SkillTransition::RunningToSuspended, SkillTransition::SuspendedToRunning,
    SkillTransition::SuspendedToHalted,  SkillTransition::SuspendedToReady,
    SkillTransition::ReadyToHalted};
inline constexpr std::array kAllMethods = {SkillMethod::Start, SkillMethod::Suspend,
                                           SkillMethod::Resume, SkillMethod::Halt,
                                           SkillMethod::Reset};

[[nodiscard]] std::string_view name(SkillState state);
[[nodiscard]] std::string_view name(SkillTransition transition);
[[nodiscard]] std::string_view name(SkillMethod method);
[[nodiscard]] std::optional<SkillState> stateFromNumber(std::uint32_t number);
[[nodiscard]] std::optional<SkillState> stateFromName(std::string_view name);
[[nodiscard]] std::optional<SkillTransition> transitionFromNumber(std::uint32_t number);
[[nodiscard]] std::optional<SkillMethod> methodFromName(std::string_view name);

[[nodiscard]] SkillState fromState(SkillTransition transition);
[[nodiscard]] SkillState toState(SkillTransition transition);
/// The transition from `from` to `to`, if the state machine has one.
[[nodiscard]] std::optional<SkillTransition> transitionBetween(SkillState from, SkillState to);

/// The transition `method` causes in `state`, or nullopt when the method is not allowed
/// there (the caller answers BadInvalidState). Start: Ready→Running; Suspend:
/// Running→Suspended; Resume: Suspended→Running; Halt: Ready, Running or Suspended→Halted;
/// Reset: Halted→Ready.
[[nodiscard]] std::optional<SkillTransition> transitionFor(SkillMethod method, SkillState state);

/// NodeIds in namespace 0 (ProgramStateMachineType's declarations).
[[nodiscard]] ua::NodeId stateNodeId(SkillState state);
[[nodiscard]] ua::NodeId transitionNodeId(SkillTransition transition);
[[nodiscard]] ua::NodeId methodNodeId(SkillMethod method);
[[nodiscard]] std::optional<SkillState> stateFromNodeId(const ua::NodeId& id);
[[nodiscard]] std::optional<SkillTransition> transitionFromNodeId(const ua::NodeId& id);

}  // namespace skillcell::skills
