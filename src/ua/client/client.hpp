#pragma once
// Client: an OPC UA client over UA-TCP, as C++20 coroutines on an Asio executor. It speaks
// SecurityPolicy None and the RSA policies (Basic256Sha256, Aes128_Sha256_RsaOaep,
// Aes256_Sha256_RsaPss) with Sign or SignAndEncrypt, and authenticates its user anonymously,
// by user name and password, or by an X.509 certificate.
//
// One connection = one socket, one SecureChannel, at most one session. A reader coroutine
// owns the receive side and hands each response to the request waiting for its requestId,
// so any number of requests may be in flight at once. Every operation reports failure as a
// StatusCode (see README.md for the mapping of network errors); no exception escapes.
//
// Threading: a Client and everything it starts run on the executor given to the
// constructor, which must not run handlers concurrently (one thread, or a strand). Call
// its coroutines from that executor only; BlockingClient does this for plain threads.
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>

#include "ua/client/subscription.hpp"
#include "ua/crypto/primitives.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/messages/attribute.hpp"
#include "ua/messages/discovery.hpp"
#include "ua/messages/method.hpp"
#include "ua/messages/secure_channel.hpp"
#include "ua/messages/session.hpp"
#include "ua/messages/view.hpp"
#include "ua/transport/security_policy.hpp"
#include "ua/transport/tcp_framing.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

/// Good when the server's certificate (DER, possibly a chain) is trusted, else why not.
using ServerCertificateValidator =
    std::function<StatusCode(const ByteString& certificate, std::string* reason)>;

/// The user a session acts for.
struct UserCredentials {
    enum class Kind : std::uint8_t { Anonymous, UserName, Certificate };
    Kind kind = Kind::Anonymous;
    std::string userName;
    std::string password;
    ByteString certificate;  // Certificate: the user's DER certificate
    crypto::AsymmetricKey privateKey;
};

/// Who the client is and how it protects its traffic: the same for every connection an
/// application makes, so components keep one and copy it into each ClientConfig.
struct ClientSecurity {
    ClientSecurity() = default;  // not an aggregate: see ClientConfig

    /// The secure channel. kBestSecurity: the most secure endpoint the server offers among
    /// the policies we implement (SignAndEncrypt before Sign, then the server's
    /// securityLevel); None is chosen only when `allowNone` says so.
    std::string policyUri = std::string(kSecurityPolicyNoneUri);
    MessageSecurityMode mode = MessageSecurityMode::None;
    bool allowNone = false;
    /// Our application instance certificate and its key; needed by every policy but None.
    ByteString certificate;
    crypto::AsymmetricKey privateKey;
    /// A second certificate of ours, with a P-256 key (when `certificate` has an RSA one):
    /// with it the client may also use ECC_nistP256, and kBestSecurity prefers it. Once an
    /// ECC endpoint is chosen the client's copy swaps the two pairs (the channel and the
    /// handshake read `certificate`), and so the user's when the user is `certificate`.
    ByteString eccCertificate;
    crypto::AsymmetricKey eccPrivateKey;
    /// Decides whether to trust the server's certificate; unset: trusted (tests only).
    ServerCertificateValidator validateServerCertificate;
    UserCredentials user;

    [[nodiscard]] bool choosesEndpoint() const { return policyUri.empty(); }
};

/// ClientSecurity::policyUri meaning "choose the best endpoint the server offers".
inline constexpr std::string_view kBestSecurity{};

struct ClientConfig {
    // Not an aggregate on purpose: GCC 12 destroys a braced aggregate temporary twice when
    // it appears inside a co_await expression (`co_await client.connect(url, {})`).
    ClientConfig() = default;

    /// Covers name resolution, the TCP connect and the Hello/Acknowledge exchange.
    std::chrono::milliseconds connectTimeout{2000};
    /// Per request, from sending until its response arrived (also sent as timeoutHint).
    std::chrono::milliseconds requestTimeout{10000};
    /// What we offer in Hello; the server's Acknowledge may lower it.
    TransportLimits limits{};
    std::uint32_t tokenLifetimeMs = 600'000;
    double sessionTimeoutMs = 60'000;
    /// false: open only a secure channel (enough for GetEndpoints and FindServers).
    bool createSession = true;
    std::string applicationUri = "urn:skillcell:client";
    std::string productUri = "urn:skillcell";
    std::string applicationName = "skillcell client";
    std::string sessionName = "skillcell session";

    /// SecurityPolicy None and anonymous by default. The server's certificate is taken
    /// from its endpoint (fetched by GetEndpoints on a None discovery channel first)
    /// unless given here.
    ClientSecurity security;
    ByteString serverCertificate;
    /// The server's endpoints as the caller already has them from a GetEndpoints of this URL
    /// (a watcher that described an announced server): the endpoint and its certificate are
    /// chosen among these, and no discovery connection is opened. Empty: asked for.
    std::vector<EndpointDescription> endpoints;
};

/// The parts of "opc.tcp://host[:port][/path]"; host keeps no IPv6 brackets.
struct EndpointAddress {
    std::string host;
    std::uint16_t port = 4840;
    std::string path;  // with its leading '/', or empty
};

/// Parses an opc.tcp URL (scheme case-insensitive, port defaults to 4840, IPv6 hosts in
/// brackets). BadTcpEndpointUrlInvalid for anything else.
[[nodiscard]] Result<EndpointAddress> parseEndpointUrl(std::string_view url);

namespace client_detail {

struct Connection;  // client.cpp

/// A service message body: the type's binary encoding NodeId, then the structure.
template <EncodableStructure T>
[[nodiscard]] Result<std::vector<std::uint8_t>> encodeBody(const T& message) {
    std::vector<std::uint8_t> out;
    BinaryWriter w(out);
    encode(w, NodeId(T::kBinaryEncodingId));
    encode(w, message);
    if (!w.ok()) return w.status();
    return out;
}

/// Decodes a response body into Resp. A ServiceFault, or a response whose serviceResult is
/// Bad, gives that serviceResult; any other type gives BadUnknownResponse.
template <EncodableStructure Resp>
[[nodiscard]] Result<Resp> decodeBody(std::span<const std::uint8_t> body) {
    BinaryReader r(body);
    NodeId type;
    decode(r, type);
    if (!r.ok()) return status::BadDecodingError;
    if (type == NodeId(ServiceFault::kBinaryEncodingId)) {
        ServiceFault fault;
        decode(r, fault);
        if (!r.ok()) return status::BadDecodingError;
        const StatusCode s = fault.responseHeader.serviceResult;
        return s.isBad() ? s : status::BadUnknownResponse;
    }
    if (type != NodeId(Resp::kBinaryEncodingId)) return status::BadUnknownResponse;
    Resp response{};
    decode(r, response);
    if (!r.ok()) return r.status();
    if (r.remaining() != 0) return status::BadDecodingError;
    if (response.responseHeader.serviceResult.isBad()) {
        return response.responseHeader.serviceResult;
    }
    return response;
}

}  // namespace client_detail

class Client {
public:
    explicit Client(asio::any_io_executor executor);
    /// Aborts the connection without the closing handshake (use disconnect() for that).
    ~Client();
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    [[nodiscard]] asio::any_io_executor executor() const { return executor_; }

    /// Connects, opens the secure channel and, unless config.createSession is false, creates
    /// and activates a session for config.user. Good, or why not (the client is then
    /// disconnected): BadCertificateUntrusted and the other certificate codes for a server
    /// certificate the validator refuses, BadSecurityPolicyRejected when the server offers
    /// no endpoint with the policy and mode asked for, BadApplicationSignatureInvalid when
    /// the server cannot prove it holds its certificate's key, BadUserAccessDenied and
    /// BadIdentityTokenRejected for a user the server refuses. BadInvalidState when already
    /// connected.
    asio::awaitable<StatusCode> connect(std::string endpointUrl, ClientConfig config = {});
    /// CloseSession (if any), CloseSecureChannel, then closes the socket. Requests still in
    /// flight fail with BadConnectionClosed. Returns the CloseSession outcome; disconnecting
    /// a disconnected client is Good.
    asio::awaitable<StatusCode> disconnect();
    /// Drops the connection at once, without the closing handshake.
    void abort();

    [[nodiscard]] bool isConnected() const;
    /// Requests sent on the current connection (OpenSecureChannel included): what a test
    /// counts to see how many round trips a walk took.
    [[nodiscard]] std::uint64_t requestsSent() const;
    [[nodiscard]] bool hasSession() const { return !authenticationToken_.isNull(); }
    [[nodiscard]] const std::string& endpointUrl() const { return endpointUrl_; }
    /// The server's endpoints as returned by CreateSession.
    [[nodiscard]] const std::vector<EndpointDescription>& serverEndpoints() const {
        return serverEndpoints_;
    }
    [[nodiscard]] const NodeId& sessionId() const { return sessionId_; }
    /// The channel's security after connect (the chosen one, with kBestSecurity).
    [[nodiscard]] const std::string& securityPolicyUri() const {
        return config_.security.policyUri;
    }
    [[nodiscard]] MessageSecurityMode securityMode() const { return config_.security.mode; }

    /// Sends any request and waits for its response: fills the request header
    /// (authenticationToken, timestamp, requestHandle, timeoutHint), then maps every failure
    /// to a StatusCode: BadServerNotConnected, BadTimeout, BadConnectionClosed (or the ERR
    /// status the server sent), the ServiceFault's serviceResult, BadUnknownResponse,
    /// BadDecodingError, BadRequestCancelledByClient (when the awaiting coroutine is cancelled).
    template <EncodableStructure Req, EncodableStructure Resp>
    asio::awaitable<Result<Resp>> request(Req req) {
        return requestWithin<Req, Resp>(std::move(req), config_.requestTimeout);
    }
    /// request() with its own deadline (also sent as timeoutHint) instead of
    /// ClientConfig::requestTimeout: a Publish may rightly wait a whole keep-alive period.
    template <EncodableStructure Req, EncodableStructure Resp>
    asio::awaitable<Result<Resp>> requestWithin(Req req, std::chrono::milliseconds timeout) {
        fillRequestHeader(req.requestHeader, timeout);
        auto body = client_detail::encodeBody(req);
        if (!body) co_return body.status();
        auto reply = co_await exchange(MessageType::Message, std::move(*body), timeout);
        if (!reply) co_return reply.status();
        co_return client_detail::decodeBody<Resp>(*reply);
    }
    [[nodiscard]] std::chrono::milliseconds requestTimeout() const {
        return config_.requestTimeout;
    }

    // Discovery (need a secure channel only).
    asio::awaitable<Result<std::vector<EndpointDescription>>> getEndpoints(
        std::string endpointUrl = {});
    asio::awaitable<Result<std::vector<ApplicationDescription>>> findServers(
        std::string endpointUrl = {});

    // View.
    asio::awaitable<Result<BrowseResponse>> browse(BrowseRequest req);
    /// Browses one node; a Bad BrowseResult status becomes the error.
    /// referenceTypeId defaults to HierarchicalReferences (i=33).
    asio::awaitable<Result<BrowseResult>> browse(
        NodeId nodeId, BrowseDirection direction = BrowseDirection::Forward,
        NodeId referenceTypeId = NodeId(33), bool includeSubtypes = true,
        std::uint32_t nodeClassMask = 0);
    asio::awaitable<Result<BrowseNextResponse>> browseNext(BrowseNextRequest req);
    /// Continues one browse; releaseContinuationPoint frees it on the server instead.
    asio::awaitable<Result<BrowseResult>> browseNext(ByteString continuationPoint,
                                                     bool releaseContinuationPoint = false);
    asio::awaitable<Result<TranslateBrowsePathsToNodeIdsResponse>> translateBrowsePaths(
        TranslateBrowsePathsToNodeIdsRequest req);
    /// Follows browse names along hierarchical references from `start`; the first target.
    asio::awaitable<Result<NodeId>> translateBrowsePath(NodeId start,
                                                        std::vector<QualifiedName> path);
    asio::awaitable<Result<std::vector<NodeId>>> registerNodes(std::vector<NodeId> nodes);
    asio::awaitable<StatusCode> unregisterNodes(std::vector<NodeId> nodes);

    // Attribute.
    asio::awaitable<Result<ReadResponse>> read(ReadRequest req);
    /// One attribute; a Bad DataValue status becomes the error.
    asio::awaitable<Result<DataValue>> readAttribute(NodeId nodeId, AttributeId attribute);
    asio::awaitable<Result<Variant>> readValue(NodeId nodeId);
    asio::awaitable<Result<WriteResponse>> write(WriteRequest req);
    /// The per-node result of writing one attribute (or the request's failure).
    asio::awaitable<StatusCode> writeAttribute(NodeId nodeId, AttributeId attribute,
                                               DataValue value);
    asio::awaitable<StatusCode> writeValue(NodeId nodeId, Variant value);

    // Method.
    asio::awaitable<Result<CallResponse>> call(CallRequest req);
    /// Calls one method; its output arguments, or its Bad status.
    asio::awaitable<Result<std::vector<Variant>>> call(NodeId objectId, NodeId methodId,
                                                       std::vector<Variant> inputs);

    // Subscriptions (subscription.hpp; implemented in subscription.cpp).
    /// CreateSubscription; the returned Subscription adds monitored items and receives their
    /// notifications through a publish loop this Client runs while subscriptions exist.
    /// `onStatusChange` hears what happens to the subscription: a StatusChangeNotification,
    /// BadTimeout from the keep-alive watchdog (then Good when the server is heard again),
    /// BadMessageNotAvailable when notifications were lost in a gap that Republish could not
    /// fill (the subscription goes on), or the status with which the session or connection
    /// was lost (the last call).
    asio::awaitable<Result<std::shared_ptr<Subscription>>> createSubscription(
        SubscriptionSettings settings, Subscription::StatusCallback onStatusChange = {});

private:
    using Connection = client_detail::Connection;

    void fillRequestHeader(RequestHeader& header);
    void fillRequestHeader(RequestHeader& header, std::chrono::milliseconds timeout);
    /// Sends one message body and waits (up to `timeout`) for the reply body with the same
    /// requestId.
    asio::awaitable<Result<std::vector<std::uint8_t>>> exchange(MessageType type,
                                                                std::vector<std::uint8_t> body,
                                                                std::chrono::milliseconds timeout);
    /// Stops the publish loop without calling the status callbacks (disconnect, abort).
    void endSubscriptions(StatusCode reason);
    asio::awaitable<StatusCode> createAndActivateSession();
    /// Secured connects: checks our key, fetches the server's certificate from its
    /// endpoints when not given (GetEndpoints on a None discovery channel) and asks the
    /// validator whether to trust it.
    asio::awaitable<StatusCode> prepareSecurity();
    void resetSession();

    asio::any_io_executor executor_;
    std::shared_ptr<Connection> conn_;
    ClientConfig config_;
    std::string endpointUrl_;
    NodeId authenticationToken_;
    NodeId sessionId_;
    std::vector<EndpointDescription> serverEndpoints_;
    std::uint32_t nextRequestHandle_ = 1;
    std::shared_ptr<client_detail::SubscriptionEngine> subscriptions_;
};

}  // namespace skillcell::ua
