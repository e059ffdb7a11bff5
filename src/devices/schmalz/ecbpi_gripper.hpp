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
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "devices/gripper/parallel_gripper.hpp"
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
};

class EcbpiGripper final : public Gripper {
public:
    [[nodiscard]] static std::unique_ptr<EcbpiGripper> start(IoLinkMaster& master,
                                                             EcbpiGripperOptions options = {});
    ~EcbpiGripper() override;

    void grasp(Done done) override;
    void release(Done done) override;
    void suspend() override;
    void resume() override;
    void halt() override;

    struct Token {
    private:
        friend class EcbpiGripper;
        Token() = default;
    };
    EcbpiGripper(Token, IoLinkMaster& master, EcbpiGripperOptions options)
        : master_(master), options_(options) {}

private:
    enum class Goal : std::uint8_t { Grasp, Release };
    struct Job {
        Goal goal;
        Done done;
    };
    void submit(Goal goal, Done done);
    void run();
    std::optional<std::string> execute(Goal goal, bool& abandoned);
    ua::StatusCode write(const EcbpiCommand& command);
    [[nodiscard]] ua::Result<EcbpiStatus> read();
    /// One poll period; false when halted. `suspended` tells whether the operation is held.
    bool pause(std::uint64_t generation, bool& suspended);

    IoLinkMaster& master_;
    EcbpiGripperOptions options_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<Job> pending_;
    std::uint64_t generation_ = 0;
    bool suspended_ = false;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace skillcell::devices::schmalz
