#include "tampering_proxy.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>

#include "socket_io.hpp"

namespace skillcell::test {

namespace {

int connectLoopback(std::uint16_t port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(port);
    if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) return fd;
    if (fd >= 0) ::close(fd);
    return -1;
}

}  // namespace

TamperingProxy::TamperingProxy(std::uint16_t upstreamPort, Hook hook, Hook fromServer)
    : upstream_(upstreamPort), hook_(std::move(hook)), fromServer_(std::move(fromServer)) {
    listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (listener_ < 0) throw std::runtime_error("socket");
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (::bind(listener_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(listener_, 4) != 0 ||
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
        ::close(listener_);
        throw std::runtime_error("bind/listen");
    }
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] { serve(); });
}

TamperingProxy::~TamperingProxy() {
    stopping_ = true;
    ::shutdown(listener_, SHUT_RDWR);
    thread_.join();
    ::close(listener_);
}

void TamperingProxy::serve() {
    while (!stopping_) {
        pollfd p{listener_, POLLIN, 0};
        if (::poll(&p, 1, 100) <= 0) continue;  // bounded: re-checks stopping_
        const int client = ::accept(listener_, nullptr, nullptr);
        if (client < 0) continue;
        const int server = connectLoopback(upstream_);
        if (server < 0) {
            ::close(client);
            continue;
        }
        std::thread back([this, server, client] { pumpFromServer(server, client); });
        pumpFromClient(client, server);
        // Either side closing ends both directions.
        ::shutdown(server, SHUT_RDWR);
        ::shutdown(client, SHUT_RDWR);
        back.join();
        ::close(server);
        ::close(client);
    }
}

void TamperingProxy::pumpFromServer(int from, int to) {
    if (fromServer_) {
        pumpFrames(from, to, fromServer_);
    } else {
        std::uint8_t buffer[16384];
        for (;;) {
            const auto n = ::recv(from, buffer, sizeof buffer, 0);
            if (n <= 0 || !writeAll(to, buffer, static_cast<std::size_t>(n))) break;
        }
    }
    ::shutdown(to, SHUT_RDWR);
    ::shutdown(from, SHUT_RDWR);
}

void TamperingProxy::pumpFromClient(int from, int to) {
    pumpFrames(from, to, hook_);
}

void TamperingProxy::pumpFrames(int from, int to, const Hook& hook) {
    for (std::size_t index = 0;; ++index) {
        Frame frame(8);
        if (!readExactly(from, frame.data(), 8)) return;
        const std::uint32_t size = frame[4] | (frame[5] << 8) | (frame[6] << 16) |
                                   (static_cast<std::uint32_t>(frame[7]) << 24);
        if (size < 8 || size > (1U << 24)) return;
        frame.resize(size);
        if (!readExactly(from, frame.data() + 8, size - 8)) return;
        for (const auto& out : hook(index, std::move(frame))) {
            if (!writeAll(to, out.data(), out.size())) return;
        }
    }
}

}  // namespace skillcell::test
