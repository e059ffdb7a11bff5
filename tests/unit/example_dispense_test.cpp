// The example of a new skill type (examples/dispense_skill) works end to end: its NodeSet2
// file loads after the companion models, the Skill instantiates it with its EURange
// checks, and a SkillClient runs it to the end or into its failure.
#include <gtest/gtest.h>

#include "client_thread.hpp"
#include "dispense_behaviour.hpp"
#include "running_server.hpp"
#include "skills/skill_server.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::examples::example_dispense_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

TEST(ExampleDispenseSkill, RunsFromItsOwnNodeSetAndOneClass) {
    std::unique_ptr<skills::SkillServer> skills;
    DispenseBehaviour* dispenser = nullptr;
    test::RunningServer server(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
        skills = skills::SkillServer::create(s, s.executor());
        ASSERT_TRUE(skills);
        const auto loaded = ua::loadNodeSetFile(s.addressSpace(), SKILLCELL_EXAMPLE_MODEL);
        ASSERT_TRUE(loaded.ok()) << loaded.error;
        const auto type = ua::findTypeByName(
            s.addressSpace(), "http://skillcell.dev/UA/Examples/Dispense/", "DispenseSkillType");
        ASSERT_TRUE(type);
        auto behaviour = std::make_unique<DispenseBehaviour>(s.executor(), 10.0, 100.0);
        dispenser = behaviour.get();
        ASSERT_TRUE(skills->add(*type, "Dispense", std::move(behaviour)));
    });
    test::ClientThread t;
    auto dispense = t.attach(server.url(), ua::NodeId(1, ua::String("Skills/Dispense")));
    ASSERT_TRUE(dispense);

    auto outcome = t.invoke(dispense, {{"Volume", 4.0}, {"FlowRate", 10.0}}, 5s);
    EXPECT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_DOUBLE_EQ(server.inServer([&](ua::Server&) { return dispenser->reservoirMl(); }), 6.0);

    outcome = t.invoke(dispense, {{"Volume", 60.0}}, 5s);  // EURange 0..50
    EXPECT_EQ(outcome.kind, Kind::Refused);
    EXPECT_EQ(outcome.status, ua::status::BadOutOfRange);

    outcome = t.invoke(dispense, {{"Volume", 8.0}}, 5s);  // more than the 6 ml left
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("reservoir"), std::string::npos) << outcome.reason;
    server.inServer([&](ua::Server&) {  // the dispenser's timer goes before the io_context
        skills.reset();
        return 0;
    });
}

}  // namespace
}  // namespace skillcell::examples::example_dispense_test
