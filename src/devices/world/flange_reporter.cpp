#include "devices/world/flange_reporter.hpp"

#include <spdlog/spdlog.h>

namespace skillcell::devices {

std::unique_ptr<FlangeReporter> FlangeReporter::start(std::unique_ptr<WorldLink> link) {
    auto reporter = std::make_unique<FlangeReporter>(Token{}, std::move(link));
    reporter->thread_ = std::thread([r = reporter.get()] { r->run(); });
    return reporter;
}

FlangeReporter::~FlangeReporter() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void FlangeReporter::report(const KDL::Frame& flange) {
    {
        std::lock_guard lock(mutex_);
        pending_ = flange;
        ++reported_;
    }
    cv_.notify_all();
}

std::uint64_t FlangeReporter::unanswered() {
    std::lock_guard lock(mutex_);
    return reported_ - sent_;
}

bool FlangeReporter::flush(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    const std::uint64_t target = reported_;
    return cv_.wait_for(lock, timeout, [&] { return sent_ >= target; });
}

void FlangeReporter::whenSent(std::function<void()> callback) {
    {
        std::lock_guard lock(mutex_);
        if (sent_ < reported_) {
            waiters_.emplace_back(reported_, std::move(callback));
            return;
        }
    }
    callback();
}

void FlangeReporter::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        cv_.wait(lock, [this] { return stopping_ || pending_.has_value(); });
        if (stopping_) return;
        const KDL::Frame flange = *pending_;
        const std::uint64_t covers = reported_;
        pending_.reset();
        lock.unlock();
        double force = 0;
        const auto status = link_->setFlangePose(flange, &force);
        if (status.isGood()) contactForce_.store(force);
        lock.lock();
        if (status.isBad() && !warned_) {
            spdlog::warn("world model: SetFlangePose failed: {}", ua::statusName(status));
            warned_ = true;
        }
        sent_ = covers;
        cv_.notify_all();
        std::vector<std::function<void()>> ready;
        std::erase_if(waiters_, [&](auto& w) {
            if (w.first > sent_) return false;
            ready.push_back(std::move(w.second));
            return true;
        });
        if (ready.empty()) continue;
        lock.unlock();
        for (auto& callback : ready) callback();
        lock.lock();
    }
}

}  // namespace skillcell::devices
