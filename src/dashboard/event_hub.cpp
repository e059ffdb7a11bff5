#include "dashboard/event_hub.hpp"

#include <algorithm>

namespace skillcell::dashboard {

std::optional<std::string> EventHub::Listener::next(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [this] { return closed_ || !queue_.empty(); });
    if (closed_ || queue_.empty()) return std::nullopt;
    std::string event = std::move(queue_.front());
    queue_.pop_front();
    return event;
}

bool EventHub::Listener::closed() {
    const std::lock_guard lock(mutex_);
    return closed_;
}

std::shared_ptr<EventHub::Listener> EventHub::subscribe() {
    auto listener = std::make_shared<Listener>();
    const std::lock_guard lock(mutex_);
    if (closed_) {
        listener->closed_ = true;
    } else {
        listeners_.push_back(listener);
    }
    return listener;
}

void EventHub::publish(const std::string& event) {
    const std::lock_guard lock(mutex_);
    std::erase_if(listeners_, [](const auto& w) { return w.expired(); });
    for (const auto& weak : listeners_) {
        const auto l = weak.lock();
        if (!l) continue;
        {
            const std::lock_guard inner(l->mutex_);
            if (l->closed_) continue;
            if (l->queue_.size() >= kMaxQueued) {
                l->closed_ = true;  // a reader that fell behind starts again from a snapshot
                l->queue_.clear();
            } else {
                l->queue_.push_back(event);
            }
        }
        l->ready_.notify_one();
    }
}

void EventHub::close() {
    const std::lock_guard lock(mutex_);
    closed_ = true;
    for (const auto& weak : listeners_) {
        if (const auto l = weak.lock()) {
            {
                const std::lock_guard inner(l->mutex_);
                l->closed_ = true;
            }
            l->ready_.notify_all();
        }
    }
    listeners_.clear();
}

std::size_t EventHub::listeners() {
    const std::lock_guard lock(mutex_);
    std::erase_if(listeners_, [](const auto& w) { return w.expired(); });
    return listeners_.size();
}

}  // namespace skillcell::dashboard
