#pragma once
// ClientThread: a ua::Client on its own io_context thread, for tests that drive coroutine
// APIs (SkillClient) from plain test code: run() executes a coroutine there and waits.
#include <asio/co_spawn.hpp>
#include <asio/executor_work_guard.hpp>
#include <asio/io_context.hpp>
#include <asio/use_future.hpp>
#include <map>
#include <thread>

#include "skills/skill_client.hpp"
#include "ua/client/client.hpp"

namespace skillcell::test {

/// A client on its own io_context thread; run() executes a coroutine there and waits.
class ClientThread {
public:
    ClientThread()
        : work_(io_.get_executor()), thread_([this] { io_.run(); }), client_(io_.get_executor()) {}
    ~ClientThread() {
        asio::co_spawn(
            io_, [this]() -> asio::awaitable<void> { (void)co_await client_.disconnect(); },
            asio::use_future)
            .get();
        work_.reset();
        thread_.join();
    }
    ClientThread(const ClientThread&) = delete;
    ClientThread& operator=(const ClientThread&) = delete;

    template <class F>
    auto run(F f) {
        return asio::co_spawn(io_, f(), asio::use_future).get();
    }
    ua::Client& client() { return client_; }
    asio::io_context& io() { return io_; }

    std::shared_ptr<skills::SkillClient> attach(const std::string& url, const ua::NodeId& skill) {
        return run([&]() -> asio::awaitable<std::shared_ptr<skills::SkillClient>> {
            if ((co_await client_.connect(url)).isBad()) co_return nullptr;
            auto sc = co_await skills::SkillClient::attach(client_, skill);
            co_return sc ? *sc : nullptr;
        });
    }
    skills::SkillOutcome invoke(const std::shared_ptr<skills::SkillClient>& sc,
                                std::map<std::string, ua::Variant> parameters,
                                std::chrono::milliseconds timeout) {
        return run([&]() -> asio::awaitable<skills::SkillOutcome> {
            co_return co_await sc->run(parameters, timeout);
        });
    }

private:
    asio::io_context io_{1};
    asio::executor_work_guard<asio::io_context::executor_type> work_;
    std::thread thread_;
    ua::Client client_;
};

}  // namespace skillcell::test
