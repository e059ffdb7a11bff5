#pragma once
// VirtuosoWatch: the knowledge base's supervision of its private Virtuoso. When virtuoso-t
// ends on its own (a crash, a SIGKILL) while the KB runs, the watch starts it again on the
// same data directory and ports: acknowledged updates are there (the transaction log rolls
// forward), and the KB then records again the components that are live, whose latest changes
// may not have reached the store. Meanwhile SPARQL requests fail (HTTP 503) and their senders
// try again. A start that fails is tried again after 1 s, doubling up to 30 s.
#include <functional>
#include <thread>

#include "kb/engine/virtuoso_instance.hpp"
#include "process/child_process.hpp"

namespace skillcell::kb::engine {

class VirtuosoWatch {
public:
    /// Watches `virtuoso` (started already) from a thread of its own; `restarted` runs on it
    /// after each restart. `virtuoso` must outlive the watch, and nothing else may start or
    /// stop it while the watch runs.
    VirtuosoWatch(VirtuosoInstance& virtuoso, std::function<void()> restarted);
    /// Stops watching (a Virtuoso being started is started to its end first).
    ~VirtuosoWatch();
    VirtuosoWatch(const VirtuosoWatch&) = delete;
    VirtuosoWatch& operator=(const VirtuosoWatch&) = delete;

private:
    void run();
    /// Waits up to `ms` (-1: for ever) for the stop event or `fd`; true when stopping.
    bool waitFor(int fd, int ms);

    VirtuosoInstance& virtuoso_;
    std::function<void()> restarted_;
    process::UniqueFd stop_;  // an eventfd
    std::thread thread_;
};

}  // namespace skillcell::kb::engine
