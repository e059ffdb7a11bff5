#pragma once
// MonitoredItem: one item of a subscription (OPC 10000-4, 5.12.1): what it watches, its
// monitoring mode, filter and notification queue. No I/O, no clock: the engine offers it
// samples and events and takes its notifications at publishing time.
#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "ua/messages/subscription.hpp"
#include "ua/server/subscriptions/event.hpp"

namespace skillcell::ua {

/// Status code info bits of a queued value that replaced or followed a discarded one
/// (OPC 10000-4, 7.39.1: InfoType DataValue + Overflow).
inline constexpr std::uint32_t kOverflowInfoBits = 0x0480;

/// True when `current` differs from `last` enough for `filter` to report it (7.22.2).
/// The deadband applies to numeric scalars and arrays (Absolute only).
[[nodiscard]] bool dataChangePasses(const DataChangeFilter& filter, const DataValue& last,
                                    const DataValue& current);

class MonitoredItem {
public:
    using TimePoint = std::chrono::steady_clock::time_point;
    enum class Kind : std::uint8_t { DataChange, Event };

    MonitoredItem(std::uint32_t id, Kind kind, ReadValueId itemToMonitor,
                  TimestampsToReturn timestamps)
        : id_(id), kind_(kind), itemToMonitor_(std::move(itemToMonitor)), timestamps_(timestamps) {}

    [[nodiscard]] std::uint32_t id() const { return id_; }
    [[nodiscard]] Kind kind() const { return kind_; }
    [[nodiscard]] const ReadValueId& itemToMonitor() const { return itemToMonitor_; }
    [[nodiscard]] MonitoringMode mode() const { return mode_; }
    [[nodiscard]] std::uint32_t clientHandle() const { return clientHandle_; }
    [[nodiscard]] double samplingIntervalMs() const { return samplingIntervalMs_; }
    [[nodiscard]] std::uint32_t queueSize() const { return queueSize_; }
    [[nodiscard]] bool discardOldest() const { return discardOldest_; }
    [[nodiscard]] std::size_t queued() const { return values_.size() + events_.size(); }
    [[nodiscard]] bool hasNotifications() const {
        return mode_ == MonitoringMode::Reporting && queued() > 0;
    }

    /// Revised parameters; a smaller queue drops what no longer fits (oldest or newest).
    void configure(std::uint32_t clientHandle, double samplingIntervalMs, std::uint32_t queueSize,
                   bool discardOldest, TimestampsToReturn timestamps);
    void setDataChangeFilter(const DataChangeFilter& filter) { dataFilter_ = filter; }
    void setEventFilter(CompiledEventFilter filter) { eventFilter_ = std::move(filter); }
    [[nodiscard]] const CompiledEventFilter* eventFilter() const {
        return eventFilter_ ? &*eventFilter_ : nullptr;
    }
    /// Disabled drops the queue and forgets the last value, so that re-enabling reports
    /// the current value again (OPC 10000-4, 5.12.1.3).
    void setMode(MonitoringMode mode);

    /// A sampled value: queued when it passes the data change filter against the last one
    /// queued. Returns true if queued. Ignored while Disabled.
    bool offerValue(const DataValue& sample, DateTime serverTime);
    /// An event's selected fields: queued (events have no filter beyond the where clause).
    void offerEvent(std::vector<Variant> fields);

    /// Moves up to `max` notifications to `out` (oldest first); returns how many.
    std::size_t takeDataChanges(std::vector<MonitoredItemNotification>& out, std::size_t max);
    std::size_t takeEvents(std::vector<EventFieldList>& out, std::size_t max);

    /// Polled sampling (variables with a ValueSource): when the next sample is due.
    TimePoint nextSample{};

private:
    template <class T>
    bool push(std::deque<T>& queue, T entry);

    std::uint32_t id_;
    Kind kind_;
    ReadValueId itemToMonitor_;
    TimestampsToReturn timestamps_;
    MonitoringMode mode_ = MonitoringMode::Disabled;
    std::uint32_t clientHandle_ = 0;
    double samplingIntervalMs_ = 0;
    std::uint32_t queueSize_ = 1;
    bool discardOldest_ = true;
    DataChangeFilter dataFilter_;
    std::optional<CompiledEventFilter> eventFilter_;
    std::optional<DataValue> last_;  // the last sample that passed, as sampled
    std::deque<MonitoredItemNotification> values_;
    std::deque<EventFieldList> events_;
};

}  // namespace skillcell::ua
