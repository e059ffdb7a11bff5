// The PlaceTerminalBlock composite in a work cell of processes (discovery on, in a private
// network namespace): the world model with the rail and the terminal blocks of
// examples/cells/din-rail.toml, the UR5, the tool changer with the Robotiq 2F-85 and the
// pick-and-place component. Two blocks are placed side by side at the next free position;
// a third asked to go over the second is refused before anything moves, with the reason;
// the world model then shows each block's position along the rail.
#include <gtest/gtest.h>

#include "client_thread.hpp"
#include "devices/world/world_link.hpp"
#include "simulated_cell.hpp"

namespace skillcell::devices::device_din_rail_cell_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;

/// The din-rail cell's rails and terminal blocks, as the world model's arguments.
std::vector<std::string> railScene(const cell::CellFile& c) {
    cell::CellFile scene;
    scene.rails = c.rails;
    scene.objects = c.objects;
    return cell::worldArguments(scene);
}

TEST(DinRailCell, PlacesBlocksSideBySideAndRefusesOneOverAnother) {
    const cell::CellFile din = test::exampleCell("din-rail");
    ASSERT_EQ(din.rails.size(), 1u);
    const double width = din.objects.at(0).size[0];
    test::SimulatedCell cell(SKILLCELL_BINARY, {}, true, test::kRobotiq2f85, false, "50",
                             railScene(din));
    ASSERT_TRUE(cell.ready());

    auto link = WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    WorldLink& w = **link;
    test::ClientThread client, placeClient;
    auto change =
        client.attach(cell.changer->url(), ua::NodeId(1, ua::String("Skills/ChangeTool")));
    auto place = placeClient.attach(cell.pickplace->url(),
                                    ua::NodeId(1, ua::String("Skills/PlaceTerminalBlock")));
    ASSERT_TRUE(change && place);
    auto outcome = client.invoke(change,
                                 {{"ToolPosition", test::poseValue(test::parallelDock())},
                                  {"ToolAppUri", test::textValue(cell.parallelUri.c_str())}},
                                 60s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;

    const std::string rail = din.rails[0].name;
    for (const char* block : {"tb1", "tb2"}) {
        outcome = placeClient.invoke(place,
                                     {{"ObjectId", test::textValue(block)},
                                      {"RailId", test::textValue(rail.c_str())},
                                      {"Position", ua::Variant(-1.0)}},
                                     120s);
        ASSERT_EQ(outcome.kind, Kind::Finished) << block << ": " << outcome.reason;
    }
    const auto tb1 = w.railMount("tb1");
    const auto tb2 = w.railMount("tb2");
    ASSERT_TRUE(tb1.ok() && *tb1 && tb2.ok() && *tb2);
    EXPECT_EQ((*tb1)->rail, rail);
    EXPECT_NEAR((*tb1)->position, width / 2, 1e-6);
    EXPECT_NEAR((*tb2)->position, width * 3 / 2, 1e-6);  // side by side at its width
    EXPECT_EQ(*w.graspedObject(), "");

    // Over tb2: refused before the robot moves, naming both blocks.
    const auto before = w.objectPose("tb3");
    ASSERT_TRUE(before.ok());
    outcome = placeClient.invoke(place,
                                 {{"ObjectId", test::textValue("tb3")},
                                  {"RailId", test::textValue(rail.c_str())},
                                  {"Position", ua::Variant(width * 3 / 2 + 0.001)}},
                                 120s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("terminal block tb3 at 8.8 mm on rail rail1 would sit over "
                                  "terminal block tb2 at 7.8 mm"),
              std::string::npos)
        << outcome.reason;
    const auto after = w.objectPose("tb3");
    ASSERT_TRUE(after.ok());
    EXPECT_TRUE(near(*before, *after, 1e-9, 1e-9));
    const auto tb3 = w.railMount("tb3");
    ASSERT_TRUE(tb3.ok());
    EXPECT_FALSE(tb3->has_value());
    // A rail the world does not have: the reason names it.
    ASSERT_EQ(placeClient.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await place->call(skills::SkillMethod::Reset);
    }),
              ua::status::Good);
    outcome = placeClient.invoke(place,
                                 {{"ObjectId", test::textValue("tb3")},
                                  {"RailId", test::textValue("rail9")},
                                  {"Position", ua::Variant(-1.0)}},
                                 120s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("no rail rail9"), std::string::npos) << outcome.reason;
}

}  // namespace
}  // namespace skillcell::devices::device_din_rail_cell_test
