#include "devices/world/flange_reporter.hpp"

#include "ua/types/connection_loss.hpp"

#include <spdlog/spdlog.h>

namespace skillcell::devices {

namespace {
constexpr std::chrono::milliseconds kResendPause{100};
constexpr std::chrono::milliseconds kStandingPause{500};
// A standing arm's pose goes to the world this often even on a link that looks up: it keeps
// the link's session well inside its timeout (60 s), and a connection lost without a word
// (no FIN from a host that vanished) shows within it.
constexpr std::chrono::seconds kStandingResend{10};
}  // namespace

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
    // The last pose sent, and whether the world was out of reach for it. It is sent again
    // every 100 ms until the world answers, and, while the arm stands, whenever the link's
    // connection has gone (looked at every 500 ms, without a round trip) or was made anew,
    // and every 10 s: a world that restarted while the arm moved, or stood, learns where the
    // flange is (it acts at a restored robot's flange only once it has heard it,
    // World::actingRobot). A standing arm sent its pose every 500 ms before: two secured
    // round trips a second that cost the idle arm and the world each about a tenth of a
    // percent of a core.
    std::optional<KDL::Frame> last;
    bool unsent = false;
    // link_->connections() when the world answered `last` with Good; 0 (no connection's
    // number) when it did not.
    std::uint64_t sentOnConnection = 0;
    auto sentAt = std::chrono::steady_clock::now();
    for (;;) {
        const auto wake = [this] { return stopping_ || pending_.has_value(); };
        if (!last) {
            cv_.wait(lock, wake);
        } else {
            cv_.wait_for(lock, unsent ? kResendPause : kStandingPause, wake);
        }
        if (stopping_) return;
        if (!pending_ && !unsent) {  // standing (`last` is set: the wait above saw to it)
            lock.unlock();
            const bool heard = link_->connected() && link_->connections() == sentOnConnection &&
                               std::chrono::steady_clock::now() - sentAt < kStandingResend;
            lock.lock();
            if (stopping_) return;
            if (heard && !pending_) continue;
        }
        KDL::Frame flange;
        std::uint64_t covers = sent_;
        if (pending_) {
            flange = *pending_;
            covers = reported_;
            pending_.reset();
        } else {
            flange = *last;
        }
        last = flange;
        lock.unlock();
        double force = 0;
        const auto status = link_->setFlangePose(flange, &force);
        sentOnConnection = status.isGood() ? link_->connections() : 0;
        if (status.isGood()) {
            sentAt = std::chrono::steady_clock::now();
            contactForce_.store(force);
        }
        lock.lock();
        if (status.isBad() && !warned_) {
            spdlog::warn("world model: SetFlangePose failed: {}", ua::statusName(status));
            warned_ = true;
        }
        unsent = ua::isConnectionLoss(status);
        if (status.isGood() && warned_) {
            spdlog::info("world model: SetFlangePose answered again");
            warned_ = false;
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
