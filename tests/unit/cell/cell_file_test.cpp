// Cell files (src/cell): the paper's cell reads as the demo runs it, and each class of
// mistake in tests/data/cells/ gives the problems its first lines announce ("# expect:
// LINE:COLUMN: TEXT"), exactly those, at those places, and no cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cell/cell_file.hpp"

namespace skillcell::cell::cell_file_test {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = SKILLCELL_SOURCE_DIR;

TEST(CellFile, ThePapersCellReadsAsTheDemoRunsIt) {
    const auto result = readCellFile(kSource / "examples/cells/paper.toml");
    for (const auto& p : result.problems) ADD_FAILURE() << p.describe();
    ASSERT_TRUE(result.cell);
    const CellFile& c = *result.cell;
    EXPECT_EQ(c.name, "paper");
    EXPECT_EQ(c.network.kind, Network::Kind::PrivateNamespace);
    EXPECT_EQ(c.network.mdnsTtlSeconds, 5);
    EXPECT_EQ(c.network.mdnsQueryPeriodSeconds, 60);
    EXPECT_TRUE(c.security.enabled);
    EXPECT_TRUE(c.security.ca.empty());
    EXPECT_TRUE(c.lds);
    ASSERT_TRUE(c.kb);
    ASSERT_EQ(c.kb->processes.size(), 1U);
    EXPECT_EQ(c.kb->processes[0], (kSource / "models/owl/demo-process.ttl").lexically_normal());
    EXPECT_TRUE(c.mes);
    ASSERT_TRUE(c.dashboard);
    EXPECT_EQ(c.dashboard->port, 0);  // a free one
    ASSERT_EQ(c.docks.size(), 2U);
    EXPECT_EQ(c.docks[0].name, "dockP");
    EXPECT_EQ(c.docks[0].pose, (Pose{0.3, -0.45, 0.35, 3.141592653589793, 0, 0}));
    ASSERT_EQ(c.objects.size(), 2U);
    EXPECT_EQ(c.objects[1].name, "boxB");
    EXPECT_EQ(c.objects[1].size, (std::array<double, 3>{0.04, 0.04, 0.04}));
    EXPECT_EQ(c.objects[1].pose, (Pose{0.45, -0.05, 0.02, 0, 0, 0}));
    ASSERT_EQ(c.tools.size(), 2U);
    EXPECT_EQ(c.tools[0].name, "parallel");
    EXPECT_EQ(c.tools[0].dock, "dockP");
    EXPECT_EQ(c.tools[0].adapter, "robotiq-2f85");
    EXPECT_EQ(c.tools[0].gripOffset, (std::array<double, 3>{0, 0, 0.15}));
    EXPECT_EQ(c.tools[1].pinVoltage, (std::array<double, 2>{2.0, 2.5}));
    ASSERT_EQ(c.robots.size(), 1U);
    EXPECT_EQ(c.robots[0].model, "ur5");
    EXPECT_EQ(c.robots[0].speed, 10);
    ASSERT_EQ(c.toolChangers.size(), 1U);
    EXPECT_EQ(c.toolChangers[0].name, "toolchanger");
    EXPECT_EQ(c.toolChangers[0].robot, "ur5");  // the only robot
    for (const auto& t : c.tools) EXPECT_EQ(t.changer, "toolchanger") << t.name;
    ASSERT_EQ(c.pickAndPlaces.size(), 1U);
    EXPECT_EQ(c.pickAndPlaces[0].name, "pickplace");
}

/// The "# expect: LINE:COLUMN: TEXT" lines at the top of a file.
struct Expected {
    int line = 0;
    int column = 0;
    std::string text;
};

std::vector<Expected> expectations(const fs::path& file) {
    std::ifstream in(file);
    std::vector<Expected> out;
    std::string line;
    const std::string tag = "# expect: ";
    while (std::getline(in, line) && line.rfind('#', 0) == 0) {
        if (line.rfind(tag, 0) != 0) continue;
        Expected e;
        std::size_t used = 0;
        const std::string rest = line.substr(tag.size());
        e.line = std::stoi(rest, &used);
        const std::string afterLine = rest.substr(used + 1);
        e.column = std::stoi(afterLine, &used);
        e.text = afterLine.substr(used + 2);
        out.push_back(e);
    }
    return out;
}

std::vector<std::string> badFiles() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kSource / "tests/data/cells")) {
        if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

class BadCellFile : public testing::TestWithParam<std::string> {};

TEST_P(BadCellFile, GivesItsProblemsWithFileLineAndColumnAndNoCell) {
    const fs::path file = kSource / "tests/data/cells" / (GetParam() + ".toml");
    const auto expected = expectations(file);
    ASSERT_FALSE(expected.empty()) << file << " announces no problem (# expect: LINE:COLUMN: TEXT)";
    const auto result = readCellFile(file);
    EXPECT_FALSE(result.cell);
    std::string all;
    for (const auto& p : result.problems) all += "\n  " + p.describe();
    ASSERT_EQ(result.problems.size(), expected.size()) << "problems:" << all;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const Problem& p = result.problems[i];
        EXPECT_EQ(p.file, file.string());
        EXPECT_EQ(p.line, expected[i].line) << p.describe();
        EXPECT_EQ(p.column, expected[i].column) << p.describe();
        EXPECT_NE(p.message.find(expected[i].text), std::string::npos)
            << "expected \"" << expected[i].text << "\" in: " << p.describe();
    }
}

INSTANTIATE_TEST_SUITE_P(Classes, BadCellFile, testing::ValuesIn(badFiles()),
                         [](const testing::TestParamInfo<std::string>& file) {
                             return file.param;
                         });

TEST(CellFile, AFileThatCannotBeOpenedIsOneProblemNamingIt) {
    const auto result = readCellFile("/nonexistent/cell.toml");
    EXPECT_FALSE(result.cell);
    ASSERT_EQ(result.problems.size(), 1U);
    EXPECT_EQ(result.problems[0].describe(),
              "/nonexistent/cell.toml: cannot open: No such file or directory");
}

TEST(CellFile, DefaultsApplyWhereAFileIsSilent) {
    const auto result = readCellText("name = \"bare\"\n", "bare.toml", ".");
    ASSERT_TRUE(result.cell);
    EXPECT_EQ(result.cell->network.kind, Network::Kind::PrivateNamespace);
    EXPECT_EQ(result.cell->network.mdnsTtlSeconds, 120);
    EXPECT_TRUE(result.cell->security.enabled);
    EXPECT_FALSE(result.cell->lds);
    EXPECT_FALSE(result.cell->kb);
    EXPECT_TRUE(result.cell->toolChangers.empty());
}

TEST(CellFile, ComponentsOnHostsOfTheirOwnAreNamedByTheirHostKeyOrPlacedLater) {
    const auto result = readCellText(
        "name = \"two-pcs\"\n[kb]\nhost = \"server\"\n[mes]\nhost = \"mes-pc\"\n[lds]\n",
        "two-pcs.toml", ".");
    for (const auto& p : result.problems) ADD_FAILURE() << p.describe();
    ASSERT_TRUE(result.cell);
    CellFile c = *result.cell;
    EXPECT_EQ(c.hostOf("kb"), "server");
    EXPECT_EQ(c.hostOf("mes"), "mes-pc");
    EXPECT_EQ(c.hostOf("lds"), "");  // the cell's own network
    EXPECT_EQ(c.hostNames(), (std::vector<std::string>{"mes-pc", "server"}));
    // `cell up --host`: the same checks as the key, and the component must be there.
    EXPECT_EQ(placeOnHost(c, "lds", "server"), "");
    EXPECT_EQ(c.hostOf("lds"), "server");
    EXPECT_EQ(c.hostNames(), (std::vector<std::string>{"mes-pc", "server"}));
    EXPECT_EQ(placeOnHost(c, "ur5", "robot-pc"),
              "the cell has no component 'ur5'; it has: lds, kb, mes");
    EXPECT_NE(placeOnHost(c, "mes", "MES").find("use 1 to 12 lower-case letters"),
              std::string::npos);
    EXPECT_EQ(c.hostOf("mes"), "mes-pc");  // a refused placement changes nothing
}

}  // namespace
}  // namespace skillcell::cell::cell_file_test
