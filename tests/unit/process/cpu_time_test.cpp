// process/cpu_time: a process's CPU time from the scheduler's account, and the processes
// under one of ours (the demo measures its cell's idleness with them).
#include "process/cpu_time.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <chrono>
#include <string>

#include "process/child_process.hpp"

namespace skillcell::process::cpu_time_test {
namespace {

using namespace std::chrono_literals;

TEST(CpuTime, GrowsWithTheWorkOfThisProcessAndIsZeroForNone) {
    const auto before = cpuTime(::getpid());
    // 20 ms of work on this thread, by the thread's own clock.
    const auto spin = [] {
        timespec t{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return std::chrono::seconds(t.tv_sec) + std::chrono::nanoseconds(t.tv_nsec);
    };
    const auto start = spin();
    volatile unsigned sink = 0;
    while (spin() - start < 20ms) sink = sink + 1;
    const auto after = cpuTime(::getpid());
    EXPECT_GE(after - before, 15ms);
    EXPECT_LT(after - before, 5s);
    // No such process (pid_max is at most 2^22).
    EXPECT_EQ(cpuTime(1 << 23).count(), 0);
}

TEST(CpuTime, WithReapedChildrenCountsWhatAChildUsedOnceItIsReaped) {
    const auto before = cpuTimeWithReapedChildren(::getpid());
    EXPECT_GE(before, cpuTime(::getpid()) - 1ms);  // read just before: at least as much
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // 60 ms of work by the child's own clock, then out without running our exit code.
        timespec t{};
        const auto used = [&t] {
            clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
            return std::chrono::seconds(t.tv_sec) + std::chrono::nanoseconds(t.tv_nsec);
        };
        volatile unsigned sink = 0;
        while (used() < 60ms) sink = sink + 1;
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    // The child's time is the parent's once reaped (to the clock tick: 10 ms).
    const auto after = cpuTimeWithReapedChildren(::getpid());
    EXPECT_GE(after - before, 40ms);
    EXPECT_LT(after - before, 5s);
    EXPECT_EQ(cpuTimeWithReapedChildren(1 << 23).count(), 0);
}

TEST(CpuTime, DescendantsAreChildrenAndTheirChildren) {
    // A shell that starts a child of its own and prints its pid, then waits.
    auto shell = ChildProcess::start({"sh", "-c", "sleep 30 & echo $!; wait"}, reportingChild());
    ASSERT_TRUE(shell) << shell.error();
    const auto line = shell->readLine(10s);
    ASSERT_TRUE(line.has_value());
    const pid_t grandchild = std::stoi(*line);
    struct Reaper {  // the grandchild is not ours to wait for: end it whatever happens
        pid_t pid;
        ~Reaper() { ::kill(pid, SIGKILL); }
    } reaper{grandchild};
    const auto all = descendantsOf(::getpid());
    EXPECT_NE(std::find(all.begin(), all.end(), shell->pid()), all.end());
    EXPECT_NE(std::find(all.begin(), all.end(), grandchild), all.end());
    EXPECT_EQ(std::find(all.begin(), all.end(), ::getpid()), all.end());
    // The grandchild is the shell's, not ours directly: only its descendants hold it.
    const auto underShell = descendantsOf(shell->pid());
    EXPECT_EQ(underShell, std::vector<pid_t>{grandchild});
    (void)shell->terminate(5s);
}

}  // namespace
}  // namespace skillcell::process::cpu_time_test
