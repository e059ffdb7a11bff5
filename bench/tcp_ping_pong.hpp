#pragma once
// The floor of every request/response benchmark: a raw TCP ping-pong on loopback with
// blocking sockets and TCP_NODELAY, the same message sizes as an OPC UA Read, no protocol.
#include <chrono>
#include <cstddef>
#include <vector>

namespace skillcell::bench {

/// Round-trip times of `count` sequential ping-pongs of `requestSize` bytes answered with
/// `responseSize` bytes, after `warmup` unmeasured ones.
std::vector<std::chrono::nanoseconds> tcpPingPong(std::size_t count, std::size_t warmup,
                                                  std::size_t requestSize,
                                                  std::size_t responseSize);

}  // namespace skillcell::bench
