#pragma once
// SceneWatcher: the world model's scene as the dashboard draws it, kept current by a
// subscription to the world's variables (devices/world/world_nodes.hpp): the flange's pose,
// the mounted tool and the grasped object, each object's pose (and a terminal block's rail
// and position on it), each dock's tool and each fuse slot's fuse. What does not move (object
// sizes, dock poses, rails, fuse slots) is read once per connection. The changes of one
// publish come out as one scene. The world's objects and docks are browsed when it connects;
// one added later is drawn after the next reconnection.
//
// A world that cannot be reached, or a subscription that is lost (the world restarted), is
// connected to again every 2 s until stop().
//
// Threading: everything on `executor` (one thread), the callback included.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <functional>
#include <memory>
#include <string>

#include "dashboard/cell_view.hpp"
#include "ua/client/client.hpp"

namespace skillcell::dashboard {

class SceneWatcher : public std::enable_shared_from_this<SceneWatcher> {
public:
    using Listener = std::function<void(const SceneView&)>;

    /// Starts watching the world model at `url`, connecting with `config`.
    [[nodiscard]] static std::shared_ptr<SceneWatcher> start(asio::any_io_executor executor,
                                                             std::string url,
                                                             ua::ClientConfig config,
                                                             Listener onScene);
    /// Ends the watch (its connection closes); the listener is not called any more.
    void stop();

    struct Token {
    private:
        friend class SceneWatcher;
        Token() = default;
    };
    SceneWatcher(Token, asio::any_io_executor executor, std::string url, ua::ClientConfig config,
                 Listener onScene);

private:
    asio::awaitable<void> run();
    /// One connection: read, subscribe, then wait until it is lost or stopped. Returns why
    /// it ended.
    asio::awaitable<ua::StatusCode> watch(ua::Client& client);
    /// Publishes the scene after the current batch of notifications.
    void changed();

    asio::any_io_executor executor_;
    std::string url_;
    ua::ClientConfig config_;
    Listener onScene_;
    asio::steady_timer wake_;
    ua::StatusCode lost_;
    bool stopped_ = false;
    bool flushPending_ = false;
    std::uint64_t connection_ = 0;  // bumps per connection: late callbacks of old ones are ignored
    SceneView scene_;
};

}  // namespace skillcell::dashboard
