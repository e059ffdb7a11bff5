#pragma once
// The dynamic half of the conformance checker (`skillcell check --exercise`): drives one
// skill through its state machine and checks what it answers and what it announces.
//
// With a subscription to the skill's transition events (on the skill when it is an event
// notifier, else on the Server object, filtered by SourceNode):
// - from Ready, every method that Ready does not allow (skill_state_machine.hpp:
//   Suspend, Resume, Reset) must answer BadInvalidState and change nothing;
// - Halt: event ReadyToHalted, CurrentState Halted, LastTransition ReadyToHalted;
// - in Halted, Start, Suspend, Resume and Halt must answer BadInvalidState;
// - Reset: HaltedToReady, Ready again;
// - Start with the parameters as they are: ReadyToRunning; while the run lasts, Suspend
//   (RunningToSuspended), the refusals of Suspended (Start, Suspend, Reset), Resume
//   (SuspendedToRunning) — a run that ends before Suspend is tried is not a fault; then
//   RunningToReady or RunningToHalted within the run timeout (a skill that cannot do its
//   job with its current parameters may halt: that is conformant);
// - every event: a SkillTransitionEventType (or subtype) from the skill, Transition/Id,
//   FromState/Id and ToState/Id the namespace-0 nodes of one transition of the table, the
//   texts their names, a Time; CurrentState and LastTransition agree with it afterwards.
// At the end the skill is left in Ready (Reset if Halted; Halt first if a run hung).
// A skill found Running or Suspended (in use by someone else) is not touched.
#include <array>
#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include <asio/awaitable.hpp>

#include "skills/conformance_report.hpp"
#include "skills/remote_address_space.hpp"
#include "skills/skill_state_machine.hpp"

namespace skillcell::skills {

/// What the static checks learnt of a skill, for the exercise.
struct SkillUnderTest {
    std::string path;  // browse path (the findings' subject)
    ua::NodeId nodeId;
    /// The instance's Method nodes, by SkillMethod (nullopt: missing).
    std::array<std::optional<ua::NodeId>, kAllMethods.size()> methods{};
    std::optional<ua::NodeId> currentState;
    std::optional<ua::NodeId> currentStateId;
    std::optional<ua::NodeId> currentStateNumber;
    std::optional<ua::NodeId> lastTransition;
    std::optional<ua::NodeId> lastTransitionId;
    /// EventNotifier bit SubscribeToEvents set on the skill object.
    bool eventNotifier = false;
};

struct ExerciseOptions {
    // Not an aggregate on purpose (GCC 12, see ua::ClientConfig).
    ExerciseOptions() = default;
    /// SkillTransitionEventType on this server (ns=<Skills>;i=1001).
    ua::NodeId skillTransitionEventType;
    std::chrono::milliseconds eventTimeout{3000};
    std::chrono::milliseconds runTimeout{10000};
    /// True ends the exercise after the step under way; the skill is still left in Ready.
    std::function<bool()> stopRequested;
};

/// Drives `skill` through its state machine and adds the findings to `report`.
asio::awaitable<void> exerciseSkill(RemoteAddressSpace& remote, const SkillUnderTest& skill,
                                    ExerciseOptions options, ConformanceReport& report);

}  // namespace skillcell::skills
