#pragma once
// EventHub: the dashboard's changes, pushed to every open page. Each page (a server-sent
// events stream, answered on a thread of the web server) has a Listener with a queue of its
// own; publish() appends to every queue and wakes their readers. A page that stops reading
// (its queue holds kMaxQueued events) is dropped rather than allowed to hold memory: its
// browser reconnects and starts from a snapshot.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace skillcell::dashboard {

class EventHub {
public:
    static constexpr std::size_t kMaxQueued = 1000;

    class Listener {
    public:
        /// The next event, waiting at most `timeout`; nothing on timeout, and nothing
        /// (with closed() true) once the hub closed or dropped this listener.
        std::optional<std::string> next(std::chrono::milliseconds timeout);
        [[nodiscard]] bool closed();

    private:
        friend class EventHub;
        std::mutex mutex_;
        std::condition_variable ready_;
        std::deque<std::string> queue_;
        bool closed_ = false;
    };

    EventHub() = default;
    ~EventHub() { close(); }
    EventHub(const EventHub&) = delete;
    EventHub& operator=(const EventHub&) = delete;

    /// A new listener; it hears every publish() from now on, until it is released.
    [[nodiscard]] std::shared_ptr<Listener> subscribe();
    void publish(const std::string& event);
    /// Ends every listener (their next() returns nothing at once).
    void close();
    [[nodiscard]] std::size_t listeners();

private:
    std::mutex mutex_;
    std::vector<std::weak_ptr<Listener>> listeners_;
    bool closed_ = false;
};

}  // namespace skillcell::dashboard
