// ChildProcess (src/process), which starts the children of our components: exit codes and signals,
// output to pipes and files, working directory and environment, bounded waits, and the
// death signal that ties a child's life to ours.
#include "process/child_process.hpp"

#include <gtest/gtest.h>

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.hpp"

namespace skillcell::process::child_process_test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

long long msSince(Clock::time_point t0) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
}

TEST(ChildProcess, ReportsExitCodesAndCapturesOutput) {
    auto run = runToCompletion({"sh", "-c", "echo out; echo err >&2; exit 3"}, 10s);
    ASSERT_TRUE(run) << run.error();
    EXPECT_EQ(run->exitCode, 3);
    EXPECT_EQ(run->out, "out\n");
    EXPECT_EQ(run->err, "err\n");

    auto child = ChildProcess::start({"true"});
    ASSERT_TRUE(child) << child.error();
    auto status = child->wait(10s);
    ASSERT_TRUE(status) << status.error();
    EXPECT_TRUE(status->success());
    EXPECT_FALSE(child->running());
}

/// A line of /proc/<pid>/status ("SigBlk", "SigCgt", ...), its value.
std::string statusField(const std::string& status, const std::string& field) {
    const auto at = status.find(field + ":\t");
    if (at == std::string::npos) return "?";
    const auto begin = at + field.size() + 2;
    return status.substr(begin, status.find('\n', begin) - begin);
}

void countSignal(int /*signal*/) {}

TEST(ChildProcess, StartsWithNoSignalBlockedOrCaughtWhateverItsParentDoes) {
    // The child runs in our memory until it execs: none of our handlers may run there, and
    // what we block or catch must not reach the program it becomes.
    struct sigaction handler {};
    handler.sa_handler = countSignal;
    struct sigaction before {};
    ASSERT_EQ(::sigaction(SIGUSR1, &handler, &before), 0);
    sigset_t blocked;
    sigemptyset(&blocked);
    sigaddset(&blocked, SIGTERM);
    sigset_t previous;
    ASSERT_EQ(::pthread_sigmask(SIG_BLOCK, &blocked, &previous), 0);

    auto run = runToCompletion({"cat", "/proc/self/status"}, 10s);

    sigset_t after;
    ::pthread_sigmask(SIG_SETMASK, &previous, &after);
    struct sigaction still {};
    ::sigaction(SIGUSR1, &before, &still);
    ASSERT_TRUE(run) << run.error();
    EXPECT_EQ(statusField(run->out, "SigBlk"), "0000000000000000");
    EXPECT_EQ(statusField(run->out, "SigCgt"), "0000000000000000");
    EXPECT_EQ(statusField(run->out, "SigIgn"), "0000000000000000");
    // Ours are as they were.
    EXPECT_EQ(sigismember(&after, SIGTERM), 1);
    EXPECT_EQ(sigismember(&after, SIGUSR1), 0);
    EXPECT_EQ(still.sa_handler, &countSignal);
}

TEST(ChildProcess, ReadsStdoutLineByLineWhileTheChildRuns) {
    ProcessOptions options;
    options.stdoutTo = OutputSink::capture();
    auto child = ChildProcess::start(
        {"sh", "-c", "echo 'READY a'; printf 'b\\r\\npart'; exec sleep 60"}, options);
    ASSERT_TRUE(child) << child.error();
    EXPECT_EQ(child->readLine(10s), "READY a");
    EXPECT_EQ(child->readLine(10s), "b") << "a CR before the LF is not part of the line";
    const auto t0 = Clock::now();
    EXPECT_EQ(child->readLine(200ms), std::nullopt) << "no whole line: the wait is bounded";
    EXPECT_LT(msSince(t0), 3000);
    ASSERT_TRUE(child->terminate(5s));
    EXPECT_EQ(child->readLine(10s), std::nullopt) << "stdout closed, half a line left";
}

TEST(ChildProcess, PassesWorkingDirectoryAndEnvironment) {
    test::TempDir dir("skillcell-process-test");
    ProcessOptions options;
    options.workingDir = dir.path();
    options.envAdd = {{"SKILLCELL_TEST_VALUE", "forty two"}};
    auto run = runToCompletion({"sh", "-c", "pwd; echo \"$SKILLCELL_TEST_VALUE\""}, 10s, options);
    ASSERT_TRUE(run) << run.error();
    EXPECT_EQ(run->out, std::filesystem::canonical(dir.path()).string() + "\nforty two\n");
}

TEST(ChildProcess, RunsAtTheNicenessAskedFor) {
    ProcessOptions options;
    options.niceness = 5;
    errno = 0;
    const int ours = ::getpriority(PRIO_PROCESS, 0);
    ASSERT_EQ(errno, 0);
    auto run = runToCompletion({"nice"}, 10s, options);  // prints its own niceness
    ASSERT_TRUE(run) << run.error();
    EXPECT_EQ(run->out, std::to_string(std::min(ours + 5, 19)) + "\n");
    auto plain = runToCompletion({"nice"}, 10s);
    ASSERT_TRUE(plain) << plain.error();
    EXPECT_EQ(plain->out, std::to_string(ours) + "\n");
}

TEST(ChildProcess, WritesOutputToAFile) {
    test::TempDir dir("skillcell-process-test");
    ProcessOptions options;
    options.stdoutTo = OutputSink::toFile(dir.path() / "out.log");
    options.stderrTo = OutputSink::discard();
    auto child = ChildProcess::start({"sh", "-c", "echo to-file; echo dropped >&2"}, options);
    ASSERT_TRUE(child) << child.error();
    ASSERT_TRUE(child->wait(10s));
    std::ifstream in(dir.path() / "out.log");
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "to-file");
}

TEST(ChildProcess, ExecFailureNamesTheProgramAndReason) {
    auto missing = ChildProcess::start({"/nonexistent/skillcell-no-such-tool", "x"});
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().find("skillcell-no-such-tool"), std::string::npos) << missing.error();
    EXPECT_NE(missing.error().find("No such file"), std::string::npos) << missing.error();

    ProcessOptions options;
    options.workingDir = "/nonexistent-dir-for-skillcell";
    auto badDir = ChildProcess::start({"true"}, options);
    ASSERT_FALSE(badDir);
    EXPECT_NE(badDir.error().find("/nonexistent-dir-for-skillcell"), std::string::npos)
        << badDir.error();

    auto run = runToCompletion({"skillcell-no-such-tool-in-path"}, 5s);
    ASSERT_FALSE(run);
    EXPECT_NE(run.error().find("skillcell-no-such-tool-in-path"), std::string::npos) << run.error();
}

TEST(ChildProcess, TerminateKillsAProcessThatIgnoresSigterm) {
    ProcessOptions options;
    options.stdoutTo = OutputSink::capture();
    // An ignored signal stays ignored across exec: `sleep` ignores SIGTERM too.
    auto child =
        ChildProcess::start({"sh", "-c", "trap '' TERM; echo ready; exec sleep 60"}, options);
    ASSERT_TRUE(child) << child.error();
    // "ready" means the trap is set; each wait is bounded, and so is the loop.
    const auto readyBy = Clock::now() + 10s;
    while (child->capturedStdout().empty() && Clock::now() < readyBy) (void)child->wait(20ms);
    ASSERT_EQ(child->capturedStdout(), "ready\n");

    const auto t0 = Clock::now();
    auto status = child->terminate(300ms);
    const auto took = msSince(t0);
    ASSERT_TRUE(status) << status.error();
    EXPECT_EQ(status->signal, SIGKILL) << status->describe();
    EXPECT_GE(took, 300);
    EXPECT_LT(took, 2000);
}

TEST(ChildProcess, TerminateEndsAWellBehavedProcessWithSigterm) {
    auto child = ChildProcess::start({"sleep", "60"});
    ASSERT_TRUE(child) << child.error();
    auto status = child->terminate(5s);
    ASSERT_TRUE(status) << status.error();
    EXPECT_EQ(status->signal, SIGTERM);
}

TEST(ChildProcess, RunToCompletionKillsOnTimeout) {
    const auto t0 = Clock::now();
    auto run = runToCompletion({"sleep", "60"}, 200ms);
    ASSERT_FALSE(run);
    EXPECT_NE(run.error().find("sleep"), std::string::npos) << run.error();
    EXPECT_NE(run.error().find("did not finish within 200 ms"), std::string::npos) << run.error();
    EXPECT_LT(msSince(t0), 3000);
}

TEST(ChildProcess, DestructorAndMoveLeaveNoProcessBehind) {
    pid_t pid = 0;
    {
        auto child = ChildProcess::start({"sleep", "60"});
        ASSERT_TRUE(child) << child.error();
        ChildProcess moved = std::move(*child);
        pid = moved.pid();
        EXPECT_TRUE(moved.running());
    }
    // Reaped, so the pid is gone (not a zombie).
    EXPECT_EQ(::kill(pid, 0), -1);
    EXPECT_EQ(errno, ESRCH);

    auto child = ChildProcess::start({"sleep", "60"});
    ASSERT_TRUE(child);
    auto killed = child->kill();
    ASSERT_TRUE(killed) << killed.error();
    EXPECT_EQ(killed->signal, SIGKILL);
}

// The kernel signals a child when the thread that started it ends: SIGKILL by default, the
// signal of ProcessOptions::deathSignal when given (SIGTERM, for a tool's adapter that must
// say goodbye). The child's object outlives the thread, so only the kernel can end it.
Expected<ExitStatus> endOfAChildWhoseThreadEnded(const ProcessOptions& options) {
    std::optional<ChildProcess> child;
    std::string why;
    std::thread starter([&] {
        auto started = ChildProcess::start({"sleep", "60"}, options);
        if (started) {
            child.emplace(std::move(*started));
        } else {
            why = started.error();
        }
    });
    starter.join();
    if (!child) return Error{why};
    return child->wait(10s);
}

TEST(ChildProcess, IsKilledWhenTheThreadThatStartedItEnds) {
    const auto ended = endOfAChildWhoseThreadEnded({});
    ASSERT_TRUE(ended) << ended.error();
    EXPECT_EQ(ended->signal, SIGKILL) << ended->describe();
}

TEST(ChildProcess, GetsTheDeathSignalItWasGiven) {
    ProcessOptions options;
    options.deathSignal = SIGTERM;
    const auto ended = endOfAChildWhoseThreadEnded(options);
    ASSERT_TRUE(ended) << ended.error();
    EXPECT_EQ(ended->signal, SIGTERM) << ended->describe();
}

}  // namespace
}  // namespace skillcell::process::child_process_test
