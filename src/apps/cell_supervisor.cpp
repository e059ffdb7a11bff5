#include "cell_supervisor.hpp"

#include <poll.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "client_security_options.hpp"

namespace skillcell::apps {

using namespace std::chrono_literals;
using Json = nlohmann::ordered_json;

namespace {

constexpr int kFailuresGivenUp = 5;  // within kFailureWindow
constexpr auto kFailureWindow = std::chrono::minutes(1);
constexpr auto kFirstRestartDelay = 1s;  // then doubling
constexpr auto kLongestRestartDelay = 30s;
constexpr std::size_t kLogLinesReported = 12;

std::string indented(const std::string& text) {
    std::string out;
    std::size_t start = 0;
    while (start < text.size()) {
        const auto end = text.find('\n', start);
        out += "    | " + text.substr(start, end - start) + "\n";
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return out;
}

}  // namespace

CellSupervisor::CellSupervisor(CellRuntime& runtime) : runtime_(runtime) {
    for (const auto& name : runtime_.components()) {
        Component c;
        c.name = name;
        c.applicationUri = runtime_.applicationUri(name);
        c.policy = runtime_.cell().restartPolicy(name);
        components_.push_back(std::move(c));
    }
}

CellSupervisor::~CellSupervisor() {
    stopAll();
}

const char* CellSupervisor::toString(State state) {
    switch (state) {
        case State::Up:
            return "up";
        case State::Restarting:
            return "restarting";
        case State::GivenUp:
            return "given up";
        case State::Stopped:
            return "stopped";
        case State::Down:
            break;
    }
    return "down";
}

bool CellSupervisor::startComponent(Component& c) {
    auto launch = runtime_.launch(c.name);
    if (!launch) {
        std::cerr << "cell: " << launch.error() << "\n";
        return false;
    }
    auto p = runtime_.start(*launch);
    if (!p) {
        std::cerr << "cell: " << p.error() << "\n";
        const std::string tail = lastLines(runtime_.log(c.name), kLogLinesReported);
        if (!tail.empty()) std::cerr << indented(tail);
        return false;
    }
    c.endpoint = p->url();
    c.process.emplace(std::move(*p));
    c.state = State::Up;
    return true;
}

bool CellSupervisor::listen() {
    auto control = ControlSocket::listen(controlSocketPath(runtime_.dir()));
    if (!control) {
        std::cerr << "cell: " << control.error() << "\n";
        return false;
    }
    control_.emplace(std::move(*control));
    return true;
}

bool CellSupervisor::start(const Interruption& interruption) {
    if (!listen()) return false;
    // Our own detector, a client of the cell like any component: `cell status` shows the
    // skills as the cell's components see them.
    std::string error;
    const ClientUserOptions user = runtime_.componentUser();
    auto security = componentClientSecurity(runtime_.identity(), user, !runtime_.secure(), &error);
    if (!security) {
        std::cerr << "cell: " << error << "\n";
        return false;
    }
    skills::SkillDetectorConfig detector;
    detector.applicationUri = runtime_.selfUri();
    detector.security = *security;
    ua::mdns::MdnsConfig mdns;
    mdns.queryPeriod = std::chrono::seconds(runtime_.cell().network.mdnsQueryPeriodSeconds);
    mdns.interfaces = runtime_.cell().network.interfaces;
    detector_ = SkillDetectionClock::start(detector, mdns, &error);
    if (!detector_) {
        std::cerr << "cell: mDNS: " << error << "\n";
        return false;
    }
    detection_ = detector_.get();
    // On a terminal, the line of the component that is starting says so (the KB's first
    // start takes minutes on a slow machine); in a file, only the result.
    const bool terminal = ::isatty(STDOUT_FILENO) == 1;
    for (auto& c : components_) {
        if (interruption.requested()) return false;
        if (terminal) {
            std::printf("  %-14s starting...", c.name.c_str());
            std::fflush(stdout);
        }
        if (!startComponent(c)) {
            if (terminal) std::printf("\n");
            return false;
        }
        std::printf("%s  %-14s %s", terminal ? "\r\033[K" : "", c.name.c_str(), c.endpoint.c_str());
        if (c.name == "kb") std::printf("  SPARQL %s", runtime_.sparqlUrl().c_str());
        if (c.name == "dashboard") std::printf("  PAGE %s", runtime_.dashboardUrl().c_str());
        if (const auto host = runtime_.cell().hostOf(c.name); !host.empty()) {
            std::printf("  on host %s (link %s)", host.c_str(), CellHosts::linkName(host).c_str());
        }
        std::printf("\n");
        std::fflush(stdout);
    }
    return true;
}

void CellSupervisor::ended(Component& c) {
    auto how = c.process->ended();
    c.lastEnd = how ? how->describe() : how.error();
    c.process.reset();
    const bool failed = !how || !how->success();
    std::fprintf(stderr, "cell: %s ended (%s); the last lines of %s:\n%s", c.name.c_str(),
                 c.lastEnd.c_str(), runtime_.log(c.name).string().c_str(),
                 indented(lastLines(runtime_.log(c.name), kLogLinesReported)).c_str());
    const bool restart = c.policy == cell::RestartPolicy::Always ||
                         (c.policy == cell::RestartPolicy::OnFailure && failed);
    if (!restart) {
        c.state = State::Down;
        std::fprintf(stderr, "cell: %s stays down (restart = \"%s\")\n", c.name.c_str(),
                     std::string(cell::toString(c.policy)).c_str());
        return;
    }
    const auto now = Clock::now();
    std::erase_if(c.failures, [&](Clock::time_point t) { return now - t > kFailureWindow; });
    c.failures.push_back(now);
    if (static_cast<int>(c.failures.size()) >= kFailuresGivenUp) {
        c.state = State::GivenUp;
        givenUp_ = true;
        std::fprintf(stderr, "cell: %s ended %d times within a minute; given up\n", c.name.c_str(),
                     kFailuresGivenUp);
        return;
    }
    auto delay = std::chrono::duration_cast<std::chrono::milliseconds>(kFirstRestartDelay) *
                 (1 << (c.failures.size() - 1));
    delay = std::min<std::chrono::milliseconds>(delay, kLongestRestartDelay);
    c.state = State::Restarting;
    c.restartAt = now + delay;
    std::fprintf(stderr, "cell: restarting %s in %lld ms (restart = \"%s\")\n", c.name.c_str(),
                 static_cast<long long>(delay.count()),
                 std::string(cell::toString(c.policy)).c_str());
}

void CellSupervisor::restartDue(Component& c) {
    ++c.restarts;
    if (startComponent(c)) {
        std::fprintf(stderr, "cell: %s is up again at %s (restart %d)\n", c.name.c_str(),
                     c.endpoint.c_str(), c.restarts);
        return;
    }
    // Did not come up: counts as a failure like an end.
    c.state = State::Restarting;
    const auto now = Clock::now();
    c.failures.push_back(now);
    if (static_cast<int>(c.failures.size()) >= kFailuresGivenUp) {
        c.state = State::GivenUp;
        givenUp_ = true;
        std::fprintf(stderr, "cell: %s did not come up again; given up\n", c.name.c_str());
        return;
    }
    c.restartAt = now + kLongestRestartDelay;
}

std::string CellSupervisor::statusJson() const {
    Json j;
    j["cell"] = runtime_.cell().name;
    j["file"] = runtime_.cell().path.string();
    j["workDirectory"] = runtime_.dir().string();
    j["supervisor"] = ::getpid();
    j["secure"] = runtime_.secure();
    j["sparql"] = runtime_.sparqlUrl();
    const auto instances =
        detection_ != nullptr ? detection_->instances() : std::vector<skills::SkillInstance>{};
    std::map<std::string, std::vector<const skills::SkillInstance*>> byComponent;
    for (const auto& i : instances) byComponent[i.componentUri].push_back(&i);
    const auto skillsOf = [&](const std::string& uri) {
        Json skills = Json::array();
        const auto it = byComponent.find(uri);
        if (it == byComponent.end()) return skills;
        std::vector<std::pair<std::string, std::string>> rows;
        for (const auto* i : it->second)
            rows.emplace_back(i->browsePathString(), i->type().browseName);
        std::sort(rows.begin(), rows.end());
        for (const auto& [path, type] : rows) skills.push_back({{"path", path}, {"type", type}});
        return skills;
    };
    Json list = Json::array();
    std::set<std::string> ours;
    for (const auto& c : components_) {
        ours.insert(c.applicationUri);
        Json e;
        e["name"] = c.name;
        e["state"] = toString(c.state);
        e["pid"] = c.process ? c.process->pid() : 0;
        e["applicationUri"] = c.applicationUri;
        e["endpoint"] = c.endpoint;
        if (const auto host = runtime_.cell().hostOf(c.name); !host.empty()) {
            e["host"] = host;
            e["link"] = CellHosts::linkName(host);
        }
        e["restart"] = std::string(cell::toString(c.policy));
        e["restarts"] = c.restarts;
        e["lastEnd"] = c.lastEnd;
        e["log"] = runtime_.log(c.name).string();
        e["skills"] = skillsOf(c.applicationUri);
        list.push_back(std::move(e));
    }
    // Components the cell's own ones start: the adapters the tool changer powers.
    for (const auto& [uri, skills] : byComponent) {
        if (ours.count(uri) != 0) continue;
        Json e;
        e["name"] = uri;
        e["state"] = "detected";
        e["applicationUri"] = uri;
        e["endpoint"] = skills.front()->endpointUrl;
        e["skills"] = skillsOf(uri);
        list.push_back(std::move(e));
    }
    j["components"] = std::move(list);
    return j.dump();
}

void CellSupervisor::answer(ControlRequest& request, bool* down) {
    if (request.line == "ping") {
        ControlSocket::reply(request, Json{{"pong", true}}.dump());
    } else if (request.line == "status") {
        ControlSocket::reply(request, statusJson());
    } else if (request.line == "down") {
        *down = true;  // answered once the cell has stopped
    } else {
        ControlSocket::reply(request,
                             Json{{"error", "unknown request '" + request.line + "'"}}.dump());
    }
}

int CellSupervisor::supervise(const Interruption& interruption) {
    const process::UniqueFd signals(::signalfd(-1, &interruption.signals(), SFD_CLOEXEC));
    std::optional<ControlRequest> downRequest;
    while (!interruption.requested() && !downRequest) {
        std::vector<pollfd> fds;
        if (signals.valid()) fds.push_back({signals.get(), POLLIN, 0});
        if (control_) fds.push_back({control_->fd(), POLLIN, 0});
        int timeoutMs = -1;
        const auto now = Clock::now();
        for (auto& c : components_) {
            if (c.state == State::Up && c.process) {
                if (c.process->exitFd() >= 0) {
                    fds.push_back({c.process->exitFd(), POLLIN, 0});
                } else {
                    timeoutMs = timeoutMs < 0 ? 500 : std::min(timeoutMs, 500);  // no pidfd
                }
            } else if (c.state == State::Restarting) {
                const auto wait = std::max<long long>(
                    0, std::chrono::ceil<std::chrono::milliseconds>(c.restartAt - now).count());
                timeoutMs = timeoutMs < 0 ? static_cast<int>(wait)
                                          : std::min(timeoutMs, static_cast<int>(wait));
            }
        }
        const int ready = ::poll(fds.data(), fds.size(), timeoutMs);
        if (ready < 0 && errno != EINTR) {
            std::perror("cell: poll");
            break;
        }
        if (interruption.requested()) break;
        check();
        if (control_) {
            while (auto request = control_->accept()) {
                bool down = false;
                answer(*request, &down);
                if (down) {
                    downRequest.emplace(std::move(*request));
                    break;
                }
            }
        }
    }
    std::printf("\ncell: stopping %s (%s)\n", runtime_.cell().name.c_str(),
                downRequest ? "cell down" : "interrupted");
    std::fflush(stdout);
    stopAll();
    if (downRequest) ControlSocket::reply(*downRequest, Json{{"stopped", true}}.dump());
    return givenUp_ ? 1 : 0;
}

bool CellSupervisor::adopt(CellProcess process) {
    for (auto& c : components_) {
        if (c.name != process.name()) continue;
        if (c.process) (void)c.process->stop(std::chrono::seconds(10));
        c.endpoint = process.url();
        c.process.emplace(std::move(process));
        c.state = State::Up;
        return true;
    }
    return false;
}

void CellSupervisor::check() {
    for (auto& c : components_) {
        if (c.state == State::Up && c.process && !c.process->running()) ended(c);
    }
    for (auto& c : components_) {
        if (c.state == State::Restarting && Clock::now() >= c.restartAt) restartDue(c);
    }
}

void CellSupervisor::stopAll() {
    // The tool changers power their tools off when they stop: they go first; then the
    // others, the last started first.
    std::vector<Component*> order;
    for (auto it = components_.rbegin(); it != components_.rend(); ++it) order.push_back(&*it);
    std::stable_partition(order.begin(), order.end(), [&](const Component* c) {
        return runtime_.cell().toolChanger(c->name) != nullptr;
    });
    for (Component* c : order) {
        if (!c->process) continue;
        auto s = c->process->stop(10s);
        if (!s) {
            std::cerr << "cell: " << s.error() << "\n";
        } else if (!s->success()) {
            std::cerr << "cell: " << c->name << " stopped: " << s->describe() << "\n";
        }
        c->process.reset();
        c->state = State::Stopped;
    }
}

}  // namespace skillcell::apps
