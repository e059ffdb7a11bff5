#include "process/cpu_time.hpp"

#include <unistd.h>

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

/// The fields of /proc/PID/stat after the command name (field 2, in parentheses, which may
/// hold spaces and parentheses: they start after the last ')'); empty when it cannot be read.
std::vector<std::string_view> statFields(const std::string& stat) {
    std::vector<std::string_view> fields;
    const auto close = stat.rfind(')');
    if (close == std::string::npos) return fields;
    std::string_view rest = std::string_view(stat).substr(close + 1);
    while (!rest.empty()) {
        const auto start = rest.find_first_not_of(' ');
        if (start == std::string_view::npos) break;
        rest.remove_prefix(start);
        const auto end = rest.find(' ');
        fields.push_back(rest.substr(0, end));
        if (end == std::string_view::npos) break;
        rest.remove_prefix(end);
    }
    return fields;
}

/// The whole of /proc/PID/stat; empty when the process is gone.
std::string statOf(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    std::getline(in, stat);
    return stat;
}

/// The parent of `pid` (field 4), or 0.
pid_t parentOf(pid_t pid) {
    const std::string stat = statOf(pid);
    const auto fields = statFields(stat);
    pid_t parent = 0;
    if (fields.size() > 1)
        std::from_chars(fields[1].data(), fields[1].data() + fields[1].size(), parent);
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

std::chrono::nanoseconds cpuTimeWithReapedChildren(pid_t pid) {
    const std::string stat = statOf(pid);
    // Field 3 (the state) is the first after the name: cutime and cstime are 16 and 17.
    const auto fields = statFields(stat);
    if (fields.size() < 15) return std::chrono::nanoseconds(0);
    long long ticks = 0;
    for (const std::size_t i : {13U, 14U}) {
        long long v = 0;
        std::from_chars(fields[i].data(), fields[i].data() + fields[i].size(), v);
        ticks += v;
    }
    const long perSecond = ::sysconf(_SC_CLK_TCK);
    const auto children =
        std::chrono::nanoseconds(perSecond > 0 ? ticks * 1'000'000'000 / perSecond : 0);
    return cpuTime(pid) + children;
}

}  // namespace skillcell::process
