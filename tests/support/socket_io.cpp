#include "socket_io.hpp"

#include <sys/socket.h>

namespace skillcell::test {

bool readExactly(int fd, std::uint8_t* p, std::size_t n) {
    while (n > 0) {
        const auto got = ::recv(fd, p, n, 0);
        if (got <= 0) return false;
        p += got;
        n -= static_cast<std::size_t>(got);
    }
    return true;
}

bool writeAll(int fd, const std::uint8_t* p, std::size_t n) {
    while (n > 0) {
        const auto sent = ::send(fd, p, n, MSG_NOSIGNAL);
        if (sent <= 0) return false;
        p += sent;
        n -= static_cast<std::size_t>(sent);
    }
    return true;
}

}  // namespace skillcell::test
