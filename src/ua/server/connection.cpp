#include "ua/server/connection.hpp"

#include <algorithm>
#include <cstring>

#include <spdlog/spdlog.h>

#include "ua/messages/secure_channel.hpp"
#include "ua/server/request_dispatch.hpp"
#include "ua/transport/no_throw.hpp"

namespace skillcell::ua {
namespace {

// Errors as values: a closed socket is normal control flow here, not an exception.

struct Frame {
    MessageHeader header;
    std::span<const std::uint8_t> bytes;
};

SteadyTime steadyNow() {
    return std::chrono::steady_clock::now();
}

}  // namespace

Connection::Connection(asio::ip::tcp::socket socket, ConnectionEnvironment env,
                       std::uint32_t channelId)
    : socket_(std::move(socket)),
      env_(env),
      channelId_(channelId),
      limits_(env.limits.transport),
      in_(std::max<std::size_t>(env.limits.transport.receiveBufferSize, kMinBufferSize)),
      deadlineTimer_(socket_.get_executor()) {}

asio::awaitable<void> Connection::run() {
    auto self = shared_from_this();
    asio::error_code ignored;
    socket_.set_option(asio::ip::tcp::no_delay(true), ignored);  // request/response latency
    if (auto ep = socket_.remote_endpoint(ignored); !ignored) {
        peer_ = ep.address().to_string() + ":" + std::to_string(ep.port());
    }
    spdlog::debug("channel {}: connection from {}", channelId_, peer_);
    setDeadline(steadyNow() + std::chrono::milliseconds(env_.limits.helloTimeoutMs));
    auto executor = co_await asio::this_coro::executor;
    asio::co_spawn(
        executor, [self] { return self->watchdog(); }, asio::detached);

    const StatusCode result = co_await serve();
    if (result.isBad() && result != status::BadConnectionClosed) {
        fail(result, statusName(result));
    } else {
        closing_ = true;
        if (!writing_) writeQueued();  // nothing in flight: close now
    }
}

void Connection::close() {
    asio::error_code ignored;
    socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
    deadlineTimer_.cancel();
}

asio::awaitable<StatusCode> Connection::serve() {
    auto readOne = [this](std::uint32_t maxSize) -> asio::awaitable<Result<Frame>> {
        auto bytes = co_await readFrame(maxSize);
        if (!bytes) co_return bytes.status();
        auto header = parseMessageHeader(bytes->first<kMessageHeaderSize>(), maxSize);
        if (!header) co_return header.status();
        co_return Frame{*header, *bytes};
    };

    // 1. Hello. Anything else first is a protocol error.
    auto hello = co_await readOne(env_.limits.transport.receiveBufferSize);
    if (!hello) co_return hello.status();
    if (hello->header.type != MessageType::Hello) co_return status::BadTcpMessageTypeInvalid;
    if (const StatusCode s = handleHello(hello->bytes); s.isBad()) co_return s;
    // The client picks policy and mode among the offered endpoints in its first OPN.
    SecureChannelConfig channelConfig = env_.channelConfig;
    channelConfig.acceptsMode = [&description = env_.description](std::string_view uri,
                                                                  MessageSecurityMode mode) {
        return description.offers(uri, mode) ||
               (uri == kSecurityPolicyNoneUri && mode == MessageSecurityMode::None);
    };
    auto selector = [this](const AsymmetricSecurityHeader& header) {
        const std::string who = "channel " + std::to_string(channelId_) + " (" + peer_ + ")";
        return selectPolicy(env_.description.securityEndpoints, env_.security,
                            env_.description.certificateFor(header.securityPolicyUri), header, who);
    };
    channel_.emplace(limits_, selector, channelConfig);

    // 2. Secure channel messages until the peer closes the channel or the connection.
    for (;;) {
        auto frame = co_await readOne(limits_.receiveBufferSize);
        if (!frame) co_return frame.status();
        const auto type = frame->header.type;
        if (type != MessageType::OpenChannel && type != MessageType::Message &&
            type != MessageType::CloseChannel) {
            co_return status::BadTcpMessageTypeInvalid;
        }
        const SteadyTime now = steadyNow();
        auto received = channel_->receiveFrame(frame->bytes, now);
        if (!received) co_return received.status();
        if (!received->has_value()) continue;  // more chunks to come
        const ChannelMessage& message = **received;
        StatusCode s = status::Good;
        switch (message.type) {
            case MessageType::OpenChannel:
                s = handleOpen(message, now);
                break;
            case MessageType::Message:
                s = handleMessage(message, now);
                break;
            case MessageType::CloseChannel:
                spdlog::debug("channel {} ({}): closed by the client", channelId_, peer_);
                co_return status::BadConnectionClosed;
            default:
                s = status::BadTcpMessageTypeInvalid;
                break;
        }
        if (s.isBad()) co_return s;
    }
}

asio::awaitable<Result<std::span<const std::uint8_t>>> Connection::readFrame(
    std::uint32_t maxSize) {
    // Reads as much as the socket has into one buffer and cuts frames out of it, so that a
    // request usually costs one read system call.
    auto fill = [this](std::size_t need) -> asio::awaitable<bool> {
        while (inEnd_ - inBegin_ < need) {
            if (in_.size() - inBegin_ < need) {
                std::memmove(in_.data(), in_.data() + inBegin_, inEnd_ - inBegin_);
                inEnd_ -= inBegin_;
                inBegin_ = 0;
                if (in_.size() < need) in_.resize(need);
            }
            auto [ec, n] = co_await socket_.async_read_some(
                asio::buffer(in_.data() + inEnd_, in_.size() - inEnd_), kNoThrow);
            if (ec) co_return false;
            inEnd_ += n;
        }
        co_return true;
    };
    if (!co_await fill(kMessageHeaderSize)) co_return status::BadConnectionClosed;
    auto header = parseMessageHeader(std::span<const std::uint8_t, kMessageHeaderSize>(
                                         in_.data() + inBegin_, kMessageHeaderSize),
                                     maxSize);
    if (!header) co_return header.status();
    if (!co_await fill(header->size)) co_return status::BadConnectionClosed;
    std::span<const std::uint8_t> frame(in_.data() + inBegin_, header->size);
    inBegin_ += header->size;
    co_return frame;
}

StatusCode Connection::handleHello(std::span<const std::uint8_t> frame) {
    HelloMessage hello;
    if (const StatusCode s = decodeFromBytes(frame.subspan(kMessageHeaderSize), hello); s.isBad()) {
        return s;
    }
    auto negotiated = negotiateAsServer(env_.limits.transport, hello);
    if (!negotiated) return negotiated.status();
    limits_ = negotiated->limits;
    endpointUrl_ = hello.endpointUrl;
    spdlog::debug("channel {} ({}): hello for '{}', buffers {}/{}", channelId_, peer_, endpointUrl_,
                  limits_.receiveBufferSize, limits_.sendBufferSize);
    send(encodeAcknowledge(negotiated->ack));
    return status::Good;
}

StatusCode Connection::handleOpen(const ChannelMessage& message, SteadyTime now) {
    BinaryReader r(message.body);
    NodeId typeId;
    decode(r, typeId);
    OpenSecureChannelRequest request;
    decode(r, request);
    if (!r.ok()) return r.status();
    if (typeId != NodeId(OpenSecureChannelRequest::kBinaryEncodingId) || r.remaining() != 0) {
        return status::BadDecodingError;
    }
    auto response = channel_->openOrRenew(request, channelId_, now);
    if (!response) return response.status();
    response->responseHeader.timestamp = DateTime::now();
    response->responseHeader.requestHandle = request.requestHeader.requestHandle;
    // A channel whose token expires without renewal is closed (OPC 10000-6, 6.7.4: the
    // token stays valid for 125% of its lifetime).
    setDeadline(now +
                std::chrono::milliseconds(
                    static_cast<std::int64_t>(response->securityToken.revisedLifetime) * 5 / 4));
    std::vector<std::uint8_t> body;
    encodeServiceMessage(body, *response);
    return sendMessage(MessageType::OpenChannel, message.requestId,
                       request.requestHeader.requestHandle, std::move(body));
}

StatusCode Connection::handleMessage(const ChannelMessage& message, SteadyTime now) {
    RequestChannel channel;
    channel.channelId = channelId_;
    channel.endpointUrl = &endpointUrl_;
    if (const SecurityPolicy* policy = channel_->policy(); policy != nullptr) {
        channel.securityPolicyUri = policy->uri();
        channel.clientCertificate = &policy->remoteCertificate();
        channel.clientKey = policy->remoteKey();
    }
    channel.securityMode = channel_->securityMode();
    channel.discoveryOnly = discoveryOnly();
    // A deferred service answers through this later; the weak reference makes an answer
    // after the connection closed a no-op instead of keeping the connection alive.
    const ReplyFactory replyFor = [this, requestId = message.requestId](std::uint32_t handle) {
        return ResponseSender(
            [weak = weak_from_this(), requestId, handle](std::vector<std::uint8_t> body) {
                if (auto self = weak.lock()) self->sendDeferred(requestId, handle, std::move(body));
            });
    };
    auto served = dispatchRequest(env_.services, env_.sessions, env_.limits, channel, message.body,
                                  now, replyFor);
    if (served.status.isBad()) return served.status;
    if (served.response.empty()) return status::Good;  // deferred: answered through the sender
    return sendMessage(MessageType::Message, message.requestId, served.requestHandle,
                       std::move(served.response));
}

bool Connection::discoveryOnly() const {
    return channel_->securityMode() == MessageSecurityMode::None &&
           !env_.description.offers(kSecurityPolicyNoneUri, MessageSecurityMode::None);
}

StatusCode Connection::sendMessage(MessageType type, std::uint32_t requestId,
                                   std::uint32_t requestHandle, std::vector<std::uint8_t> body) {
    auto frames = channel_->encodeMessage(type, requestId, body);
    if (!frames && type == MessageType::Message) {
        // Too large for what the client accepts: tell it so instead of dropping the channel.
        frames = channel_->encodeMessage(type, requestId,
                                         encodeServiceFault(requestHandle, frames.status()));
    }
    if (!frames) return frames.status();
    for (auto& f : *frames) send(std::move(f));
    return status::Good;
}

void Connection::sendDeferred(std::uint32_t requestId, std::uint32_t requestHandle,
                              std::vector<std::uint8_t> body) {
    if (closing_ || !channel_ || !socket_.is_open()) return;
    const StatusCode s =
        sendMessage(MessageType::Message, requestId, requestHandle, std::move(body));
    if (s.isBad()) fail(s, statusName(s));
}

void Connection::send(std::vector<std::uint8_t> frame) {
    out_.push_back(std::move(frame));
    if (!writing_) writeQueued();
}

void Connection::fail(StatusCode status, std::string_view reason) {
    if (closing_) return;
    spdlog::warn("channel {} ({}): closing with {}: {}", channelId_, peer_, statusName(status),
                 reason);
    closing_ = true;  // the write chain closes the socket once the ERR is out
    send(encodeError(status, reason));
}

void Connection::setDeadline(SteadyTime deadline) {
    const bool earlier = deadline < deadline_;
    deadline_ = deadline;
    if (earlier) deadlineTimer_.cancel();
}

void Connection::writeQueued() {
    if (out_.empty() || !socket_.is_open()) {
        if (closing_) close();
        return;
    }
    // Everything queued goes out in one gathered write. Initiating it here, not in a writer
    // coroutine woken by a signal, lets Asio write at once when the socket takes it: the
    // response leaves before the reader loop continues, without a trip through the
    // scheduler.
    writing_ = true;
    const std::size_t count = out_.size();
    writeBuffers_.clear();
    for (const auto& f : out_) writeBuffers_.emplace_back(asio::buffer(f));
    asio::async_write(socket_, writeBuffers_,
                      [self = shared_from_this(), count](asio::error_code ec, std::size_t) {
                          self->writing_ = false;
                          if (ec) {
                              self->close();
                              return;
                          }
                          // Frames queued meanwhile sit behind these; deque keeps them put.
                          self->out_.erase(self->out_.begin(),
                                           self->out_.begin() + static_cast<std::ptrdiff_t>(count));
                          self->writeQueued();
                      });
}

asio::awaitable<void> Connection::watchdog() {
    while (socket_.is_open() && !closing_) {
        deadlineTimer_.expires_at(deadline_);
        co_await deadlineTimer_.async_wait(kNoThrow);
        if (!socket_.is_open() || closing_) break;
        if (deadline_ <= steadyNow()) {
            fail(status::BadTimeout, "connection timed out");
            break;
        }
    }
}

}  // namespace skillcell::ua
