#include "cell_process.hpp"

namespace skillcell::apps {

kb::Expected<CellProcess> CellProcess::start(
    std::string name, const std::vector<std::string>& argv,
    const std::vector<std::pair<std::string, std::string>>& env, const std::filesystem::path& log,
    std::chrono::milliseconds timeout, const std::vector<int>& namespaces) {
    process::ProcessOptions options = process::reportingChild(log);
    options.envAdd = env;
    options.namespaces = namespaces;
    auto child = process::ChildProcess::start(argv, options);
    if (!child) return kb::Error{name + ": " + child.error()};
    CellProcess p(std::move(name), std::move(*child));
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        auto line = left.count() > 0 ? p.process_.readLine(left) : std::nullopt;
        if (!line) {
            const bool running = p.process_.running();
            return kb::Error{p.name_ + " did not report READY " +
                             (running ? "within " + std::to_string(timeout.count()) + " ms"
                                      : std::string("(it ended)")) +
                             "; see its log " + log.string()};
        }
        const auto space = line->find(' ');
        if (space == std::string::npos) continue;
        const std::string key = line->substr(0, space);
        std::string value = line->substr(space + 1);
        if (key == "READY") {
            p.url_ = std::move(value);
            return p;
        }
        p.reported_[key] = std::move(value);
    }
}

std::string CellProcess::reported(const std::string& key) const {
    const auto it = reported_.find(key);
    return it == reported_.end() ? std::string() : it->second;
}

kb::Expected<process::ExitStatus> CellProcess::stop(std::chrono::milliseconds grace) {
    return process_.terminate(grace);
}

}  // namespace skillcell::apps
