#include "skills/sub_skill_runner.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>

namespace skillcell::skills {

asio::awaitable<SkillOutcome> SubSkillRunner::run(SkillClient& skill,
                                                  std::map<std::string, ua::Variant> parameters,
                                                  std::chrono::milliseconds timeout) {
    current_ = skill.shared_from_this();
    // A sub-skill left Halted by an earlier failure is this composite's to reset: it runs
    // it again now.
    if (skill.state() == SkillState::Halted) (void)co_await skill.call(SkillMethod::Reset);
    SkillOutcome outcome = co_await skill.run(std::move(parameters), timeout);
    current_.reset();
    co_return outcome;
}

void SubSkillRunner::halt() {
    ++generation_;
    if (auto skill = current_.lock()) skill->cancel();  // its run() halts it
}

void SubSkillRunner::forward(SkillMethod method) {
    auto skill = current_.lock();
    if (!skill) return;
    asio::co_spawn(
        executor_,
        [skill, method]() -> asio::awaitable<void> { (void)co_await skill->call(method); },
        asio::detached);
}

}  // namespace skillcell::skills
