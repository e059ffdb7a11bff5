#pragma once
// What processes cost, from the kernel's own account: for benchmarks that report a
// component's CPU, and for the demo, which starts each measured component in a settled cell.
#include <sys/types.h>

#include <chrono>
#include <vector>

namespace skillcell::process {

/// The CPU time of a process, all its threads, from the scheduler's account
/// (/proc/PID/task/TID/schedstat, in ns); zero when it cannot be read (the process is gone).
/// Not /proc/PID/stat: its ticks charge a whole 10 ms to whoever runs when a tick falls, and
/// over a second of idle that is most of what there is to measure.
[[nodiscard]] std::chrono::nanoseconds cpuTime(pid_t pid);

/// cpuTime() and what the children the process has reaped used (cutime + cstime of
/// /proc/PID/stat, to the clock tick): a process that runs short-lived children (the knowledge
/// base its reasoner) shows their work when it reaps them, which cpuTime() of the parent and
/// of the children, gone by then, both miss.
[[nodiscard]] std::chrono::nanoseconds cpuTimeWithReapedChildren(pid_t pid);

/// The processes whose parent chain leads to `ancestor`, not `ancestor` itself.
[[nodiscard]] std::vector<pid_t> descendantsOf(pid_t ancestor);

}  // namespace skillcell::process
