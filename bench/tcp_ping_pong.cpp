#include "tcp_ping_pong.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>
#include <thread>

namespace skillcell::bench {
namespace {

/// An owned file descriptor.
class Fd {
public:
    explicit Fd(int fd) : fd_(fd) {
        if (fd_ < 0) throw std::runtime_error("socket failed");
    }
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { ::close(fd_); }
    [[nodiscard]] int get() const { return fd_; }

private:
    int fd_;
};

bool readExactly(int fd, std::byte* p, std::size_t n) {
    while (n > 0) {
        const auto got = ::read(fd, p, n);
        if (got <= 0) return false;
        p += got;
        n -= static_cast<std::size_t>(got);
    }
    return true;
}

bool writeAll(int fd, const std::byte* p, std::size_t n) {
    while (n > 0) {
        const auto put = ::write(fd, p, n);
        if (put <= 0) return false;
        p += put;
        n -= static_cast<std::size_t>(put);
    }
    return true;
}

void noDelay(int fd) {
    int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

}  // namespace

std::vector<std::chrono::nanoseconds> tcpPingPong(std::size_t count, std::size_t warmup,
                                                  std::size_t requestSize,
                                                  std::size_t responseSize) {
    Fd listener(::socket(AF_INET, SOCK_STREAM, 0));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;
    if (::bind(listener.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(listener.get(), 1) != 0) {
        throw std::runtime_error("bind/listen failed");
    }
    socklen_t len = sizeof addr;
    ::getsockname(listener.get(), reinterpret_cast<sockaddr*>(&addr), &len);

    const std::size_t total = count + warmup;
    std::jthread echo([&listener, total, requestSize, responseSize] {
        Fd conn(::accept(listener.get(), nullptr, nullptr));
        noDelay(conn.get());
        std::vector<std::byte> in(requestSize), out(responseSize);
        for (std::size_t i = 0; i < total; ++i) {
            if (!readExactly(conn.get(), in.data(), in.size())) return;
            if (!writeAll(conn.get(), out.data(), out.size())) return;
        }
    });

    Fd client(::socket(AF_INET, SOCK_STREAM, 0));
    if (::connect(client.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        throw std::runtime_error("connect failed");
    }
    noDelay(client.get());
    std::vector<std::byte> request(requestSize), response(responseSize);
    std::vector<std::chrono::nanoseconds> samples;
    samples.reserve(count);
    for (std::size_t i = 0; i < total; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        if (!writeAll(client.get(), request.data(), request.size()) ||
            !readExactly(client.get(), response.data(), response.size())) {
            throw std::runtime_error("ping-pong interrupted");
        }
        if (i >= warmup) samples.push_back(std::chrono::steady_clock::now() - t0);
    }
    return samples;
}

}  // namespace skillcell::bench
