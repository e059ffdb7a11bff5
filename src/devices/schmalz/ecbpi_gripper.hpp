#pragma once
// EcbpiGripper: the Schmalz ECBPi adapter, a Gripper over an IoLinkMaster port. One worker
// thread runs one operation at a time, writing the process data out and polling the
// process data in (IO-Link is cyclic: the adapter samples what the master last received):
//   Grasp:   suction on, until SP2 (part present); no SP2 within the evacuation time
//            means no part sealed the cup: suction off, the run fails with the vacuum
//            reached.
//   Release: suction off and blow-off on until the vacuum is gone, then blow-off off.
// Suspend pauses the polling and the deadline (the vacuum command stays as it is);
// Halt abandons the operation and switches suction and blow-off off.
#include <chrono>
#include <memory>
#include <optional>

#include "devices/gripper/gripper_worker.hpp"
#include "devices/schmalz/ecbpi_process_data.hpp"
#include "devices/schmalz/io_link_master.hpp"

namespace skillcell::devices::schmalz {

struct EcbpiGripperOptions {
    EcbpiGripperOptions() = default;
    int port = 1;
    std::chrono::milliseconds poll{5};
    std::chrono::milliseconds evacuationTime{1000};  // real time for SP2 to come
    std::chrono::milliseconds releaseTime{1000};     // real time for the vacuum to go
    std::uint16_t releasedBelow = 20;                // mbar: the part is free
    // What the rating is computed from: the suction cup on the tool, the vacuum at which the
    // ECBPi reports the part held (its SP2 switching point), and the safety factor for a
    // horizontal face lifted vertically.
    double cupDiameter = 0.04;   // m
    double holdingVacuum = 400;  // mbar
    double safetyFactor = 2;
};

class EcbpiGripper final : public Gripper {
public:
    [[nodiscard]] static std::unique_ptr<EcbpiGripper> start(IoLinkMaster& master,
                                                             EcbpiGripperOptions options = {});
    ~EcbpiGripper() override = default;

    void grasp(Done done) override;
    void release(Done done) override;
    void suspend() override { worker_.suspend(); }
    void resume() override { worker_.resume(); }
    void halt() override { worker_.halt(); }
    /// The holding force of the cup at the holding vacuum, over the safety factor; a suction
    /// cup's width does not limit what it holds.
    [[nodiscard]] GripperRating rating() const override;

    struct Token {
    private:
        friend class EcbpiGripper;
        Token() = default;
    };
    EcbpiGripper(Token, IoLinkMaster& master, EcbpiGripperOptions options)
        : master_(master), options_(options), worker_(options.poll) {}

private:
    enum class Goal : std::uint8_t { Grasp, Release };
    void submit(Goal goal, Done done);
    std::optional<std::string> execute(Goal goal, GripperWorker::Control& control);
    ua::StatusCode write(const EcbpiCommand& command);
    [[nodiscard]] ua::Result<EcbpiStatus> read();

    IoLinkMaster& master_;
    EcbpiGripperOptions options_;
    GripperWorker worker_;  // last: stopped (joined) before the rest goes
};

}  // namespace skillcell::devices::schmalz
