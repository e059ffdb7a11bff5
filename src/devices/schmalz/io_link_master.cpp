#include "devices/schmalz/io_link_master.hpp"

#include <algorithm>

namespace skillcell::devices::schmalz {

SimulatedIoLinkMaster::SimulatedIoLinkMaster(SimulatedIoLinkOptions options)
    : options_(std::move(options)),
      epoch_(options_.clock ? options_.clock() : std::chrono::steady_clock::now()),
      device_(options_.probe) {
    if (options_.holding) {
        device_.startHolding(*options_.holding);
        shown_.partPresent = true;
    }
}

double SimulatedIoLinkMaster::now() const {
    const auto t = options_.clock ? options_.clock() : std::chrono::steady_clock::now();
    return std::chrono::duration<double>(t - epoch_).count() * options_.speed;
}

void SimulatedIoLinkMaster::deliver(std::vector<CupEvent> events) {
    for (const auto& e : events) {
        if (options_.onEvent) options_.onEvent(e);
    }
}

ua::Result<std::vector<std::uint8_t>> SimulatedIoLinkMaster::readProcessData(int port) {
    if (port != options_.port) return ua::status::BadNotFound;
    EcbpiStatus status;
    std::vector<CupEvent> events;
    {
        std::lock_guard lock(mutex_);
        status = device_.status(now());
        events = device_.takeEvents();
    }
    // The world learns of a grasp before the adapter reads "part present". While it has not
    // heard one yet (it restarts), the switching points show what they showed before: the
    // vacuum is still building or going, for all the adapter can tell.
    deliver(std::move(events));
    bool behind = options_.worldBehind && options_.worldBehind();
    if (behind && options_.awaitWorld) behind = !options_.awaitWorld();
    {
        std::lock_guard lock(mutex_);
        if (behind) {
            status.partPresent = shown_.partPresent;
            status.partDetached = shown_.partDetached;
        } else {
            shown_ = status;
        }
    }
    const ProcessDataIn data = encode(status);
    return std::vector<std::uint8_t>(data.begin(), data.end());
}

ua::StatusCode SimulatedIoLinkMaster::writeProcessData(int port,
                                                       std::span<const std::uint8_t> data) {
    if (port != options_.port) return ua::status::BadNotFound;
    if (data.size() != kProcessDataOutSize) return ua::status::BadInvalidArgument;
    ProcessDataOut out{};
    std::copy(data.begin(), data.end(), out.begin());
    std::vector<CupEvent> events;
    {
        std::lock_guard lock(mutex_);
        device_.write(decodeCommand(out), now());
        events = device_.takeEvents();
    }
    deliver(std::move(events));
    return ua::status::Good;
}

double SimulatedIoLinkMaster::vacuum() {
    std::lock_guard lock(mutex_);
    (void)device_.status(now());
    return device_.vacuum();
}

EcbpiCommand SimulatedIoLinkMaster::lastCommand() {
    std::lock_guard lock(mutex_);
    return device_.command();
}

}  // namespace skillcell::devices::schmalz
