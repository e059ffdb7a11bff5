#pragma once
// RawConnection: a blocking loopback TCP client for protocol tests. It sends exactly the
// bytes a test builds (valid, truncated or garbage) and reads frames back with a bounded
// wait, so a server that does not answer fails the test instead of hanging it.
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ua/transport/secure_channel.hpp"

namespace skillcell::test {

struct ReceivedFrame {
    ua::MessageHeader header;
    std::vector<std::uint8_t> bytes;  // whole frame, header included
};

class RawConnection {
public:
    explicit RawConnection(std::uint16_t port,
                           std::chrono::milliseconds timeout = std::chrono::seconds(5));
    RawConnection(const RawConnection&) = delete;
    RawConnection& operator=(const RawConnection&) = delete;
    ~RawConnection();

    void send(std::span<const std::uint8_t> bytes);
    /// The next frame; std::nullopt on EOF, timeout or a malformed header.
    std::optional<ReceivedFrame> readFrame();
    /// The status of the next frame if it is ERR; std::nullopt for anything else.
    std::optional<ua::StatusCode> readError();
    /// True when the server closed the connection (EOF) within the timeout.
    bool closedByPeer();

    /// Hello with default limits; returns the Acknowledge's limits negotiated as a client.
    ua::TransportLimits hello();
    /// Hello + OpenSecureChannel (None); afterwards `channel()` encodes and decodes.
    /// `misbehave` may change the negotiated limits, to send what the server did not allow.
    void open(const std::function<void(ua::TransportLimits&)>& misbehave = {});
    ua::SecureChannel& channel() { return *channel_; }

    /// Sends a service body (type id + structure) as MSG and returns the response body.
    std::optional<std::vector<std::uint8_t>> exchange(std::span<const std::uint8_t> body);
    std::uint32_t nextRequestId() { return ++requestId_; }

private:
    bool readExactly(std::uint8_t* p, std::size_t n);

    int fd_ = -1;
    std::optional<ua::SecureChannel> channel_;
    std::uint32_t requestId_ = 0;
};

}  // namespace skillcell::test
