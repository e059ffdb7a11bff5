// The MES's journal: what it records survives closing and reopening the file, the run to
// resume is the latest unfinished one of its process (the one a report shows is the latest
// of any state), and a file that is not a journal is refused with its name.
#include "mes/journal.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "temp_dir.hpp"

namespace skillcell::mes::journal_test {
namespace {

class JournalTest : public testing::Test {
protected:
    [[nodiscard]] std::string file() const { return dir_ / "journal.sqlite"; }

    test::TempDir dir_{"skillcell-journal"};
};

StepRecord step(int index, int attempt, StepState state) {
    StepRecord s;
    s.index = index;
    s.attempt = attempt;
    s.stepIri = "http://example.org/p#s" + std::to_string(index);
    s.state = state;
    s.skillTypeIri = "http://skillcell.dev/UA/ToolChangerSkills/ChangeToolSkillType";
    s.componentUri = "urn:c";
    s.endpointUrl = "opc.tcp://127.0.0.1:4841";
    s.skillNodeId = "ns=1;s=Skills/ChangeTool";
    s.transitionTimeBefore = 133'000'000'000'000'000 + index;
    s.startedMs = 1000 * index;
    return s;
}

TEST_F(JournalTest, KeepsRunsAndStepsAcrossReopening) {
    std::int64_t id = 0;
    {
        auto j = Journal::open(file());
        ASSERT_TRUE(j) << j.error();
        auto run = (*j)->beginRun("http://example.org/p");
        ASSERT_TRUE(run) << run.error();
        id = *run;
        ASSERT_TRUE((*j)->recordStep(id, step(1, 1, StepState::Starting)));
        auto done = step(1, 1, StepState::Finished);
        done.endedMs = 5000;
        ASSERT_TRUE((*j)->recordStep(id, done));  // replaces the Starting row
        auto failed = step(2, 1, StepState::Failed);
        failed.reason = "Lost (BadConnectionClosed)";
        ASSERT_TRUE((*j)->recordStep(id, failed));
        auto retry = step(2, 2, StepState::Starting);
        retry.note = "retry 1 of 1 after: Halted";
        ASSERT_TRUE((*j)->recordStep(id, retry));
    }
    auto j = Journal::open(file());
    ASSERT_TRUE(j) << j.error();
    auto run = (*j)->run(id);
    ASSERT_TRUE(run && *run);
    const RunRecord& r = **run;
    EXPECT_EQ(r.processIri, "http://example.org/p");
    EXPECT_EQ(r.state, RunState::Running);
    ASSERT_EQ(r.steps.size(), 3U);
    EXPECT_EQ(r.steps[0].state, StepState::Finished);
    EXPECT_EQ(r.steps[0].endedMs, 5000);
    EXPECT_EQ(r.steps[0].transitionTimeBefore, 133'000'000'000'000'001);
    EXPECT_EQ(r.steps[0].skillNodeId, "ns=1;s=Skills/ChangeTool");
    EXPECT_EQ(r.steps[1].reason, "Lost (BadConnectionClosed)");
    const StepRecord* last = r.lastAttempt(2);
    ASSERT_NE(last, nullptr);
    EXPECT_EQ(last->attempt, 2);
    EXPECT_EQ(last->state, StepState::Starting);
    EXPECT_EQ(last->note, "retry 1 of 1 after: Halted");
    EXPECT_EQ(r.lastAttempt(3), nullptr);
}

TEST_F(JournalTest, AJournalFromBeforeStepNotesGainsTheColumnAndKeepsItsRuns) {
    // The tables as the MES wrote them before steps had a note.
    const std::string script = dir_ / "old.sql";
    std::ofstream(script)
        << "CREATE TABLE runs (id INTEGER PRIMARY KEY AUTOINCREMENT, process "
           "TEXT NOT NULL, state TEXT NOT NULL, reason TEXT NOT NULL DEFAULT '', "
           "started_ms INTEGER NOT NULL, ended_ms INTEGER NOT NULL DEFAULT 0);\n"
           "CREATE TABLE steps (run INTEGER NOT NULL REFERENCES runs(id), idx "
           "INTEGER NOT NULL, attempt INTEGER NOT NULL, step TEXT NOT NULL, "
           "state TEXT NOT NULL, skill_type TEXT NOT NULL, component TEXT NOT "
           "NULL, endpoint TEXT NOT NULL, skill_node TEXT NOT NULL, "
           "transition_before INTEGER NOT NULL, reason TEXT NOT NULL, started_ms "
           "INTEGER NOT NULL, ended_ms INTEGER NOT NULL, PRIMARY KEY (run, idx, "
           "attempt));\n"
           "INSERT INTO runs VALUES (1, 'http://example.org/p', 'completed', '', "
           "1, 2);\n"
           "INSERT INTO steps VALUES (1, 1, 1, 'http://example.org/p#s1', "
           "'finished', 't', 'urn:c', 'opc.tcp://h:1', 'ns=1;i=1', 0, '', 1, 2);\n";
    ASSERT_EQ(std::system(("sqlite3 " + file() + " < " + script).c_str()), 0);
    auto j = Journal::open(file());
    ASSERT_TRUE(j) << j.error();
    auto old = (*j)->run(1);
    ASSERT_TRUE(old && *old);
    ASSERT_EQ((**old).steps.size(), 1U);
    EXPECT_EQ((**old).steps[0].note, "");
    auto again = Journal::open(file());  // a second opener finds the column there
    ASSERT_TRUE(again) << again.error();
    auto run = (*again)->beginRun("http://example.org/p");
    ASSERT_TRUE(run);
    auto s = step(1, 1, StepState::Finished);
    s.note = "the skill was Halted: reset";
    ASSERT_TRUE((*again)->recordStep(*run, s));
    EXPECT_EQ((**(*j)->run(*run)).steps[0].note, "the skill was Halted: reset");
}

TEST_F(JournalTest, TheRunToResumeIsTheLatestUnfinishedOneOfItsProcess) {
    auto j = Journal::open(file());
    ASSERT_TRUE(j) << j.error();
    Journal& journal = **j;
    const auto a1 = *journal.beginRun("urn:a");
    ASSERT_TRUE(journal.setRunState(a1, RunState::Completed, {}));
    const auto b1 = *journal.beginRun("urn:b");
    ASSERT_TRUE(journal.setRunState(b1, RunState::Stopped, "step 3: no vacuum gripper"));
    auto none = journal.unfinishedRun("urn:a");
    ASSERT_TRUE(none);
    EXPECT_FALSE(*none) << "a completed run is not resumed";
    auto b = journal.unfinishedRun("urn:b");
    ASSERT_TRUE(b && *b);
    EXPECT_EQ((*b)->id, b1);
    EXPECT_EQ((*b)->state, RunState::Stopped);
    EXPECT_EQ((*b)->reason, "step 3: no vacuum gripper");
    EXPECT_GT((*b)->endedMs, 0);
    const auto a2 = *journal.beginRun("urn:a");
    auto a = journal.unfinishedRun("urn:a");
    ASSERT_TRUE(a && *a);
    EXPECT_EQ((*a)->id, a2);
    ASSERT_TRUE(journal.setRunState(a2, RunState::Completed, {}));
    auto latest = journal.latestRun("urn:a");
    ASSERT_TRUE(latest && *latest);
    EXPECT_EQ((*latest)->id, a2) << "the latest run, completed or not";
    auto nothing = journal.latestRun("urn:never-run");
    ASSERT_TRUE(nothing);
    EXPECT_FALSE(*nothing);
    auto all = journal.unfinishedRuns();
    ASSERT_TRUE(all);
    EXPECT_EQ(all->size(), 1U);
    EXPECT_FALSE(journal.setRunState(9999, RunState::Completed, {})) << "no such run";
}

TEST_F(JournalTest, TheRecentRunsAreTheLastOnesOldestFirstWithTheirSteps) {
    auto j = Journal::open(file());
    ASSERT_TRUE(j) << j.error();
    Journal& journal = **j;
    auto none = journal.recentRuns(5);
    ASSERT_TRUE(none) << none.error();
    EXPECT_TRUE(none->empty());
    std::vector<std::int64_t> ids;
    for (int i = 0; i < 7; ++i) ids.push_back(*journal.beginRun("urn:p" + std::to_string(i)));
    ASSERT_TRUE(journal.recordStep(ids.back(), step(1, 1, StepState::Running)));
    auto recent = journal.recentRuns(3);
    ASSERT_TRUE(recent) << recent.error();
    ASSERT_EQ(recent->size(), 3U);
    EXPECT_EQ((*recent)[0].id, ids[4]);
    EXPECT_EQ((*recent)[2].id, ids[6]);
    EXPECT_EQ((*recent)[2].processIri, "urn:p6");
    ASSERT_EQ((*recent)[2].steps.size(), 1U);
    EXPECT_EQ((*recent)[2].steps[0].state, StepState::Running);
    EXPECT_EQ(journal.recentRuns(100)->size(), 7U);
    EXPECT_TRUE(journal.recentRuns(0)->empty());
}

TEST_F(JournalTest, RefusesAFileThatIsNotAJournalNamingIt) {
    {
        std::ofstream out(file());
        out << "this is not an SQLite database, but long enough to look like a header.....\n";
    }
    auto j = Journal::open(file());
    ASSERT_FALSE(j);
    EXPECT_NE(j.error().find(file()), std::string::npos) << j.error();
    auto missing = Journal::open(dir_ / "no/such/dir/journal.sqlite");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().find("no/such/dir"), std::string::npos) << missing.error();
}

}  // namespace
}  // namespace skillcell::mes::journal_test
