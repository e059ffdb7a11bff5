#include "devices/schmalz/ecbpi_gripper.hpp"

namespace skillcell::devices::schmalz {

std::unique_ptr<EcbpiGripper> EcbpiGripper::start(IoLinkMaster& master,
                                                  EcbpiGripperOptions options) {
    auto gripper = std::make_unique<EcbpiGripper>(Token{}, master, options);
    gripper->thread_ = std::thread([g = gripper.get()] { g->run(); });
    return gripper;
}

EcbpiGripper::~EcbpiGripper() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        ++generation_;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void EcbpiGripper::submit(Goal goal, Done done) {
    {
        std::lock_guard lock(mutex_);
        pending_ = Job{goal, std::move(done)};
        suspended_ = false;
    }
    cv_.notify_all();
}

void EcbpiGripper::grasp(Done done) {
    submit(Goal::Grasp, std::move(done));
}
void EcbpiGripper::release(Done done) {
    submit(Goal::Release, std::move(done));
}

void EcbpiGripper::suspend() {
    std::lock_guard lock(mutex_);
    suspended_ = true;
}
void EcbpiGripper::resume() {
    {
        std::lock_guard lock(mutex_);
        suspended_ = false;
    }
    cv_.notify_all();
}
void EcbpiGripper::halt() {
    {
        std::lock_guard lock(mutex_);
        ++generation_;
        pending_.reset();
        suspended_ = false;
    }
    cv_.notify_all();
}

bool EcbpiGripper::pause(std::uint64_t generation, bool& suspended) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, options_.poll, [&] { return generation_ != generation; });
    suspended = suspended_;
    return generation_ == generation;
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

void EcbpiGripper::run() {
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [this] { return stopping_ || pending_.has_value(); });
            if (stopping_) return;
            job = std::move(*pending_);
            pending_.reset();
        }
        bool abandoned = false;
        auto failure = execute(job.goal, abandoned);
        if (abandoned) {
            (void)write(EcbpiCommand{});  // halted: suction and blow-off off
            continue;
        }
        job.done(std::move(failure));
    }
}

std::optional<std::string> EcbpiGripper::execute(Goal goal, bool& abandoned) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mutex_);
        generation = generation_;
    }
    const EcbpiCommand command{goal == Goal::Grasp, goal == Goal::Release};
    if (const auto s = write(command); s.isBad()) {
        return "IO-Link: cannot write the process data (" + std::string(ua::statusName(s)) + ")";
    }
    auto budget = goal == Goal::Grasp ? options_.evacuationTime : options_.releaseTime;
    auto last = std::chrono::steady_clock::now();
    for (;;) {
        bool suspended = false;
        if (!pause(generation, suspended)) {
            abandoned = true;
            return std::nullopt;
        }
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
