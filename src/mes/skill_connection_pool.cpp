#include "mes/skill_connection_pool.hpp"

#include <vector>

namespace skillcell::mes {

SkillConnectionPool::SkillConnectionPool(asio::any_io_executor executor, ua::ClientConfig config,
                                         skills::SkillClientOptions options,
                                         std::chrono::milliseconds idle)
    : executor_(std::move(executor)),
      config_(std::move(config)),
      options_(options),
      idleFor_(idle) {}

// Connections still idle at the end are dropped without a goodbye (the destructor cannot talk
// to the servers): their sessions time out there. closeAll() first says goodbye.
SkillConnectionPool::~SkillConnectionPool() = default;

SkillConnectionPool::Key SkillConnectionPool::keyOf(const skills::SkillInstance& skill) {
    return {skill.componentUri, skill.endpointUrl, skill.nodeId.toString()};
}

bool SkillConnectionPool::alive(skills::SkillConnection& c) {
    return c.client().isConnected() && c.skill().lost().isGood();
}

asio::awaitable<ua::Result<std::unique_ptr<skills::SkillConnection>>> SkillConnectionPool::take(
    const skills::SkillInstance& skill, std::string* why, FirstUse first) {
    if (!first) {
        first = [](skills::SkillConnection& c) -> asio::awaitable<bool> {
            co_return (co_await c.lastTransitionTime()).ok();
        };
    }
    co_await expire();
    const Key key = keyOf(skill);
    while (true) {
        const auto it = idle_.find(key);
        if (it == idle_.end()) break;
        auto c = std::move(it->second.connection);
        idle_.erase(it);
        // An answer proves the session: a component that restarted a moment ago may have left
        // a socket whose end the client has not seen yet.
        if (alive(*c) && co_await first(*c)) {
            ++reused_;
            co_return c;
        }
        co_await c->close();  // lost while idle (the component restarted, the link failed)
    }
    ++opened_;
    auto opened = co_await skills::SkillConnection::open(executor_, skill, config_, why, options_);
    if (opened) (void)co_await first(**opened);  // what it answered is the taker's to judge
    co_return opened;
}

asio::awaitable<void> SkillConnectionPool::giveBack(
    const skills::SkillInstance& skill, std::unique_ptr<skills::SkillConnection> connection) {
    if (!connection) co_return;
    const auto state = connection->skill().state();
    // A skill still running, or one left in a state the next step must look at afresh, is
    // not kept: the next step attaches anew and reads it.
    const bool settled = state == skills::SkillState::Ready || state == skills::SkillState::Halted;
    if (!alive(*connection) || !settled || idleFor_.count() <= 0) {
        co_await connection->close();
        co_return;
    }
    idle_.emplace(keyOf(skill), Idle{std::move(connection), std::chrono::steady_clock::now()});
    co_await expire();
}

asio::awaitable<void> SkillConnectionPool::closeAll() {
    auto all = std::move(idle_);
    idle_.clear();
    for (auto& [key, i] : all) co_await i.connection->close();
}

asio::awaitable<void> SkillConnectionPool::expire() {
    const auto before = std::chrono::steady_clock::now() - idleFor_;
    std::vector<std::unique_ptr<skills::SkillConnection>> closing;
    for (auto it = idle_.begin(); it != idle_.end();) {
        if (it->second.since <= before) {
            closing.push_back(std::move(it->second.connection));
            it = idle_.erase(it);
        } else {
            ++it;
        }
    }
    for (auto& c : closing) co_await c->close();
}

}  // namespace skillcell::mes
