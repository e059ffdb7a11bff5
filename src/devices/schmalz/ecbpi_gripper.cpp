#include "devices/schmalz/ecbpi_gripper.hpp"

#include <numbers>

namespace skillcell::devices::schmalz {

GripperRating EcbpiGripper::rating() const {
    constexpr double kGravity = 9.81;  // m/s²
    const double area = std::numbers::pi * options_.cupDiameter * options_.cupDiameter / 4;
    const double force = options_.holdingVacuum * 100 /* Pa per mbar */ * area;
    return {force / (options_.safetyFactor * kGravity), 0};
}

std::unique_ptr<EcbpiGripper> EcbpiGripper::start(IoLinkMaster& master,
                                                  EcbpiGripperOptions options) {
    return std::make_unique<EcbpiGripper>(Token{}, master, options);
}

void EcbpiGripper::submit(Goal goal, Done done) {
    worker_.submit([this, goal](GripperWorker::Control& control) { return execute(goal, control); },
                   std::move(done), [this] { (void)write(EcbpiCommand{}); });  // halted: all off
}

void EcbpiGripper::grasp(Done done) {
    submit(Goal::Grasp, std::move(done));
}
void EcbpiGripper::release(Done done) {
    submit(Goal::Release, std::move(done));
}

ua::StatusCode EcbpiGripper::write(const EcbpiCommand& command) {
    const ProcessDataOut out = encode(command);
    return master_.writeProcessData(options_.port, out);
}

ua::Result<EcbpiStatus> EcbpiGripper::read() {
    const auto data = master_.readProcessData(options_.port);
    if (!data) return data.status();
    if (data->size() != kProcessDataInSize) return ua::status::BadDecodingError;
    ProcessDataIn in{};
    std::copy(data->begin(), data->end(), in.begin());
    return decodeStatus(in);
}

std::optional<std::string> EcbpiGripper::execute(Goal goal, GripperWorker::Control& control) {
    const EcbpiCommand command{goal == Goal::Grasp, goal == Goal::Release};
    if (const auto s = write(command); s.isBad()) {
        return "IO-Link: cannot write the process data (" + std::string(ua::statusName(s)) + ")";
    }
    auto budget = goal == Goal::Grasp ? options_.evacuationTime : options_.releaseTime;
    auto last = std::chrono::steady_clock::now();
    for (;;) {
        if (!control.pause()) return std::nullopt;
        const bool suspended = control.suspended();
        const auto now = std::chrono::steady_clock::now();
        if (!suspended) {
            budget -= std::chrono::duration_cast<std::chrono::milliseconds>(now - last);
        }
        last = now;
        if (suspended) continue;
        const auto status = read();
        if (!status) {
            return "IO-Link: cannot read the process data (" +
                   std::string(ua::statusName(status.status())) + ")";
        }
        if (status->device == DeviceStatus::Red) return std::string("the ECBPi reports an error");
        if (goal == Goal::Grasp && status->partPresent) return std::nullopt;
        if (goal == Goal::Release && !status->partPresent &&
            status->vacuum < options_.releasedBelow) {
            (void)write(EcbpiCommand{});  // blow-off done
            return std::nullopt;
        }
        if (budget.count() <= 0) {
            if (goal == Goal::Grasp) {
                (void)write(EcbpiCommand{});
                return "no part under the cup: the vacuum reached " +
                       std::to_string(status->vacuum) +
                       " mbar and the part-present switching point (SP2) was not reached";
            }
            return "the vacuum did not go: " + std::to_string(status->vacuum) + " mbar left";
        }
    }
}

}  // namespace skillcell::devices::schmalz
