#include "ua/discovery/link_monitor.hpp"

#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/use_awaitable.hpp>
#include <cstring>

namespace skillcell::ua::mdns {

std::vector<unsigned> LinkStates::cameUp(std::span<const std::uint8_t> datagram) {
    std::vector<unsigned> up;
    std::size_t offset = 0;
    // Each message: an aligned nlmsghdr whose nlmsg_len covers it; copied out, since a
    // datagram buffer promises no alignment.
    while (datagram.size() - offset >= sizeof(nlmsghdr)) {
        nlmsghdr header{};
        std::memcpy(&header, datagram.data() + offset, sizeof header);
        const std::size_t length = header.nlmsg_len;
        if (length < sizeof header || length > datagram.size() - offset) break;
        if (header.nlmsg_type == RTM_NEWLINK && length >= NLMSG_LENGTH(sizeof(ifinfomsg))) {
            ifinfomsg info{};
            std::memcpy(&info, datagram.data() + offset + NLMSG_HDRLEN, sizeof info);
            const auto it = running_.find(static_cast<unsigned>(info.ifi_index));
            if (it != running_.end()) {
                const bool running =
                    (info.ifi_flags & IFF_UP) != 0 && (info.ifi_flags & IFF_RUNNING) != 0;
                if (running && !it->second) up.push_back(it->first);
                it->second = running;
            }
        }
        offset += NLMSG_ALIGN(length);
        if (offset > datagram.size()) break;
    }
    return up;
}

LinkMonitor::LinkMonitor(asio::any_io_executor executor, std::map<unsigned, bool> running,
                         Listener listener)
    : socket_(executor), states_(std::move(running)), listener_(std::move(listener)) {}

std::shared_ptr<LinkMonitor> LinkMonitor::create(asio::any_io_executor executor,
                                                 std::map<unsigned, bool> running,
                                                 Listener listener, std::string* error) {
    std::shared_ptr<LinkMonitor> m(
        new LinkMonitor(std::move(executor), std::move(running), std::move(listener)));
    const asio::generic::raw_protocol protocol(AF_NETLINK, NETLINK_ROUTE);
    asio::error_code ec;
    m->socket_.open(protocol, ec);
    if (!ec) {
        sockaddr_nl local{};
        local.nl_family = AF_NETLINK;
        local.nl_groups = RTMGRP_LINK;
        m->socket_.bind(asio::generic::raw_protocol::endpoint(&local, sizeof local), ec);
    }
    if (ec) {
        if (error != nullptr) *error = "rtnetlink: " + ec.message();
        return nullptr;
    }
    return m;
}

void LinkMonitor::start() {
    asio::co_spawn(socket_.get_executor(), readLoop(), asio::detached);
}

void LinkMonitor::stop() {
    asio::error_code ec;
    socket_.close(ec);
}

asio::awaitable<void> LinkMonitor::readLoop() {
    auto self = shared_from_this();
    // Link messages are a few hundred bytes to a few KB (their attributes); a bigger one is
    // cut, and its header then says so: it is skipped.
    std::array<std::uint8_t, 16384> buffer{};
    while (socket_.is_open()) {
        auto [ec, n] = co_await socket_.async_receive(
            asio::buffer(buffer), asio::experimental::as_tuple(asio::use_awaitable));
        if (ec == asio::error::operation_aborted || !socket_.is_open()) break;
        if (ec == asio::error::no_buffer_space) continue;  // some were lost; the next count
        if (ec) break;
        for (const unsigned index :
             states_.cameUp(std::span<const std::uint8_t>(buffer.data(), n))) {
            listener_(index);
        }
    }
}

}  // namespace skillcell::ua::mdns
