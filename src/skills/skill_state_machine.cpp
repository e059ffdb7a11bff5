#include "skills/skill_state_machine.hpp"

namespace skillcell::skills {
namespace {

struct StateRow {
    SkillState state;
    std::string_view name;
    std::uint32_t nodeId;  // namespace 0
};
constexpr std::array<StateRow, 4> kStates = {{
    {SkillState::Halted, "Halted", 2406},
    {SkillState::Ready, "Ready", 2400},
    {SkillState::Running, "Running", 2402},
    {SkillState::Suspended, "Suspended", 2404},
}};

struct TransitionRow {
    SkillTransition transition;
    std::string_view name;
    SkillState from;
    SkillState to;
    std::uint32_t nodeId;  // namespace 0
};
using S = SkillState;
using Tr = SkillTransition;
constexpr std::array<TransitionRow, 9> kTransitions = {{
    {Tr::HaltedToReady, "HaltedToReady", S::Halted, S::Ready, 2408},
    {Tr::ReadyToRunning, "ReadyToRunning", S::Ready, S::Running, 2410},
    {Tr::RunningToHalted, "RunningToHalted", S::Running, S::Halted, 2412},
    {Tr::RunningToReady, "RunningToReady", S::Running, S::Ready, 2414},
    {Tr::RunningToSuspended, "RunningToSuspended", S::Running, S::Suspended, 2416},
    {Tr::SuspendedToRunning, "SuspendedToRunning", S::Suspended, S::Running, 2418},
    {Tr::SuspendedToHalted, "SuspendedToHalted", S::Suspended, S::Halted, 2420},
    {Tr::SuspendedToReady, "SuspendedToReady", S::Suspended, S::Ready, 2422},
    {Tr::ReadyToHalted, "ReadyToHalted", S::Ready, S::Halted, 2424},
}};

struct MethodRow {
    SkillMethod method;
    std::string_view name;
    std::uint32_t nodeId;  // namespace 0
};
constexpr std::array<MethodRow, 5> kMethods = {{
    {SkillMethod::Start, "Start", 2426},
    {SkillMethod::Suspend, "Suspend", 2427},
    {SkillMethod::Resume, "Resume", 2428},
    {SkillMethod::Halt, "Halt", 2429},
    {SkillMethod::Reset, "Reset", 2430},
}};

const StateRow& row(SkillState s) {
    for (const auto& r : kStates) {
        if (r.state == s) return r;
    }
    return kStates[0];  // unreachable for valid enumerators
}
const TransitionRow& row(SkillTransition t) {
    for (const auto& r : kTransitions) {
        if (r.transition == t) return r;
    }
    return kTransitions[0];
}
const MethodRow& row(SkillMethod m) {
    for (const auto& r : kMethods) {
        if (r.method == m) return r;
    }
    return kMethods[0];
}

}  // namespace

std::string_view name(SkillState state) {
    return row(state).name;
}
std::string_view name(SkillTransition transition) {
    return row(transition).name;
}
std::string_view name(SkillMethod method) {
    return row(method).name;
}

std::optional<SkillState> stateFromNumber(std::uint32_t number) {
    for (const auto& r : kStates) {
        if (static_cast<std::uint32_t>(r.state) == number) return r.state;
    }
    return std::nullopt;
}
std::optional<SkillState> stateFromName(std::string_view text) {
    for (const auto& r : kStates) {
        if (r.name == text) return r.state;
    }
    return std::nullopt;
}
std::optional<SkillTransition> transitionFromNumber(std::uint32_t number) {
    for (const auto& r : kTransitions) {
        if (static_cast<std::uint32_t>(r.transition) == number) return r.transition;
    }
    return std::nullopt;
}
std::optional<SkillMethod> methodFromName(std::string_view text) {
    for (const auto& r : kMethods) {
        if (r.name == text) return r.method;
    }
    return std::nullopt;
}

SkillState fromState(SkillTransition transition) {
    return row(transition).from;
}
SkillState toState(SkillTransition transition) {
    return row(transition).to;
}

std::optional<SkillTransition> transitionBetween(SkillState from, SkillState to) {
    for (const auto& r : kTransitions) {
        if (r.from == from && r.to == to) return r.transition;
    }
    return std::nullopt;
}

std::optional<SkillTransition> transitionFor(SkillMethod method, SkillState state) {
    switch (method) {
        case SkillMethod::Start:
            if (state != S::Ready) return std::nullopt;
            return Tr::ReadyToRunning;
        case SkillMethod::Suspend:
            if (state != S::Running) return std::nullopt;
            return Tr::RunningToSuspended;
        case SkillMethod::Resume:
            if (state != S::Suspended) return std::nullopt;
            return Tr::SuspendedToRunning;
        case SkillMethod::Halt:
            return transitionBetween(state, S::Halted);
        case SkillMethod::Reset:
            if (state != S::Halted) return std::nullopt;
            return Tr::HaltedToReady;
    }
    return std::nullopt;
}

ua::NodeId stateNodeId(SkillState state) {
    return ua::NodeId(row(state).nodeId);
}
ua::NodeId transitionNodeId(SkillTransition transition) {
    return ua::NodeId(row(transition).nodeId);
}
ua::NodeId methodNodeId(SkillMethod method) {
    return ua::NodeId(row(method).nodeId);
}

std::optional<SkillState> stateFromNodeId(const ua::NodeId& id) {
    for (const auto& r : kStates) {
        if (id == ua::NodeId(r.nodeId)) return r.state;
    }
    return std::nullopt;
}
std::optional<SkillTransition> transitionFromNodeId(const ua::NodeId& id) {
    for (const auto& r : kTransitions) {
        if (id == ua::NodeId(r.nodeId)) return r.transition;
    }
    return std::nullopt;
}

}  // namespace skillcell::skills
