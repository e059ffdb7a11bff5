// The semantic MES in the paper's work cell, every component a process with discovery on (in
// a private network namespace): the knowledge base with the demo process, the world model,
// UR5, tool changer with both grippers' adapters, pick and place, and `skillcell mes`.
// `skillcell run` hands it the demo process; the test checks the world (both boxes at their
// targets, no tool mounted) and the journal (every step run exactly once). Then the faults:
// the MES killed mid-process and restarted (after its step's skill ended, and while that skill
// still runs), the vacuum gripper's adapter missing until the process has stopped for want
// of it, and a vacuum gripper in the parallel gripper's dock (the pick that needs a parallel
// grip does not start).
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <set>
#include <thread>

#include "devices/world/world_link.hpp"
#include "mes/journal.hpp"
#include "simulated_cell.hpp"
#include "temp_dir.hpp"
#include "ua/client/blocking_client.hpp"

namespace skillcell::mes::mes_cell_test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// Processes the MES must refuse before any motion (tests/data/mes/refused_processes.ttl).
const std::string kRefusedProcesses =
    std::string(SKILLCELL_SOURCE_DIR) + "/tests/data/mes/refused_processes.ttl";
// Processes of one step with and without retries (tests/data/mes/retried_processes.ttl).
const std::string kRetriedProcesses =
    std::string(SKILLCELL_SOURCE_DIR) + "/tests/data/mes/retried_processes.ttl";
constexpr const char* kRetried = "http://skillcell.dev/test/retried#";
// A process of three steps on no-op skills (tests/data/mes/orders.ttl).
const std::string kOrderProcesses =
    std::string(SKILLCELL_SOURCE_DIR) + "/tests/data/mes/orders.ttl";
constexpr const char* kThreeSteps = "http://skillcell.dev/test/orders#three";
constexpr const char* kRefused = "http://skillcell.dev/test/refused#";
constexpr const char* kDemo = "http://skillcell.dev/demo#pickAndPlaceTwoBoxes";

std::vector<std::string> withFastMdns(std::vector<std::string> args) {
    for (const char* a : {"--mdns-ttl", "5", "--mdns-query-period", "1"}) args.emplace_back(a);
    return args;
}

// The port of the KB's "SPARQL http://127.0.0.1:PORT/sparql" line.
std::string sparqlUrl(const test::ComponentProcess& kb) {
    for (const auto& line : kb.output()) {
        if (line.rfind("SPARQL ", 0) == 0) return line.substr(7);
    }
    return {};
}

struct RunResult {
    int exitCode = -1;
    std::string output;
};

// A command's output and exit code; the command bounds itself (its --timeout).
RunResult shell(const std::string& command) {
    RunResult r;
    FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (pipe == nullptr) return r;
    std::array<char, 512> buffer{};
    while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) r.output += buffer.data();
    const int status = ::pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// `skillcell run` to its end (bounded by its --timeout).
RunResult runNamedProcess(const std::string& mesUrl, const std::string& process) {
    return shell(std::string(SKILLCELL_BINARY) + " run " + process + " --mes " + mesUrl +
                 " --insecure --timeout 240");
}
RunResult runProcess(const std::string& mesUrl) {
    return runNamedProcess(mesUrl, kDemo);
}
// `skillcell orders wait ID`: follows an order (one a restarted MES resumed) to its end.
RunResult waitForOrder(const std::string& mesUrl, std::int64_t order) {
    return shell(std::string(SKILLCELL_BINARY) + " orders wait " + std::to_string(order) +
                 " --mes " + mesUrl + " --insecure --timeout 240");
}

void expectAt(devices::WorldLink& w, const std::string& id, double x, double y, double z) {
    const auto p = w.objectPose(id);
    ASSERT_TRUE(p.ok()) << id;
    EXPECT_NEAR(p->p.x(), x, 1e-3) << id;
    EXPECT_NEAR(p->p.y(), y, 1e-3) << id;
    EXPECT_NEAR(p->p.z(), z, 1e-3) << id;
}

// The demo process's work done: both boxes at their targets, no tool mounted.
void expectTheProcessDone(const test::SimulatedCell& cell) {
    auto link = devices::WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    expectAt(**link, "boxA", 0.25, 0.35, 0.025);
    expectAt(**link, "boxB", 0.25, -0.2, 0.02);
    EXPECT_EQ(*(*link)->mountedTool(), "");
}

// Attempts that really ran the skill: finished ones, and failed ones whose Start got through.
int runsOf(const RunRecord& run, int index) {
    int n = 0;
    for (const auto& s : run.steps) {
        if (s.index != index) continue;
        if (s.state == StepState::Finished) ++n;
        if (s.state == StepState::Failed &&
            s.reason.find("Start never reached") == std::string::npos)
            ++n;
    }
    return n;
}

class MesCell : public testing::Test {
protected:
    void SetUp() override {
        kb_ = std::make_unique<test::ComponentProcess>(
            SKILLCELL_BINARY,
            withFastMdns({"kb", "--demo-process", "--process", kRefusedProcesses, "--process",
                          kRetriedProcesses, "--process", kOrderProcesses, "--http-port", "0",
                          "--data-dir", dir_ / "kb"}),
            true);
        ASSERT_FALSE(kb_->url().empty()) << "the KB did not start";
        kbUrl_ = sparqlUrl(*kb_);
        ASSERT_FALSE(kbUrl_.empty());
    }
    void TearDown() override {
        mes_.reset();
        kb_.reset();
    }
    /// `skillWaitMs`: how long a step waits for a suitable skill to be detected.
    void startMes(const std::string& skillWaitMs = "15000") { mes_ = newMes(skillWaitMs); }
    [[nodiscard]] std::unique_ptr<test::ComponentProcess> newMes(
        const std::string& skillWaitMs = "15000") const {
        return std::make_unique<test::ComponentProcess>(
            SKILLCELL_BINARY,
            withFastMdns({"mes", "--kb", kbUrl_, "--journal", journalPath(), "--skill-wait-ms",
                          skillWaitMs, "--step-timeout-ms", "120000"}),
            true);
    }
    [[nodiscard]] std::string journalPath() const { return dir_ / "journal.sqlite"; }
    [[nodiscard]] std::optional<RunRecord> lastRun(std::int64_t id = 1) const {
        auto j = Journal::open(journalPath());
        if (!j) return std::nullopt;
        auto r = (*j)->run(id);
        if (!r || !*r) return std::nullopt;
        return **r;
    }

    test::TempDir dir_{"skillcell-mes-cell"};
    std::unique_ptr<test::ComponentProcess> kb_, mes_;
    std::string kbUrl_;
};

TEST_F(MesCell, RunsThePapersProcessOnTheSkillsDiscoveryFinds) {
    test::SimulatedCell cell(SKILLCELL_BINARY, test::paperObjects(), true);
    ASSERT_TRUE(cell.ready());
    startMes();
    ASSERT_FALSE(mes_->url().empty());

    const RunResult result = runProcess(mes_->url());
    EXPECT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(result.output.find("OUTCOME Finished"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("step 3/5 ChangeToolSkillType running Skills/ChangeTool @ "
                                 "urn:skillcell:device:kelvin-toolchanger"),
              std::string::npos)
        << result.output;
    EXPECT_NE(result.output.find("step 5/5 DetachToolSkillType completed"), std::string::npos)
        << result.output;

    expectTheProcessDone(cell);

    const auto run = lastRun();
    ASSERT_TRUE(run);
    EXPECT_EQ(run->state, RunState::Completed);
    ASSERT_EQ(run->steps.size(), 5U);
    for (int i = 1; i <= 5; ++i) {
        const StepRecord* s = run->lastAttempt(i);
        ASSERT_NE(s, nullptr);
        EXPECT_EQ(s->state, StepState::Finished) << i;
        EXPECT_EQ(s->attempt, 1) << i;
        EXPECT_GE(s->endedMs, s->startedMs);
    }
    EXPECT_EQ(run->steps[0].componentUri, "urn:skillcell:device:kelvin-toolchanger");
    EXPECT_EQ(run->steps[1].componentUri, "urn:skillcell:device:pick-and-place");

    // The MES filled in the gripper it checked each pick against: the pick-and-place skill's
    // ToolSkillControllerEndpoint holds an endpoint (the vacuum gripper's, of step 4), not
    // the empty "use the detected one".
    const RunResult browse =
        shell(std::string(SKILLCELL_BINARY) + " browse " + cell.pickplace->url() +
              " --values --insecure --pki-dir " + (dir_ / "browser"));
    ASSERT_EQ(browse.exitCode, 0) << browse.output;
    const auto at = browse.output.find("ToolSkillControllerEndpoint");
    ASSERT_NE(at, std::string::npos) << browse.output;
    const std::string line = browse.output.substr(at, browse.output.find('\n', at) - at);
    EXPECT_NE(line.find("opc.tcp://127.0.0.1:"), std::string::npos) << line;
}

TEST_F(MesCell, AKilledMesResumesWhereItStoppedRunningEveryStepOnce) {
    test::SimulatedCell cell(SKILLCELL_BINARY, test::paperObjects(), true);
    ASSERT_TRUE(cell.ready());
    startMes();
    ASSERT_FALSE(mes_->url().empty());
    auto first = std::async(std::launch::async, runProcess, mes_->url());

    // Kill the MES once step 2 (the first pick and place) has been started.
    bool killed = false;
    for (int i = 0; i < 600 && !killed; ++i) {  // bounded: 60 s
        if (auto run = lastRun(); run && run->lastAttempt(2) != nullptr) {
            EXPECT_TRUE(mes_->kill(SIGKILL).has_value());
            killed = true;
            break;
        }
        std::this_thread::sleep_for(100ms);  // a bounded poll of the journal file
    }
    ASSERT_TRUE(killed) << "step 2 never started";
    const RunResult lost = first.get();
    EXPECT_EQ(lost.exitCode, 1) << lost.output;
    EXPECT_NE(lost.output.find("OUTCOME Lost"), std::string::npos) << lost.output;

    // The restarted MES resumes the order by itself; the operator follows it.
    startMes();
    ASSERT_FALSE(mes_->url().empty());
    const RunResult result = waitForOrder(mes_->url(), 1);
    EXPECT_EQ(result.exitCode, 0) << result.output;

    expectTheProcessDone(cell);
    const auto run = lastRun();
    ASSERT_TRUE(run);
    EXPECT_EQ(run->state, RunState::Completed);
    for (int i = 1; i <= 5; ++i) {
        EXPECT_EQ(runsOf(*run, i), 1) << "step " << i;
        ASSERT_NE(run->lastAttempt(i), nullptr);
        EXPECT_EQ(run->lastAttempt(i)->state, StepState::Finished) << i;
    }
}

TEST_F(MesCell, AMesRestartedWhileItsSkillStillRunsWaitsForThatRunInsteadOfStartingAnother) {
    // A slow robot: the first pick and place runs for seconds, long enough to kill the MES
    // while it runs and hand the process to another one.
    test::SimulatedCell cell(SKILLCELL_BINARY, test::paperObjects(), true, test::kRobotiq2f85, true,
                             "1");
    ASSERT_TRUE(cell.ready());
    startMes();
    ASSERT_FALSE(mes_->url().empty());
    auto first = std::async(std::launch::async, runProcess, mes_->url());
    // The MES that takes over, started now: a start (seconds under the sanitizers) would
    // otherwise outlast the step it must find still running.
    auto standby = newMes();
    ASSERT_FALSE(standby->url().empty());

    // Kill the MES once the pick-and-place skill runs step 2.
    ua::BlockingClient observer;
    ASSERT_TRUE(observer.connect(cell.pickplace->url()).isGood());
    const ua::NodeId state(1, ua::String("Skills/PickAndPlace/CurrentState"));
    bool killed = false;
    for (int i = 0; i < 1200 && !killed; ++i) {  // bounded: 120 s
        const auto run = lastRun();
        const auto value = observer.readValue(state);
        const auto* text = value.ok() ? value->get<ua::LocalizedText>() : nullptr;
        if (run && run->lastAttempt(2) != nullptr && text != nullptr && text->text == "Running") {
            EXPECT_TRUE(mes_->kill(SIGKILL).has_value());
            killed = true;
            break;
        }
        std::this_thread::sleep_for(100ms);  // a bounded poll of the journal and the skill
    }
    ASSERT_TRUE(killed) << "step 2 never ran";
    // At once, while the skill still runs: the standby MES takes the journal over and
    // resumes the order; the operator follows it there.
    mes_ = std::move(standby);
    const RunResult result = waitForOrder(mes_->url(), 1);
    const RunResult lost = first.get();
    EXPECT_EQ(lost.exitCode, 1) << lost.output;
    EXPECT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(result.output.find("finished (after a restart of the MES)"), std::string::npos)
        << result.output;
    (void)observer.disconnect();

    expectTheProcessDone(cell);
    const auto run = lastRun();
    ASSERT_TRUE(run);
    EXPECT_EQ(run->state, RunState::Completed);
    const StepRecord* step2 = run->lastAttempt(2);
    ASSERT_NE(step2, nullptr);
    EXPECT_EQ(step2->attempt, 1) << "the running attempt was adopted, not started again";
    EXPECT_EQ(step2->state, StepState::Finished);
    EXPECT_EQ(step2->reason, "finished (after a restart of the MES)");
    for (int i = 1; i <= 5; ++i) EXPECT_EQ(runsOf(*run, i), 1) << "step " << i;
}

TEST_F(MesCell, StopsForWantOfAVacuumGripperAndCompletesOnceOneIsPluggedIn) {
    test::SimulatedCell cell(SKILLCELL_BINARY, test::paperObjects(), true, test::kRobotiq2f85,
                             /*vacuumPowered=*/false);
    ASSERT_TRUE(cell.ready());
    // Steps 1 to 3 run on skills detected long before step 4, whose vacuum gripper is not
    // coming: its wait need not be long to show that the MES stops for want of it.
    startMes("4000");
    ASSERT_FALSE(mes_->url().empty());

    RunResult result = runProcess(mes_->url());
    EXPECT_EQ(result.exitCode, 1) << result.output;
    EXPECT_NE(result.output.find("OUTCOME Failed"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("step 4 (PickAndPlaceSkillType)"), std::string::npos)
        << result.output;
    EXPECT_NE(result.output.find("GraspGripperSkillType with gripType \"vacuum\""),
              std::string::npos)
        << result.output;
    auto run = lastRun();
    ASSERT_TRUE(run);
    EXPECT_EQ(run->state, RunState::Stopped);
    EXPECT_NE(run->reason.find("GraspGripperSkillType"), std::string::npos) << run->reason;

    // Plug the vacuum gripper's adapter in; the same process, run again, resumes at step 4.
    test::DeviceProcess vacuum(SKILLCELL_BINARY,
                               withFastMdns({"schmalz", "--speed", "20", "--world",
                                             cell.world->url(), "--robot", cell.robotName}),
                               true);
    ASSERT_FALSE(vacuum.url().empty());
    result = runProcess(mes_->url());
    EXPECT_EQ(result.exitCode, 0) << result.output;
    run = lastRun();
    ASSERT_TRUE(run);
    EXPECT_EQ(run->state, RunState::Completed);
    EXPECT_EQ(runsOf(*run, 3), 1);
    EXPECT_EQ(runsOf(*run, 4), 1) << "no pick without a vacuum gripper: only the one that finished";
    expectTheProcessDone(cell);
}

TEST_F(MesCell, AHaltedStepRunsAgainOnlyAsItsProcessSaysAndEveryResetIsJournaled) {
    // A tool changer's DetachTool whose first two runs end Halted, as faulting hardware does.
    test::ComponentProcess flaky(
        SKILLCELL_BINARY,
        withFastMdns({"server", "--application-uri", "urn:test:flaky", "--noop-skill",
                      "DetachToolSkillType=DetachTool", "--noop-halts", "2"}),
        true);
    ASSERT_FALSE(flaky.url().empty());
    startMes();
    ASSERT_FALSE(mes_->url().empty());

    // No retries: the first Halted run stops the process, with the skill's reason.
    RunResult result = runNamedProcess(mes_->url(), std::string(kRetried) + "once");
    EXPECT_EQ(result.exitCode, 1) << result.output;
    auto once = lastRun(1);
    ASSERT_TRUE(once);
    EXPECT_EQ(once->state, RunState::Stopped);
    ASSERT_EQ(once->steps.size(), 1U);
    EXPECT_EQ(once->steps[0].state, StepState::Failed);
    EXPECT_NE(once->steps[0].reason.find("run 1 halts on purpose"), std::string::npos)
        << once->steps[0].reason;
    // No retry, no reset (its note may say that it waited for the KB to know the skill).
    EXPECT_EQ(once->steps[0].note.find("retry"), std::string::npos) << once->steps[0].note;
    EXPECT_EQ(once->steps[0].note.find("reset"), std::string::npos) << once->steps[0].note;

    // One retry: the skill, Halted since, is reset (and the journal says so), halts again,
    // is reset and run again, and finishes.
    result = runNamedProcess(mes_->url(), std::string(kRetried) + "retried");
    EXPECT_EQ(result.exitCode, 0) << result.output;
    auto retried = lastRun(2);
    ASSERT_TRUE(retried);
    EXPECT_EQ(retried->state, RunState::Completed);
    ASSERT_EQ(retried->steps.size(), 2U);
    const StepRecord& first = retried->steps[0];
    const StepRecord& second = retried->steps[1];
    EXPECT_EQ(first.attempt, 1);
    EXPECT_EQ(first.state, StepState::Failed);
    EXPECT_NE(first.reason.find("run 2 halts on purpose"), std::string::npos) << first.reason;
    EXPECT_EQ(
        first.note.rfind("the skill was Halted (an earlier fault left it so) and was reset", 0), 0U)
        << first.note;
    EXPECT_EQ(second.attempt, 2);
    EXPECT_EQ(second.state, StepState::Finished);
    EXPECT_EQ(second.componentUri, "urn:test:flaky");
    EXPECT_NE(second.note.find("retry 1 of 1 after: "), std::string::npos) << second.note;
    EXPECT_NE(second.note.find("run 2 halts on purpose"), std::string::npos) << second.note;
    EXPECT_NE(second.note.find("; the skill was reset"), std::string::npos) << second.note;
}

TEST_F(MesCell, AKilledMesResumesEachOfItsOrdersRunningNoStepTwice) {
    // Three components, each serving one order at a time: three orders run at once.
    std::vector<std::unique_ptr<test::ComponentProcess>> servers;
    for (int i = 1; i <= 3; ++i) {
        servers.push_back(std::make_unique<test::ComponentProcess>(
            SKILLCELL_BINARY,
            withFastMdns({"server", "--application-uri", "urn:test:noop" + std::to_string(i),
                          "--noop-skill", "DetachToolSkillType=DetachTool", "--noop-skill-ms",
                          "1500"}),
            true));
        ASSERT_FALSE(servers.back()->url().empty());
    }
    startMes();
    ASSERT_FALSE(mes_->url().empty());
    // The KB checks and loads its --process files after it starts: wait for this one.
    bool listed = false;
    for (int i = 0; i < 100 && !listed; ++i) {  // bounded: about 30 s
        const RunResult list =
            shell(std::string(SKILLCELL_BINARY) + " process list --kb " + kbUrl_ + " --insecure");
        listed = list.output.find(kThreeSteps) != std::string::npos;
        if (!listed) std::this_thread::sleep_for(200ms);  // a bounded poll of the KB
    }
    ASSERT_TRUE(listed) << "the KB never listed " << kThreeSteps;
    for (int i = 1; i <= 3; ++i) {
        const RunResult submitted = shell(std::string(SKILLCELL_BINARY) + " run " + kThreeSteps +
                                          " --no-wait --mes " + mes_->url() + " --insecure");
        ASSERT_EQ(submitted.exitCode, 0) << submitted.output;
        EXPECT_NE(submitted.output.find("ORDER " + std::to_string(i)), std::string::npos)
            << submitted.output;
    }
    // Kill the MES once every order has begun a step.
    bool killed = false;
    for (int i = 0; i < 600 && !killed; ++i) {  // bounded: 60 s
        int begun = 0;
        for (std::int64_t order = 1; order <= 3; ++order) {
            if (auto run = lastRun(order); run && !run->steps.empty()) ++begun;
        }
        if (begun == 3) {
            EXPECT_TRUE(mes_->kill(SIGKILL).has_value());
            killed = true;
        }
        std::this_thread::sleep_for(100ms);  // a bounded poll of the journal file
    }
    ASSERT_TRUE(killed) << "the three orders never ran at once";

    // The restarted MES resumes all three by itself.
    startMes();
    ASSERT_FALSE(mes_->url().empty());
    std::vector<std::future<RunResult>> waits;
    for (std::int64_t order = 1; order <= 3; ++order) {
        waits.push_back(std::async(std::launch::async, waitForOrder, mes_->url(), order));
    }
    for (auto& w : waits) {
        const RunResult r = w.get();
        EXPECT_EQ(r.exitCode, 0) << r.output;
    }
    std::set<std::string> components;
    for (std::int64_t order = 1; order <= 3; ++order) {
        const auto run = lastRun(order);
        ASSERT_TRUE(run);
        EXPECT_EQ(run->state, RunState::Completed) << "order " << order << ": " << run->reason;
        for (int i = 1; i <= 3; ++i) {
            EXPECT_EQ(runsOf(*run, i), 1) << "order " << order << " step " << i;
        }
        components.insert(run->steps.front().componentUri);
    }
    EXPECT_EQ(components.size(), 3U) << "the orders did not run at once, one per component";
}

TEST_F(MesCell, AWrongGripperInTheDockStopsTheProcessBeforeThePickNamingTheGripType) {
    test::SimulatedCell cell(SKILLCELL_BINARY, test::paperObjects(), true);
    ASSERT_TRUE(cell.ready());
    // Someone swapped the grippers' docks: the tool change of step 1 mounts the vacuum one.
    {
        auto link = devices::WorldLink::connect(cell.world->url(), {}, cell.robotName);
        ASSERT_TRUE(link.ok());
        for (const auto& [tool, dock] :
             {std::pair{"vacuum", "shelf"}, std::pair{"parallel", "dockV"},
              std::pair{"vacuum", "dockP"}}) {
            ASSERT_TRUE((*link)->moveTool(tool, dock).isGood()) << tool << " -> " << dock;
        }
    }
    // Every skill of the cell has been detected long before step 2 (step 1 used the changer,
    // whose tool change ends when the mounted gripper's adapter is detected): a grasp skill
    // of the wanted type will not come, and the step need not wait long to say so.
    startMes("4000");
    ASSERT_FALSE(mes_->url().empty());

    const RunResult result = runProcess(mes_->url());
    EXPECT_EQ(result.exitCode, 1) << result.output;
    const auto run = lastRun();
    ASSERT_TRUE(run);
    EXPECT_EQ(run->state, RunState::Stopped);
    // The reason names the step, what it requires and what the cell has instead.
    for (const std::string part :
         {"step 2 (PickAndPlaceSkillType)", "GraspGripperSkillType with gripType \"parallel\"",
          "urn:skillcell:device:schmalz-ecbpi has gripType \"vacuum\""}) {
        EXPECT_NE(run->reason.find(part), std::string::npos) << part << " in: " << run->reason;
        EXPECT_NE(result.output.find(part), std::string::npos) << part << " in: " << result.output;
    }
    EXPECT_EQ(runsOf(*run, 1), 1);
    EXPECT_EQ(run->lastAttempt(2), nullptr) << "the pick never started";
    auto link = devices::WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    expectAt(**link, "boxA", 0.45, 0.15, 0.025);  // where it was
}

TEST_F(MesCell, RefusesAProcessWithAMistakeOrANeedTheCellCannotMeetBeforeAnyMotion) {
    test::SimulatedCell cell(SKILLCELL_BINARY, test::paperObjects(), true);
    ASSERT_TRUE(cell.ready());
    startMes("4000");
    ASSERT_FALSE(mes_->url().empty());
    // A misspelt parameter in step 2: the process check, with the parameters the type has.
    RunResult result = runNamedProcess(mes_->url(), std::string(kRefused) + "misspelt");
    EXPECT_EQ(result.exitCode, 1) << result.output;
    for (const std::string part : {"1 problem in the process",
                                   "step m2, parameter PlacePositon: the ParameterSet of "
                                   "PickAndPlaceSkillType has no such parameter"}) {
        EXPECT_NE(result.output.find(part), std::string::npos) << part << " in: " << result.output;
    }
    // A gripper no component offers and no dock holds: the feasibility check.
    result = runNamedProcess(mes_->url(), std::string(kRefused) + "magnetic");
    EXPECT_EQ(result.exitCode, 1) << result.output;
    EXPECT_NE(result.output.find("the cell cannot run"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("step 2 (PickAndPlaceSkillType) requires an available "
                                 "GraspGripperSkillType with gripType \"magnetic\""),
              std::string::npos)
        << result.output;
    // Nothing moved, and neither order began a step.
    auto link = devices::WorldLink::connect(cell.world->url(), {}, cell.robotName);
    ASSERT_TRUE(link.ok());
    expectAt(**link, "boxA", 0.45, 0.15, 0.025);
    const auto tool = (*link)->mountedTool();
    ASSERT_TRUE(tool.ok());
    EXPECT_EQ(*tool, "");
    for (std::int64_t order = 1; order <= 2; ++order) {
        const auto refused = lastRun(order);
        ASSERT_TRUE(refused) << "order " << order;
        EXPECT_EQ(refused->state, RunState::Stopped);
        EXPECT_TRUE(refused->steps.empty()) << "refused order " << order << " began a step";
    }
}

TEST_F(MesCell, ProcessAddLoadsACheckedProcessAndABadOneChangesNothing) {
    const std::string skillcell = SKILLCELL_BINARY;
    const std::string kb = " --kb " + kb_->url() + " --insecure";
    const std::string list = skillcell + " process list --kb " + kbUrl_;
    // A misspelt parameter: its line, and nothing in the KB.
    const std::string bad =
        std::string(SKILLCELL_SOURCE_DIR) + "/tests/data/processes/unknown_parameter.ttl";
    RunResult r = shell(skillcell + " process add " + bad + kb);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("unknown_parameter.ttl:18: step s1, parameter PlacePositon"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("nothing was added"), std::string::npos) << r.output;
    r = shell(list);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("pickAndPlaceTwoBoxes (5 steps)"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("http://example.com/cell#p"), std::string::npos) << r.output;

    // A clean one: loaded, listed; loaded again, it replaces itself.
    const auto good = dir_ / "detach.ttl";
    {
        std::ofstream out(good);
        out << "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
               "@prefix ex: <http://example.com/cell#> .\n"
               "ex:dock a proc:ToolDock ; proc:pose [ a proc:Pose ; proc:x 0.3 ; proc:y -0.45 ; "
               "proc:z 0.35 ; proc:roll 3.14 ; proc:pitch 0.0 ; proc:yaw 0.0 ] .\n"
               "ex:p a proc:Process ; proc:firstStep ex:s1 ; proc:hasStep ex:s1 .\n"
               "ex:s1 a proc:Step ; proc:requiresSkillType "
               "<http://skillcell.dev/UA/ToolChangerSkills/DetachToolSkillType> ;\n"
               "  proc:hasParameter [ a proc:Parameter ; proc:parameterName \"ToolPosition\" ; "
               "proc:derivedFrom ex:dock ] .\n";
    }
    for (int time = 1; time <= 2; ++time) {
        r = shell(skillcell + " process add " + good + kb);
        EXPECT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("as graph <http://skillcell.dev/processes/detach>"),
                  std::string::npos)
            << r.output;
        r = shell(list);
        const auto first = r.output.find("http://example.com/cell#p (1 steps)");
        EXPECT_NE(first, std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("http://example.com/cell#p", first + 1), std::string::npos)
            << "listed twice after adding it " << time << " times:\n"
            << r.output;
    }
}

}  // namespace
}  // namespace skillcell::mes::mes_cell_test
