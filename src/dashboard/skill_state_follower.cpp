#include "dashboard/skill_state_follower.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <set>

#include "dashboard/cell_view.hpp"
#include "ua/types/connection_loss.hpp"

namespace skillcell::dashboard {

namespace {

/// One life of a component: what may share a session.
std::string lifeOf(const skills::SkillInstance& skill) {
    return skill.endpointUrl + " " + std::to_string(skill.componentStartTime.ticks);
}

}  // namespace

std::shared_ptr<SkillStateFollower> SkillStateFollower::create(asio::any_io_executor executor,
                                                               ua::ClientConfig config,
                                                               Listeners listeners) {
    return std::make_shared<SkillStateFollower>(Token{}, std::move(executor), std::move(config),
                                                std::move(listeners));
}

SkillStateFollower::SkillStateFollower(Token, asio::any_io_executor executor,
                                       ua::ClientConfig config, Listeners listeners)
    : executor_(std::move(executor)),
      config_(std::move(config)),
      listeners_(std::move(listeners)) {}

void SkillStateFollower::add(const skills::SkillInstance& skill) {
    if (stopped_) return;
    const std::string key = CellView::keyOf(skill);
    auto& entry = skills_[key];
    if (entry.connection) closeLater(std::move(entry.connection));
    entry = Skill{skill, nullptr};
    const std::string life = lifeOf(skill);
    auto [waiting, first] = waiting_.try_emplace(life);
    waiting->second.push_back(key);
    if (first) {
        asio::co_spawn(
            executor_, [self = shared_from_this(), life] { return self->attachAll(life); },
            asio::detached);
    }
}

void SkillStateFollower::remove(const skills::SkillInstance& skill) {
    const auto it = skills_.find(CellView::keyOf(skill));
    if (it == skills_.end()) return;
    if (it->second.connection) closeLater(std::move(it->second.connection));
    skills_.erase(it);
}

void SkillStateFollower::stop() {
    stopped_ = true;
    listeners_ = {};
    waiting_.clear();
    for (auto& [key, skill] : skills_) {
        if (skill.connection) closeLater(std::move(skill.connection));
    }
    skills_.clear();
}

std::size_t SkillStateFollower::followed() const {
    std::size_t n = 0;
    for (const auto& [key, skill] : skills_) n += skill.connection ? 1 : 0;
    return n;
}

std::size_t SkillStateFollower::sessions() const {
    std::set<const ua::Client*> clients;
    for (const auto& [key, skill] : skills_) {
        if (skill.connection) clients.insert(&skill.connection->client());
    }
    return clients.size();
}

asio::awaitable<void> SkillStateFollower::attachAll(std::string life) {
    for (;;) {
        const auto waiting = waiting_.find(life);
        if (waiting == waiting_.end()) co_return;  // stopped
        if (waiting->second.empty()) {
            waiting_.erase(waiting);
            co_return;
        }
        const std::string key = std::move(waiting->second.front());
        waiting->second.pop_front();
        const auto it = skills_.find(key);
        // Removed meanwhile, attached already (added twice), or now another life's.
        if (it == skills_.end() || it->second.connection || lifeOf(it->second.instance) != life) {
            continue;
        }
        co_await attach(it->second.instance, life);
    }
}

asio::awaitable<void> SkillStateFollower::attach(skills::SkillInstance skill, std::string life) {
    const std::string key = CellView::keyOf(skill);
    std::string why;
    // No session of this life to share yet counts as one closed.
    ua::Result<std::unique_ptr<skills::SkillConnection>> opened = ua::status::BadSessionClosed;
    if (const auto shared = sessionOf(life)) {
        const skills::RemoteSkill& remote = skill;
        opened = co_await shared->alongside(remote, &why);
    }
    // No session, or the shared one was lost meanwhile: a session of its own. A skill the
    // component refuses to attach is refused on any session: no second handshake for it.
    if (!opened && ua::isConnectionLoss(opened.status())) {
        opened = co_await skills::SkillConnection::open(executor_, skill, config_, &why);
    }
    const auto it = skills_.find(key);
    if (stopped_ || it == skills_.end() || !(it->second.instance == skill)) {
        if (opened) closeLater(std::move(*opened));  // removed or replaced meanwhile
        co_return;
    }
    if (!opened) {
        skills_.erase(it);  // a later Added tries again
        if (listeners_.failed) listeners_.failed(skill, why);
        co_return;
    }
    std::shared_ptr<skills::SkillConnection> connection = std::move(*opened);
    it->second.connection = connection;
    std::weak_ptr<SkillStateFollower> weak = weak_from_this();
    connection->skill().onTransition([weak, key](const skills::SkillTransitionRecord& t) {
        const auto self = weak.lock();
        if (self && self->listeners_.state) self->listeners_.state(key, t.to, &t);
    });
    if (listeners_.state) listeners_.state(key, connection->skill().state(), nullptr);
    if (listeners_.followed) listeners_.followed(skill, connection);
}

std::shared_ptr<skills::SkillConnection> SkillStateFollower::sessionOf(
    const std::string& life) const {
    for (const auto& [key, skill] : skills_) {
        if (skill.connection && lifeOf(skill.instance) == life) return skill.connection;
    }
    return nullptr;
}

void SkillStateFollower::closeLater(std::shared_ptr<skills::SkillConnection> connection) {
    // Closed politely if the server is still there; the session goes either way.
    asio::co_spawn(
        executor_,
        [connection = std::move(connection)]() -> asio::awaitable<void> {
            co_await connection->close();
        },
        asio::detached);
}

}  // namespace skillcell::dashboard
