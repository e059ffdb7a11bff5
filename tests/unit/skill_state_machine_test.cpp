// The state machine table against OPC 10000-10, 4.2.2: every (method, state) pair, and the
// consistency of numbers, names and NodeIds.
#include <gtest/gtest.h>

#include "skills/skill_state_machine.hpp"

namespace skillcell::skills::skill_state_machine_test {
namespace {

using S = SkillState;
using T = SkillTransition;
using M = SkillMethod;

TEST(SkillStateMachine, EveryMethodInEveryState) {
    struct Case {
        M method;
        S state;
        std::optional<T> expected;
    };
    const Case cases[] = {
        {M::Start, S::Ready, T::ReadyToRunning},
        {M::Start, S::Running, std::nullopt},
        {M::Start, S::Suspended, std::nullopt},
        {M::Start, S::Halted, std::nullopt},
        {M::Suspend, S::Running, T::RunningToSuspended},
        {M::Suspend, S::Ready, std::nullopt},
        {M::Suspend, S::Suspended, std::nullopt},
        {M::Suspend, S::Halted, std::nullopt},
        {M::Resume, S::Suspended, T::SuspendedToRunning},
        {M::Resume, S::Ready, std::nullopt},
        {M::Resume, S::Running, std::nullopt},
        {M::Resume, S::Halted, std::nullopt},
        {M::Halt, S::Ready, T::ReadyToHalted},
        {M::Halt, S::Running, T::RunningToHalted},
        {M::Halt, S::Suspended, T::SuspendedToHalted},
        {M::Halt, S::Halted, std::nullopt},
        {M::Reset, S::Halted, T::HaltedToReady},
        {M::Reset, S::Ready, std::nullopt},
        {M::Reset, S::Running, std::nullopt},
        {M::Reset, S::Suspended, std::nullopt},
    };
    for (const auto& c : cases) {
        EXPECT_EQ(transitionFor(c.method, c.state), c.expected)
            << name(c.method) << " in " << name(c.state);
    }
}

TEST(SkillStateMachine, TransitionsConnectTheirStates) {
    for (T t : kAllTransitions) {
        EXPECT_EQ(transitionBetween(fromState(t), toState(t)), t) << name(t);
        EXPECT_EQ(name(t), std::string(name(fromState(t))) + "To" + std::string(name(toState(t))));
        EXPECT_EQ(transitionFromNumber(static_cast<std::uint32_t>(t)), t);
        EXPECT_EQ(transitionFromNodeId(transitionNodeId(t)), t);
    }
    EXPECT_FALSE(transitionBetween(S::Halted, S::Running));
    EXPECT_FALSE(transitionBetween(S::Ready, S::Suspended));
    EXPECT_FALSE(transitionFromNumber(0));
    EXPECT_FALSE(transitionFromNumber(10));
}

TEST(SkillStateMachine, StatesAndMethodsRoundTrip) {
    for (S s : kAllStates) {
        EXPECT_EQ(stateFromNumber(static_cast<std::uint32_t>(s)), s);
        EXPECT_EQ(stateFromName(name(s)), s);
        EXPECT_EQ(stateFromNodeId(stateNodeId(s)), s);
    }
    EXPECT_EQ(stateNodeId(S::Ready), ua::NodeId(2400));
    EXPECT_FALSE(stateFromNumber(1));
    EXPECT_FALSE(stateFromName("ready"));
    for (M m : kAllMethods) EXPECT_EQ(methodFromName(name(m)), m);
    EXPECT_EQ(methodNodeId(M::Reset), ua::NodeId(2430));
    EXPECT_FALSE(methodFromName("Abort"));
}

}  // namespace
}  // namespace skillcell::skills::skill_state_machine_test
