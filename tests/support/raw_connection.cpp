#include "raw_connection.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>

#include "socket_io.hpp"
#include "ua/server/service_table.hpp"

namespace skillcell::test {

using namespace ua;

RawConnection::RawConnection(std::uint16_t port, std::chrono::milliseconds timeout) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd_ < 0) throw std::runtime_error("socket");
    timeval tv{};
    tv.tv_sec = static_cast<time_t>(timeout.count() / 1000);
    tv.tv_usec = static_cast<suseconds_t>((timeout.count() % 1000) * 1000);
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(port);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        ::close(fd_);
        throw std::runtime_error("connect");
    }
}

RawConnection::~RawConnection() {
    ::close(fd_);
}

void RawConnection::send(std::span<const std::uint8_t> bytes) {
    // The server may already have closed; reading tells.
    (void)writeAll(fd_, bytes.data(), bytes.size());
}

bool RawConnection::readExactly(std::uint8_t* p, std::size_t n) {
    return test::readExactly(fd_, p, n);
}

std::optional<ReceivedFrame> RawConnection::readFrame() {
    ReceivedFrame frame;
    frame.bytes.resize(kMessageHeaderSize);
    if (!readExactly(frame.bytes.data(), kMessageHeaderSize)) return std::nullopt;
    auto header = parseMessageHeader(std::span<const std::uint8_t, 8>(frame.bytes.data(), 8),
                                     16u * 1024 * 1024);
    if (!header) return std::nullopt;
    frame.header = *header;
    frame.bytes.resize(header->size);
    if (!readExactly(frame.bytes.data() + kMessageHeaderSize, header->size - kMessageHeaderSize)) {
        return std::nullopt;
    }
    return frame;
}

std::optional<StatusCode> RawConnection::readError() {
    auto frame = readFrame();
    if (!frame || frame->header.type != MessageType::Error) return std::nullopt;
    auto error = decodeError(frame->bytes);
    if (!error) return std::nullopt;
    return error->error;
}

bool RawConnection::closedByPeer() {
    std::uint8_t byte = 0;
    for (int i = 0; i < 1000; ++i) {  // bounded: drains at most 1000 bytes of late output
        const auto n = ::recv(fd_, &byte, 1, 0);
        if (n == 0) return true;
        if (n < 0) return false;  // timeout or error: not closed in time
    }
    return false;
}

TransportLimits RawConnection::hello() {
    HelloMessage h;
    h.receiveBufferSize = 65535;
    h.sendBufferSize = 65535;
    h.maxMessageSize = 0;
    h.maxChunkCount = 0;
    h.endpointUrl = "opc.tcp://127.0.0.1";
    send(encodeHello(h));
    auto frame = readFrame();
    if (!frame || frame->header.type != MessageType::Acknowledge) {
        throw std::runtime_error("no Acknowledge");
    }
    auto ack = decodeAcknowledge(frame->bytes);
    if (!ack) throw std::runtime_error("bad Acknowledge");
    auto limits = negotiateAsClient(TransportLimits{}, *ack);
    if (!limits) throw std::runtime_error("negotiation failed");
    return *limits;
}

void RawConnection::open(const std::function<void(TransportLimits&)>& misbehave) {
    TransportLimits limits = hello();
    if (misbehave) misbehave(limits);
    channel_.emplace(SecureChannel::Role::Client, limits, std::make_unique<SecurityPolicyNone>());
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, channel_->makeOpenRequest(SecurityTokenRequestType::Issue));
    auto frames = channel_->encodeMessage(MessageType::OpenChannel, nextRequestId(), body);
    if (!frames) throw std::runtime_error("encode OPN");
    for (auto& f : *frames) send(f);
    auto reply = readFrame();
    if (!reply) throw std::runtime_error("no OPN reply");
    auto message = channel_->receiveFrame(reply->bytes, std::chrono::steady_clock::now());
    if (!message || !message->has_value()) throw std::runtime_error("bad OPN reply");
    BinaryReader r((*message)->body);
    NodeId typeId;
    decode(r, typeId);
    OpenSecureChannelResponse response;
    decode(r, response);
    if (!r.ok() ||
        channel_->acceptOpenResponse(response, std::chrono::steady_clock::now()).isBad()) {
        throw std::runtime_error("OPN response rejected");
    }
}

std::optional<std::vector<std::uint8_t>> RawConnection::exchange(
    std::span<const std::uint8_t> body) {
    auto frames = channel_->encodeMessage(MessageType::Message, nextRequestId(), body);
    if (!frames) return std::nullopt;
    for (auto& f : *frames) send(f);
    for (int i = 0; i < 10'000; ++i) {  // bounded: a response has at most this many chunks
        auto frame = readFrame();
        if (!frame) return std::nullopt;
        auto message = channel_->receiveFrame(frame->bytes, std::chrono::steady_clock::now());
        if (!message) return std::nullopt;
        if (message->has_value()) return std::move((*message)->body);
    }
    return std::nullopt;
}

}  // namespace skillcell::test
