#pragma once
// The conformance checker behind `skillcell check <endpoint>`: does every skill a server
// offers follow the skill model (ARCHITECTURE.md, "The skill model"; docs/conformance.md)?
// It is what a device maker runs before shipping a skill, against any OPC UA server.
//
// Everything is resolved on the remote server: the Skills namespace index from its
// NamespaceArray, SkillType and its subtypes through HasSubtype, a skill type's instance
// declarations by browsing the type and its supertypes. Never by browse-name strings, never
// from our own copy of the models.
//
// Static checks, for every object whose type is a subtype of SkillType:
// - the type is concrete and a ProgramStateMachineType;
// - every Mandatory instance declaration of the type (recursively: CurrentState/Id,
//   LastTransition/TransitionTime, ParameterSet/<every parameter>/EngineeringUnits, ...) is
//   there with the declared node class and type definition (or a subtype); the methods
//   Start, Suspend, Resume, Halt and Reset are required too (OptionalPlaceholder in
//   OPC 10000-10 1.05, required by the skill model) and executable;
// - variables have the declared DataType (or a subtype) and a compatible ValueRank, their
//   values are readable and fit them; a declared EURange is there and holds the value;
// - CurrentState is Halted, Ready, Running or Suspended with the matching Id and Number,
//   LastTransition is a transition into it;
// - the skill is an event notifier (else events can reach clients through the Server
//   object only: a warning that --exercise settles).
// With CheckOptions::exercise, each skill is then driven through its state machine
// (conformance_exercise.hpp).
//
// Bounded: every request has the client's timeout, the search for skills a node limit, and
// a server's strange answers become findings, not crashes or hangs.
#include <chrono>
#include <cstddef>
#include <functional>

#include <asio/awaitable.hpp>

#include "skills/conformance_report.hpp"
#include "skills/remote_address_space.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/client/client.hpp"

namespace skillcell::skills {

struct CheckOptions {
    // Not an aggregate on purpose (GCC 12, see ua::ClientConfig).
    CheckOptions() = default;

    /// Where the search for skills starts; forward hierarchical references from here.
    ua::NodeId start{ua::ns0::ObjectsFolder};
    /// Objects visited while searching for skills, at most (a warning says so when hit).
    std::size_t maxObjects = 20'000;
    /// Levels below `start` searched.
    std::size_t maxDepth = 16;
    /// Levels of instance declarations compared below a skill.
    std::size_t maxDeclarationDepth = 6;
    /// Drive every skill through its state machine (it runs the skill: opt-in).
    bool exercise = false;
    /// --exercise: how long to wait for each transition event after a method call.
    std::chrono::milliseconds eventTimeout{3000};
    /// --exercise: how long a run (Start until Ready or Halted) may take.
    std::chrono::milliseconds runTimeout{10000};
    RemoteLimits limits;
    /// Asked between steps: true ends the check early (the exercise first puts the skill
    /// back in Ready), with a failure saying so. The CLI's SIGINT handler sets it.
    std::function<bool()> stopRequested;
};

/// Checks every skill of the server `client` is connected to (with a session) and adds
/// the findings to `report`. Never throws; the connection stays open.
asio::awaitable<void> checkConformance(ua::Client& client, CheckOptions options,
                                       ConformanceReport& report);

}  // namespace skillcell::skills
