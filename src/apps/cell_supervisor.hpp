#pragma once
// CellSupervisor: `skillcell cell up`. It starts every component of a cell in order
// (CellRuntime says how), then watches them: a component that ends without being asked to is
// reported with the last lines of its log and started again as its restart policy says,
// backing off (1 s, doubling to 30 s); one that fails 5 times within a minute is given up.
// It answers `cell status` and `cell down` on the control socket, and stops the whole cell
// on Ctrl-C (SIGINT/SIGTERM) or `cell down`: the tool changer first (it powers its tools
// off), then the others, the last started first, each with SIGTERM so that it says goodbye
// on mDNS. It waits for one thing at a time with poll(): a component's end (its pidfd), a
// signal (signalfd), a control request, or the next restart that is due.
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cell_control.hpp"
#include "cell_process.hpp"
#include "cell_runtime.hpp"
#include "interruption.hpp"
#include "skill_detection_clock.hpp"

namespace skillcell::apps {

class CellSupervisor {
public:
    using Clock = std::chrono::steady_clock;

    explicit CellSupervisor(CellRuntime& runtime);
    ~CellSupervisor();
    CellSupervisor(const CellSupervisor&) = delete;
    CellSupervisor& operator=(const CellSupervisor&) = delete;

    /// Listens on the control socket (`cell status`, `cell down`); false after saying why.
    [[nodiscard]] bool listen();
    /// Listens on the control socket and starts the skill detector and every component in
    /// order. False, after saying why on stderr (with the log of the one that did not come
    /// up), when one did not; the others are stopped then.
    [[nodiscard]] bool start(const Interruption& interruption);
    /// Supervises until SIGINT/SIGTERM or `cell down`, then stops the cell. Returns the
    /// exit code: 0 when asked to stop, 1 when a component had to be given up.
    int supervise(const Interruption& interruption);
    /// Puts a component of the cell that was started elsewhere under supervision (the
    /// demo starts some itself, to time their detection). False for one the cell lacks.
    bool adopt(CellProcess process);
    /// The detector whose skills `cell status` shows, when the caller runs one already (the
    /// demo's); start() runs its own.
    void showSkillsOf(const SkillDetectionClock& detector) { detection_ = &detector; }
    /// One round of supervision without waiting, for a command that supervises between its
    /// own work: the components that ended are reported and their restarts scheduled, and
    /// the restarts that are due are made (a restart waits for the component's READY).
    void check();
    /// The cell as `cell status` shows it (JSON).
    [[nodiscard]] std::string statusJson() const;
    /// Stops every component: the tool changer first, then the last started first.
    void stopAll();

private:
    enum class State { Down, Up, Restarting, GivenUp, Stopped };
    struct Component {
        std::string name;
        std::string applicationUri;
        cell::RestartPolicy policy = cell::RestartPolicy::OnFailure;
        std::optional<CellProcess> process;
        State state = State::Down;
        std::string endpoint;
        std::string lastEnd;                      // how it last ended, for status
        std::vector<Clock::time_point> failures;  // within the last minute
        Clock::time_point restartAt{};
        int restarts = 0;
    };
    static const char* toString(State state);

    bool startComponent(Component& c);
    /// Its process ended: report it with its log's tail and schedule a restart (or not).
    void ended(Component& c);
    void restartDue(Component& c);
    void answer(ControlRequest& request, bool* down);

    CellRuntime& runtime_;
    std::vector<Component> components_;  // in start order
    std::optional<ControlSocket> control_;
    std::unique_ptr<SkillDetectionClock> detector_;
    const SkillDetectionClock* detection_ = nullptr;  // detector_, or the caller's
    bool givenUp_ = false;
};

}  // namespace skillcell::apps
