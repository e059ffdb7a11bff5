#pragma once
// NoOpComponent: an in-process server with one no-op Move skill (CartesianLinearMoveSkillType)
// that runs for a given time: a component for tests and benchmarks of what drives skills (the
// MES's orders, its connection pool, its overhead).
#include <chrono>
#include <memory>
#include <string>

#include "running_server.hpp"
#include "skills/noop_behaviour.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::test {

struct NoOpComponent {
    NoOpComponent(std::string applicationUri, std::chrono::milliseconds duration)
        : uri(std::move(applicationUri)) {
        auto config = RunningServer::defaultConfig();
        config.description.applicationUri = uri;
        server =
            std::make_unique<RunningServer>(std::move(config), [this, duration](ua::Server& s) {
                skills = skills::SkillServer::create(s, s.executor());
                const auto type = skills->findSkillType("CartesianLinearMoveSkillType");
                (void)skills->add(*type, "Move",
                                  std::make_unique<skills::NoOpBehaviour>(s.executor(), duration));
            });
    }
    // The skills go on the server's thread, before the server.
    ~NoOpComponent() {
        server->inServer([this](ua::Server&) {
            skills.reset();
            return 0;
        });
    }
    NoOpComponent(const NoOpComponent&) = delete;
    NoOpComponent& operator=(const NoOpComponent&) = delete;

    [[nodiscard]] std::string url() const { return server->url(); }
    /// The Move skill's node.
    [[nodiscard]] static ua::NodeId moveSkill() { return ua::NodeId(1, ua::String("Skills/Move")); }

    std::string uri;
    std::unique_ptr<skills::SkillServer> skills;
    std::unique_ptr<RunningServer> server;
};

}  // namespace skillcell::test
