#include "process/cpu_time.hpp"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <string_view>

namespace skillcell::process {

std::chrono::nanoseconds cpuTime(pid_t pid) {
    long long sum = 0;
    std::error_code ec;
    for (const auto& task :
         std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
        std::ifstream in(task.path() / "schedstat");
        long long ns = 0;
        if (in >> ns) sum += ns;
    }
    return std::chrono::nanoseconds(sum);
}

namespace {

/// The parent of `pid` from /proc/PID/stat, or 0. The command name (field 2) is in
/// parentheses and may hold spaces and parentheses: the fields after it start after the last ')'.
pid_t parentOf(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    std::getline(in, stat);
    const auto close = stat.rfind(')');
    if (close == std::string::npos || close + 4 >= stat.size()) return 0;
    // ") S PPID ...": the state, then the parent.
    const std::string_view rest = std::string_view(stat).substr(close + 4);
    pid_t parent = 0;
    std::from_chars(rest.data(), rest.data() + rest.size(), parent);
    return parent;
}

}  // namespace

std::vector<pid_t> descendantsOf(pid_t ancestor) {
    std::map<pid_t, pid_t> parents;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
        const std::string name = entry.path().filename().string();
        pid_t pid = 0;
        const auto [end, err] = std::from_chars(name.data(), name.data() + name.size(), pid);
        if (err != std::errc() || end != name.data() + name.size()) continue;
        if (const pid_t parent = parentOf(pid); parent != 0) parents[pid] = parent;
    }
    std::vector<pid_t> out;
    for (const auto& [pid, parent] : parents) {
        // Up the chain, bounded by the number of processes (a chain never loops, but /proc is
        // read while it changes).
        pid_t p = parent;
        for (std::size_t hops = 0; p > 1 && p != ancestor && hops < parents.size(); ++hops) {
            const auto it = parents.find(p);
            p = it == parents.end() ? 0 : it->second;
        }
        if (p == ancestor) out.push_back(pid);
    }
    return out;
}

}  // namespace skillcell::process
