#pragma once
// LinkMonitor: tells the mDNS responder when an interface it uses comes back: its link has
// carrier again (a cable plugged in, a switch port enabled) or it was set up again. RFC 6762
// asks for this: a responder that sees a link change announces its records again (8.3, 13),
// and a querier asks again from its shortest interval (5.2), since what it knew may have
// changed while it was cut off. Without it, a host whose cable was out longer than the TTL
// finds the others again only at its next query, which the backoff may have put an hour away.
//
// The kernel's rtnetlink link messages (RTMGRP_LINK) say it; IFF_RUNNING is the interface's
// operational state (RFC 2863: up, with carrier). The parsing is pure (LinkStates), so that it
// can be tested with made-up messages; the monitor reads the socket on the responder's
// executor.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/generic/raw_protocol.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace skillcell::ua::mdns {

/// The operational state of the interfaces watched, from rtnetlink datagrams.
class LinkStates {
public:
    /// Watches the interfaces of `running` (if_nametoindex -> whether it runs now).
    explicit LinkStates(std::map<unsigned, bool> running) : running_(std::move(running)) {}
    /// The watched interfaces that one rtnetlink datagram says came up (were not running and
    /// now are). Messages other than RTM_NEWLINK, and truncated ones, are skipped.
    [[nodiscard]] std::vector<unsigned> cameUp(std::span<const std::uint8_t> datagram);

private:
    std::map<unsigned, bool> running_;
};

class LinkMonitor : public std::enable_shared_from_this<LinkMonitor> {
public:
    using Listener = std::function<void(unsigned index)>;

    /// Listens for link changes of the interfaces of `running` (index -> whether it runs
    /// now); `listener` hears, on `executor`, each one that comes up. Null, with `error`
    /// saying why, where rtnetlink cannot be opened.
    [[nodiscard]] static std::shared_ptr<LinkMonitor> create(asio::any_io_executor executor,
                                                             std::map<unsigned, bool> running,
                                                             Listener listener,
                                                             std::string* error = nullptr);
    LinkMonitor(const LinkMonitor&) = delete;
    LinkMonitor& operator=(const LinkMonitor&) = delete;
    ~LinkMonitor() = default;

    /// Starts reading; the monitor lives while its loop runs.
    void start();
    /// Ends the loop. Idempotent.
    void stop();

private:
    LinkMonitor(asio::any_io_executor executor, std::map<unsigned, bool> running,
                Listener listener);
    asio::awaitable<void> readLoop();

    asio::generic::raw_protocol::socket socket_;
    LinkStates states_;
    Listener listener_;
};

}  // namespace skillcell::ua::mdns
