// The process check (src/mes/process_check): the paper's process is clean against the skill
// models compiled in; each class of mistake in tests/data/processes/ gives the problems its
// first lines announce ("# expect: LINE: TEXT"), exactly those, at those lines; and the
// models know what a process needs of them (types, supertypes, inherited parameters).
#include "mes/process_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cell/cell_file.hpp"
#include "cell/scene_graph.hpp"
#include "kb/owl/embedded_ontologies.hpp"

namespace skillcell::mes::process_check_test {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(SKILLCELL_SOURCE_DIR) / "tests/data/processes";
constexpr const char* kTsk = "http://skillcell.dev/UA/ToolChangerSkills/";

const SkillModels& models() {
    static const SkillModels m = [] {
        auto e = SkillModels::embedded();
        EXPECT_TRUE(e) << e.error();
        return e ? std::move(*e) : SkillModels{};
    }();
    return m;
}

std::string readAll(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

struct Expectation {
    int line = 0;
    std::string text;
};

std::vector<Expectation> expectations(const std::string& text) {
    std::vector<Expectation> out;
    std::istringstream in(text);
    const std::string marker = "# expect: ";
    for (std::string line; std::getline(in, line);) {
        if (line.rfind(marker, 0) != 0) continue;
        Expectation e;
        const auto colon = line.find(": ", marker.size());
        e.line = std::stoi(line.substr(marker.size(), colon - marker.size()));
        e.text = line.substr(colon + 2);
        out.push_back(e);
    }
    return out;
}

TEST(ProcessCheck, ThePapersProcessIsClean) {
    const auto text = kb::owl::embeddedOntology("demo-process.ttl");
    // It names the paper cell's docks: clean with that cell's scene, and only with it.
    const auto cell =
        cell::readCellFile(std::string(SKILLCELL_SOURCE_DIR) + "/examples/cells/paper.toml");
    ASSERT_TRUE(cell.cell);
    const auto alone = checkProcessText(text, models());
    EXPECT_EQ(alone.size(), 3U) << "three steps take their tool from a dock of the cell";
    const auto problems = checkProcessText(text, models(), nullptr, cell::sceneTriples(*cell.cell));
    std::string all;
    for (const auto& p : problems) all += "\n  " + std::to_string(p.line) + ": " + p.message;
    EXPECT_TRUE(problems.empty()) << all;
}

TEST(ProcessCheck, ModelsKnowSkillTypesSupertypesAndInheritedParameters) {
    const std::string changeTool = std::string(kTsk) + "ChangeToolSkillType";
    ASSERT_NE(models().find(changeTool), nullptr);
    EXPECT_TRUE(models().isSkillType(changeTool));
    // An ObjectType that is not a skill.
    EXPECT_FALSE(models().isSkillType("http://opcfoundation.org/UA/BaseObjectType"));
    const auto parameters = models().parameters(changeTool);
    const auto tool = std::find_if(parameters.begin(), parameters.end(),
                                   [](const auto& p) { return p.name == "ToolPosition"; });
    ASSERT_NE(tool, parameters.end());
    EXPECT_EQ(tool->dataTypeIri, "http://opcfoundation.org/UA/i=18814");  // 3DFrame
    EXPECT_EQ(models().nearestSkillType(std::string(kTsk) + "ChangeToolSkilType"), changeTool);
    EXPECT_EQ(models().nearestSkillType("http://example.com/Teleport"), "");
}

TEST(ProcessCheck, TextWithoutAProcessIsAProblem) {
    const auto problems = checkProcessText("<http://a> <http://b> <http://c> .", models());
    ASSERT_EQ(problems.size(), 1U);
    EXPECT_EQ(problems[0].message, "no proc:Process in it");
}

TEST(TurtleLocator, FindsSubjectsByPrefixedOrFullNamesAndSkipsComments) {
    const TurtleLocator where(
        "@prefix ex: <http://e.x/> .\n"
        "# ex:a in a comment\n"
        "ex:p ex:has ex:a .\n"
        "ex:a ex:v \"x\" .\n"
        "<http://e.x/b> ex:v ex:ab .\n");
    EXPECT_EQ(where.subjectLine("http://e.x/a"), 4);
    EXPECT_EQ(where.iriLine("http://e.x/a", 1), 3);
    EXPECT_EQ(where.subjectLine("http://e.x/b"), 5);
    EXPECT_EQ(where.iriLine("http://e.x/ab", 1), 5);  // not ex:a
    EXPECT_EQ(where.subjectLine("http://e.x/none"), 0);
    EXPECT_EQ(where.textLine("\"x\"", 1), 4);
}

std::vector<std::string> badFiles() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kData)) {
        if (entry.path().extension() == ".ttl") names.push_back(entry.path().stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

class BadProcess : public testing::TestWithParam<std::string> {};

TEST_P(BadProcess, GivesEveryProblemAtItsLine) {
    const fs::path file = kData / (GetParam() + ".ttl");
    const std::string text = readAll(file);
    const auto expected = expectations(text);
    ASSERT_FALSE(expected.empty()) << file << " announces no problem (# expect: LINE: TEXT)";
    const auto problems = checkProcessText(text, models());
    std::string all;
    for (const auto& p : problems) all += "\n  " + std::to_string(p.line) + ": " + p.message;
    // Every announced problem is there, at its line, and nothing else.
    EXPECT_EQ(problems.size(), expected.size()) << all;
    for (const auto& e : expected) {
        const bool found = std::any_of(problems.begin(), problems.end(), [&](const auto& p) {
            return p.line == e.line && p.message.find(e.text) != std::string::npos;
        });
        EXPECT_TRUE(found) << "expected at line " << e.line << ": " << e.text << "\ngot:" << all;
    }
}

INSTANTIATE_TEST_SUITE_P(Classes, BadProcess, testing::ValuesIn(badFiles()),
                         [](const testing::TestParamInfo<std::string>& file) {
                             return file.param;
                         });

}  // namespace
}  // namespace skillcell::mes::process_check_test
