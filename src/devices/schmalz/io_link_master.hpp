#pragma once
// IoLinkMaster: the process-data level of an IO-Link master, all the ECBPi adapter uses:
// read a port's process data in, write its process data out (the master exchanges them
// with the device every cycle). SimulatedIoLinkMaster serves a simulated ECBPi on one
// port; a driver for a real master (e.g. over Modbus TCP or the TeConcept board of the
// paper) would be another implementation.
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "devices/schmalz/simulated_ecbpi.hpp"
#include "ua/types/result.hpp"

namespace skillcell::devices::schmalz {

class IoLinkMaster {
public:
    IoLinkMaster() = default;
    virtual ~IoLinkMaster() = default;
    IoLinkMaster(const IoLinkMaster&) = delete;
    IoLinkMaster& operator=(const IoLinkMaster&) = delete;

    /// BadNotFound for a port without a device; BadCommunicationError when the master
    /// cannot be reached.
    [[nodiscard]] virtual ua::Result<std::vector<std::uint8_t>> readProcessData(int port) = 0;
    /// BadInvalidArgument for data of another length than the device's process data out.
    virtual ua::StatusCode writeProcessData(int port, std::span<const std::uint8_t> data) = 0;
};

struct SimulatedIoLinkOptions {
    SimulatedIoLinkOptions() = default;
    int port = 1;
    double speed = 1.0;
    std::function<std::chrono::steady_clock::time_point()> clock;  // empty: steady_clock
    SimulatedEcbpi::Probe probe;
    std::function<void(const CupEvent&)> onEvent;  // called outside the master's lock
    std::optional<std::string> holding;            // the part on the cup as the simulation starts
    /// Whether the world has not heard every event yet (WorldLink::behind): the switching
    /// points show what they showed before until it has.
    std::function<bool()> worldBehind;
    /// Waits, bounded, for the world to hear every event (WorldLink::waitUntilHeard); whether
    /// it has. A read of this in-process master has no reply timeout, so it waits for a world
    /// that restarts rather than show the adapter a vacuum that has not gone, for longer than
    /// its budget.
    std::function<bool()> awaitWorld;
};

/// An IO-Link master with a simulated ECBPi on one port. Thread-safe.
class SimulatedIoLinkMaster final : public IoLinkMaster {
public:
    explicit SimulatedIoLinkMaster(SimulatedIoLinkOptions options);

    ua::Result<std::vector<std::uint8_t>> readProcessData(int port) override;
    ua::StatusCode writeProcessData(int port, std::span<const std::uint8_t> data) override;

    /// The system vacuum now (mbar) and the last command, for tests.
    [[nodiscard]] double vacuum();
    [[nodiscard]] EcbpiCommand lastCommand();

private:
    [[nodiscard]] double now() const;
    void deliver(std::vector<CupEvent> events);

    SimulatedIoLinkOptions options_;
    std::chrono::steady_clock::time_point epoch_;
    std::mutex mutex_;
    SimulatedEcbpi device_;
    EcbpiStatus shown_;  // the last status read while the world had heard everything
};

}  // namespace skillcell::devices::schmalz
