#include "ua/server/subscriptions/monitored_item.hpp"

#include <cmath>

namespace skillcell::ua {
namespace {

std::optional<double> numeric(const Scalar& s) {
    return std::visit(
        [](const auto& x) -> std::optional<double> {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
                return static_cast<double>(x);
            } else {
                return std::nullopt;
            }
        },
        s);
}

/// True when the values differ by more than `deadband` (any element of an array);
/// values that are not numeric compare exactly.
bool exceedsDeadband(const Variant& a, const Variant& b, double deadband) {
    if (a.isArray() != b.isArray() || a.type() != b.type()) return true;
    auto differs = [deadband](const Scalar& x, const Scalar& y) {
        const auto nx = numeric(x);
        const auto ny = numeric(y);
        if (!nx || !ny) return x != y;
        return std::fabs(*nx - *ny) > deadband;
    };
    if (!a.isArray()) return differs(a.scalar(), b.scalar());
    if (a.elements().size() != b.elements().size() || a.dimensions() != b.dimensions()) return true;
    for (std::size_t i = 0; i < a.elements().size(); ++i) {
        if (differs(a.elements()[i], b.elements()[i])) return true;
    }
    return false;
}

}  // namespace

bool dataChangePasses(const DataChangeFilter& filter, const DataValue& last,
                      const DataValue& current) {
    if (last.statusOrGood() != current.statusOrGood()) return true;
    if (filter.trigger == DataChangeTrigger::Status) return false;
    const Variant none;
    const Variant& a = last.value ? *last.value : none;
    const Variant& b = current.value ? *current.value : none;
    const bool valueChanged =
        static_cast<DeadbandType>(filter.deadbandType) == DeadbandType::Absolute
            ? exceedsDeadband(a, b, filter.deadbandValue)
            : a != b;
    if (valueChanged) return true;
    if (filter.trigger == DataChangeTrigger::StatusValueTimestamp) {
        return last.sourceTimestamp != current.sourceTimestamp ||
               last.sourcePicoseconds != current.sourcePicoseconds;
    }
    return false;
}

void MonitoredItem::configure(std::uint32_t clientHandle, double samplingIntervalMs,
                              std::uint32_t queueSize, bool discardOldest,
                              TimestampsToReturn timestamps) {
    clientHandle_ = clientHandle;
    samplingIntervalMs_ = samplingIntervalMs;
    queueSize_ = std::max<std::uint32_t>(queueSize, 1);
    discardOldest_ = discardOldest;
    timestamps_ = timestamps;
    auto shrink = [this](auto& q) {
        while (q.size() > queueSize_) {
            if (discardOldest_) {
                q.pop_front();
            } else {
                q.pop_back();
            }
        }
    };
    shrink(values_);
    shrink(events_);
}

void MonitoredItem::setMode(MonitoringMode mode) {
    mode_ = mode;
    if (mode == MonitoringMode::Disabled) {
        values_.clear();
        events_.clear();
        last_.reset();
    }
}

template <class T>
bool MonitoredItem::push(std::deque<T>& queue, T entry) {
    if (queue.size() < queueSize_) {
        queue.push_back(std::move(entry));
        return false;
    }
    // Full. A queue of one always holds the newest value and is not an overflow.
    if (queueSize_ == 1) {
        queue.back() = std::move(entry);
        return false;
    }
    if (discardOldest_) {
        queue.pop_front();
        queue.push_back(std::move(entry));
        return true;  // the new front follows a gap
    }
    queue.back() = std::move(entry);  // the newest replaces the last queued
    return true;
}

bool MonitoredItem::offerValue(const DataValue& sample, DateTime serverTime) {
    if (mode_ == MonitoringMode::Disabled || kind_ != Kind::DataChange) return false;
    if (last_ && !dataChangePasses(dataFilter_, *last_, sample)) return false;
    last_ = sample;

    DataValue dv = sample;
    dv.serverTimestamp = serverTime;
    dv.serverPicoseconds.reset();
    if (timestamps_ == TimestampsToReturn::Server || timestamps_ == TimestampsToReturn::Neither) {
        dv.sourceTimestamp.reset();
        dv.sourcePicoseconds.reset();
    }
    if (timestamps_ == TimestampsToReturn::Source || timestamps_ == TimestampsToReturn::Neither) {
        dv.serverTimestamp.reset();
    }
    if (push(values_, MonitoredItemNotification{clientHandle_, std::move(dv)})) {
        // Mark the value that follows the discarded one: the front when the oldest went,
        // the replaced newest otherwise.
        DataValue& marked = discardOldest_ ? values_.front().value : values_.back().value;
        marked.status = StatusCode(marked.statusOrGood().code | kOverflowInfoBits);
    }
    return true;
}

void MonitoredItem::offerEvent(std::vector<Variant> fields) {
    if (mode_ == MonitoringMode::Disabled || kind_ != Kind::Event) return;
    // An overflowing event queue loses events silently: the EventQueueOverflowEventType
    // notification is not implemented.
    push(events_, EventFieldList{clientHandle_, std::move(fields)});
}

std::size_t MonitoredItem::takeDataChanges(std::vector<MonitoredItemNotification>& out,
                                           std::size_t max) {
    std::size_t n = 0;
    while (n < max && !values_.empty()) {
        out.push_back(std::move(values_.front()));
        values_.pop_front();
        ++n;
    }
    return n;
}

std::size_t MonitoredItem::takeEvents(std::vector<EventFieldList>& out, std::size_t max) {
    std::size_t n = 0;
    while (n < max && !events_.empty()) {
        out.push_back(std::move(events_.front()));
        events_.pop_front();
        ++n;
    }
    return n;
}

}  // namespace skillcell::ua
