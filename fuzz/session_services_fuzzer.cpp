// Stateful fuzzing of a real server's services, the way a client's session drives them, without
// a socket (dispatchRequest, what a Connection calls). Each input opens a session
// (CreateSession, then ActivateSession as anonymous), sends the service requests the input
// describes in that session, and closes it with its subscriptions. What a request leaves
// behind carries to the next ones of the input: subscriptions, monitored items, queued
// publish requests, continuation points, registered nodes, written values. The stateless
// fuzz_message_decoder never reaches that.
//
// The input is a sequence of requests, each
//   [service: 1 byte][length: 2 bytes, little-endian][the request after its RequestHeader]
// The harness writes the type id and a valid RequestHeader (the session's token, a new request
// handle), so the fuzzed bytes reach the service rather than stopping at the session check.
// Ready handlers run after each request (a publish answered, a monitored item sampled).
// A crash, a sanitizer report or a runaway allocation is a finding.
#include <spdlog/spdlog.h>

#include <array>
#include <asio/io_context.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ua/messages/attribute.hpp"
#include "ua/messages/discovery.hpp"
#include "ua/messages/method.hpp"
#include "ua/messages/session.hpp"
#include "ua/messages/subscription.hpp"
#include "ua/messages/view.hpp"
#include "ua/server/request_dispatch.hpp"
#include "ua/server/server.hpp"

using namespace skillcell::ua;

namespace {

// The services an input may call, by its first byte (modulo their count).
constexpr std::array kServices = {
    ReadRequest::kBinaryEncodingId,
    WriteRequest::kBinaryEncodingId,
    BrowseRequest::kBinaryEncodingId,
    BrowseNextRequest::kBinaryEncodingId,
    TranslateBrowsePathsToNodeIdsRequest::kBinaryEncodingId,
    RegisterNodesRequest::kBinaryEncodingId,
    UnregisterNodesRequest::kBinaryEncodingId,
    CallRequest::kBinaryEncodingId,
    CreateSubscriptionRequest::kBinaryEncodingId,
    ModifySubscriptionRequest::kBinaryEncodingId,
    SetPublishingModeRequest::kBinaryEncodingId,
    DeleteSubscriptionsRequest::kBinaryEncodingId,
    CreateMonitoredItemsRequest::kBinaryEncodingId,
    ModifyMonitoredItemsRequest::kBinaryEncodingId,
    SetMonitoringModeRequest::kBinaryEncodingId,
    DeleteMonitoredItemsRequest::kBinaryEncodingId,
    PublishRequest::kBinaryEncodingId,
    RepublishRequest::kBinaryEncodingId,
    GetEndpointsRequest::kBinaryEncodingId,
    FindServersRequest::kBinaryEncodingId,
};

class Harness {
public:
    Harness() {
        spdlog::set_level(spdlog::level::off);
        ServerConfig config;
        config.bindAddress = "127.0.0.1";
        config.description.port = 0;
        config.description.advertisedHost = "127.0.0.1";
        std::string error;
        server_ = Server::create(io_, std::move(config), &error);
        if (!server_) std::abort();  // the harness itself is broken
    }

    // One input: a session, its requests, its end.
    void run(std::span<const std::uint8_t> data) {
        CreateSessionRequest create;
        create.requestHeader.requestHandle = ++handle_;
        create.sessionName = "fuzz";
        create.requestedSessionTimeout = 60000;
        CreateSessionResponse created;
        if (!call(create, created)) std::abort();  // the server refuses a plain session
        token_ = created.authenticationToken;
        ActivateSessionRequest activate;
        activate.requestHeader = header();
        ActivateSessionResponse activated;
        if (!call(activate, activated)) std::abort();

        while (data.size() >= 3) {
            const std::uint32_t type = kServices[data[0] % kServices.size()];
            const std::size_t length =
                std::min<std::size_t>(data[1] | (std::size_t{data[2]} << 8U), data.size() - 3);
            std::vector<std::uint8_t> body;
            BinaryWriter w(body);
            encode(w, NodeId(type));
            encode(w, header());
            body.insert(body.end(), data.begin() + 3,
                        data.begin() + static_cast<std::ptrdiff_t>(3 + length));
            (void)dispatch(body);
            data = data.subspan(3 + length);
        }

        CloseSessionRequest close;
        close.requestHeader = header();
        close.deleteSubscriptions = true;
        CloseSessionResponse closed;
        if (!call(close, closed)) std::abort();  // a session the server can no longer close
    }

private:
    RequestHeader header() {
        RequestHeader h;
        h.authenticationToken = token_;
        h.timestamp = DateTime::now();
        h.requestHandle = ++handle_;
        return h;
    }

    DispatchedRequest dispatch(std::span<const std::uint8_t> body) {
        const ConnectionEnvironment env = server_->environment();
        RequestChannel channel;
        channel.channelId = 1;
        channel.endpointUrl = &endpointUrl_;
        auto served = dispatchRequest(
            env.services, env.sessions, env.limits, channel, body, std::chrono::steady_clock::now(),
            [](std::uint32_t) { return ResponseSender([](std::vector<std::uint8_t>) {}); });
        io_.poll();  // what the request made ready: a publish answered, a sample taken
        io_.restart();
        return served;
    }

    // Sends a well-formed request; whether the server answered it with its response.
    template <class Request, class Response>
    bool call(const Request& request, Response& response) {
        std::vector<std::uint8_t> body;
        encodeServiceMessage(body, request);
        const auto served = dispatch(body);
        BinaryReader r(served.response);
        NodeId typeId;
        decode(r, typeId);
        if (!r.ok() || typeId != NodeId(Response::kBinaryEncodingId)) return false;
        decode(r, response);
        return r.ok() && response.responseHeader.serviceResult.isGood();
    }

    asio::io_context io_;
    std::unique_ptr<Server> server_;
    std::string endpointUrl_ = "opc.tcp://127.0.0.1:4840";
    NodeId token_;
    std::uint32_t handle_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static Harness harness;  // one server for the whole run; each input is its own session
    harness.run(std::span<const std::uint8_t>(data, size));
    return 0;
}
