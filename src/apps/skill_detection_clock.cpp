#include "skill_detection_clock.hpp"

#include <asio/post.hpp>
#include <asio/use_future.hpp>

namespace skillcell::apps {

std::unique_ptr<SkillDetectionClock> SkillDetectionClock::start(skills::SkillDetectorConfig config,
                                                                ua::mdns::MdnsConfig mdns,
                                                                std::string* error) {
    auto c = std::make_unique<SkillDetectionClock>(Token{});
    auto responder = ua::mdns::MdnsResponder::create(c->io_.get_executor(), mdns, error);
    if (!responder) return nullptr;
    c->responder_ = *responder;
    c->detector_ = skills::SkillDetector::create(c->io_.get_executor(), std::move(config));
    auto* self = c.get();
    c->detector_->subscribe([self](const skills::SkillEvent& e) { self->record(e); });
    c->responder_->start();
    c->watcher_ = skills::attachMdns(c->detector_, c->responder_);
    c->work_.emplace(c->io_.get_executor());
    c->thread_ = std::thread([self] { self->io_.run(); });
    return c;
}

SkillDetectionClock::~SkillDetectionClock() {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
        if (watcher_) watcher_->stop();
        detector_->stop();
        responder_->shutdown();
    });
    work_.reset();  // the thread ends once the connections have closed
    thread_.join();
}

void SkillDetectionClock::record(const skills::SkillEvent& event) {
    const auto now = Clock::now();
    {
        const std::lock_guard lock(mutex_);
        Component& c = components_[event.instance.componentUri];
        if (event.kind == skills::SkillEvent::Kind::Added) {
            if (c.skills++ == 0) c.appearances.push_back(now);
        } else if (c.skills > 0) {
            --c.skills;
        }
    }
    changed_.notify_all();
}

std::optional<SkillDetectionClock::Clock::time_point> SkillDetectionClock::waitAppeared(
    const std::string& applicationUri, Clock::time_point since, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    std::optional<Clock::time_point> seen;
    changed_.wait_for(lock, timeout, [&] {
        for (const auto t : components_[applicationUri].appearances) {
            if (t >= since) {
                seen = t;
                return true;
            }
        }
        return false;
    });
    return seen;
}

bool SkillDetectionClock::waitGone(const std::string& applicationUri,
                                   std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout,
                             [&] { return components_[applicationUri].skills == 0; });
}

std::vector<skills::SkillInstance> SkillDetectionClock::instances() const {
    return detector_->instances();
}

}  // namespace skillcell::apps
