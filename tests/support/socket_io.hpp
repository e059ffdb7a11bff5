#pragma once
// Blocking whole-buffer reads and writes on a socket, for the test clients and proxies that
// speak UA-TCP frame by frame (RawConnection, TamperingProxy).
#include <cstddef>
#include <cstdint>

namespace skillcell::test {

/// False on EOF, error or timeout (SO_RCVTIMEO) before `n` bytes arrived.
bool readExactly(int fd, std::uint8_t* p, std::size_t n);
/// False when the peer closed or an error occurred before all was sent (no SIGPIPE).
bool writeAll(int fd, const std::uint8_t* p, std::size_t n);

}  // namespace skillcell::test
