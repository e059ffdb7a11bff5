#pragma once
// RunningServer: a skillcell Server on loopback, port 0, running on its own io_context
// thread for the length of a test. Construction returns once the server accepts
// connections; destruction stops it and joins the thread.
#include <asio.hpp>
#include <functional>
#include <future>
#include <memory>
#include <thread>

#include "ua/server/server.hpp"

namespace skillcell::test {

class RunningServer {
public:
    /// `prepare` runs before listen(), e.g. to add nodes.
    explicit RunningServer(ua::ServerConfig config = {},
                           const std::function<void(ua::Server&)>& prepare = {});
    RunningServer(const RunningServer&) = delete;
    RunningServer& operator=(const RunningServer&) = delete;
    ~RunningServer();

    [[nodiscard]] std::uint16_t port() const { return port_; }
    /// The server's io_context, to post work onto its thread (benchmarks drive values so).
    [[nodiscard]] asio::io_context& io() { return io_; }
    /// The server; touch it on its own thread only (from work posted to io()).
    [[nodiscard]] ua::Server& server() { return *server_; }
    [[nodiscard]] std::string url() const;

    /// Runs `f` on the server's thread and waits for its result (the server is
    /// single-threaded; tests look at it only through here).
    template <class F>
    auto inServer(F f) -> decltype(f(std::declval<ua::Server&>())) {
        std::packaged_task<decltype(f(std::declval<ua::Server&>()))()> task(
            [this, &f] { return f(*server_); });
        auto result = task.get_future();
        asio::post(io_, [&task] { task(); });
        return result.get();
    }

    /// The default test configuration: loopback, port 0.
    static ua::ServerConfig defaultConfig();

private:
    asio::io_context io_{1};  // run by one thread only
    std::unique_ptr<ua::Server> server_;
    std::uint16_t port_ = 0;
    std::thread thread_;
};

}  // namespace skillcell::test
