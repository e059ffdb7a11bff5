#pragma once
// TamperingProxy: a loopback TCP proxy in front of a server that hands every UA-TCP frame a
// client sends to a test's hook, which may pass it on, change it or send it twice. It is the
// man in the middle of the security tests: what a tampered or replayed chunk does to a real
// connection, end to end. Frames from the server pass unchanged, or through a hook of their
// own (tests that lose the server's Publish responses). One connection at a time.
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

namespace skillcell::test {

class TamperingProxy {
public:
    using Frame = std::vector<std::uint8_t>;
    /// `index` counts the client's frames from 0 (Hello); the returned frames are sent.
    using Hook = std::function<std::vector<Frame>(std::size_t index, Frame frame)>;

    /// `fromServer`: the same for the server's frames (index from 0, Acknowledge); none:
    /// they pass unchanged.
    TamperingProxy(std::uint16_t upstreamPort, Hook hook, Hook fromServer = {});
    TamperingProxy(const TamperingProxy&) = delete;
    TamperingProxy& operator=(const TamperingProxy&) = delete;
    ~TamperingProxy();

    [[nodiscard]] std::uint16_t port() const { return port_; }

private:
    void serve();
    void pumpFromServer(int from, int to);
    void pumpFromClient(int from, int to);
    void pumpFrames(int from, int to, const Hook& hook);

    std::uint16_t upstream_;
    Hook hook_;
    Hook fromServer_;
    int listener_ = -1;
    std::uint16_t port_ = 0;
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

}  // namespace skillcell::test
