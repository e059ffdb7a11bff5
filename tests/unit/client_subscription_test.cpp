// Client subscriptions against a fake server on our SecureChannel (server role) whose
// Publish answers each test scripts: dispatch by clientHandle, event fields, acknowledgements
// in the next Publish, Republish on a gap, a Publish timeout survived (and the watchdog's
// report), a lost session and a dropped connection reported, BadNoSubscription, and the
// BlockingClient facade.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/post.hpp>
#include <asio/read.hpp>
#include <asio/use_awaitable.hpp>
#include <asio/write.hpp>

#include "ua/client/blocking_client.hpp"
#include "ua/client/client.hpp"
#include "ua/client/subscription.hpp"
#include "ua/transport/secure_channel.hpp"

namespace skillcell::ua::client_subscription_test {
namespace {

using asio::ip::tcp;
using namespace std::chrono_literals;
constexpr auto kNoThrow = asio::experimental::as_tuple(asio::use_awaitable);
constexpr std::uint32_t kSubscriptionId = 7;

/// Runs the io_context until `done()` or a safety deadline, so that a hang fails the test
/// instead of blocking the run.
bool runUntil(asio::io_context& io, const std::function<bool()>& done,
              std::chrono::milliseconds limit = 10s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done() && std::chrono::steady_clock::now() < deadline) {
        io.run_for(10ms);
        if (io.stopped()) io.restart();
    }
    return done();
}

asio::awaitable<std::vector<std::uint8_t>> readRawFrame(tcp::socket& s) {
    std::vector<std::uint8_t> frame(kMessageHeaderSize);
    auto [ec, n] = co_await asio::async_read(s, asio::buffer(frame), kNoThrow);
    if (ec) co_return std::vector<std::uint8_t>{};
    std::uint32_t size = 0;
    std::memcpy(&size, frame.data() + 4, 4);
    if (size < kMessageHeaderSize) co_return std::vector<std::uint8_t>{};
    frame.resize(size);
    auto [ec2, n2] = co_await asio::async_read(
        s, asio::buffer(frame.data() + kMessageHeaderSize, size - kMessageHeaderSize), kNoThrow);
    if (ec2) co_return std::vector<std::uint8_t>{};
    co_return frame;
}

template <class T>
T decodeAs(const std::vector<std::uint8_t>& body) {
    BinaryReader r(body);
    NodeId type;
    decode(r, type);
    T out;
    decode(r, out);
    return out;
}

NotificationMessage dataChange(std::uint32_t seq,
                               std::vector<std::pair<std::uint32_t, double>> values) {
    DataChangeNotification n;
    for (auto& [handle, v] : values) {
        MonitoredItemNotification item;
        item.clientHandle = handle;
        item.value.value = Variant(v);
        n.monitoredItems.push_back(std::move(item));
    }
    NotificationMessage msg;
    msg.sequenceNumber = seq;
    msg.publishTime = DateTime::now();
    msg.notificationData.push_back(toExtensionObject(n));
    return msg;
}

/// A session-capable server whose subscription services are answered here and whose
/// Publish requests wait in `waiting` until the test answers them (or never does).
class FakeServer {
public:
    explicit FakeServer(asio::io_context& io)
        : io_(io), acceptor_(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0)), socket_(io) {
        asio::co_spawn(io, serve(), asio::detached);
    }

    [[nodiscard]] std::string url() const {
        return "opc.tcp://127.0.0.1:" + std::to_string(acceptor_.local_endpoint().port());
    }

    /// Answers the oldest waiting Publish with `msg`; false when none waits.
    bool publish(NotificationMessage msg, std::uint32_t subscriptionId = kSubscriptionId) {
        if (waiting.empty()) return false;
        const auto id = waiting.front();
        waiting.pop_front();
        PublishResponse resp;
        resp.subscriptionId = subscriptionId;
        resp.notificationMessage = std::move(msg);
        reply(id, resp);
        return true;
    }
    /// Answers the oldest waiting Publish with a ServiceFault.
    bool publishFault(StatusCode s) {
        if (waiting.empty()) return false;
        const auto id = waiting.front();
        waiting.pop_front();
        fault(id, s);
        return true;
    }
    void drop() {
        std::error_code ignored;
        socket_.close(ignored);
    }

    // What the client sent.
    std::deque<std::uint32_t> waiting;  // requestIds of unanswered Publish requests
    int publishCount = 0;
    std::vector<std::vector<SubscriptionAcknowledgement>> acksPerPublish;
    std::vector<CreateSubscriptionRequest> createSubscriptions;
    std::vector<MonitoredItemCreateRequest> createdItems;
    std::vector<std::uint32_t> republished;  // retransmitSequenceNumber, in order
    std::vector<std::uint32_t> deletedSubscriptions;
    int readCount = 0;
    /// Messages a Republish may return, by sequence number.
    std::map<std::uint32_t, NotificationMessage> retained;

private:
    template <EncodableStructure Resp>
    void reply(std::uint32_t requestId, Resp response) {
        auto body = client_detail::encodeBody(response);
        ASSERT_TRUE(body);
        send(MessageType::Message, requestId, *body);
    }
    void fault(std::uint32_t requestId, StatusCode s) {
        ServiceFault f;
        f.responseHeader.serviceResult = s;
        reply(requestId, f);
    }

    void send(MessageType type, std::uint32_t requestId, std::span<const std::uint8_t> body) {
        if (!socket_.is_open()) return;
        auto frames = channel_->encodeMessage(type, requestId, body);
        ASSERT_TRUE(frames);
        for (auto& f : *frames) out_.push_back(std::move(f));
        if (!writing_) {
            writing_ = true;
            asio::co_spawn(io_, writeAll(), asio::detached);
        }
    }

    asio::awaitable<void> writeAll() {
        while (!out_.empty()) {
            auto f = std::move(out_.front());
            out_.pop_front();
            auto [ec, n] = co_await asio::async_write(socket_, asio::buffer(f), kNoThrow);
            if (ec) break;
        }
        writing_ = false;
    }

    void handle(std::uint32_t requestId, const NodeId& type,
                const std::vector<std::uint8_t>& body) {
        if (type == NodeId(CreateSessionRequest::kBinaryEncodingId)) {
            CreateSessionResponse resp;
            resp.sessionId = NodeId(1, "session");
            resp.authenticationToken = NodeId(1, "token");
            resp.revisedSessionTimeout = 60000;
            reply(requestId, resp);
        } else if (type == NodeId(ActivateSessionRequest::kBinaryEncodingId)) {
            reply(requestId, ActivateSessionResponse{});
        } else if (type == NodeId(CloseSessionRequest::kBinaryEncodingId)) {
            reply(requestId, CloseSessionResponse{});
        } else if (type == NodeId(CreateSubscriptionRequest::kBinaryEncodingId)) {
            auto req = decodeAs<CreateSubscriptionRequest>(body);
            CreateSubscriptionResponse resp;
            resp.subscriptionId =
                kSubscriptionId + static_cast<std::uint32_t>(createSubscriptions.size());
            resp.revisedPublishingInterval = req.requestedPublishingInterval;
            resp.revisedLifetimeCount = req.requestedLifetimeCount;
            resp.revisedMaxKeepAliveCount = req.requestedMaxKeepAliveCount;
            createSubscriptions.push_back(std::move(req));
            reply(requestId, resp);
        } else if (type == NodeId(CreateMonitoredItemsRequest::kBinaryEncodingId)) {
            auto req = decodeAs<CreateMonitoredItemsRequest>(body);
            CreateMonitoredItemsResponse resp;
            for (auto& item : req.itemsToCreate) {
                MonitoredItemCreateResult r;
                r.monitoredItemId = 100 + static_cast<std::uint32_t>(createdItems.size());
                r.revisedSamplingInterval = item.requestedParameters.samplingInterval;
                r.revisedQueueSize = item.requestedParameters.queueSize;
                createdItems.push_back(std::move(item));
                resp.results.push_back(std::move(r));
            }
            reply(requestId, resp);
        } else if (type == NodeId(PublishRequest::kBinaryEncodingId)) {
            auto req = decodeAs<PublishRequest>(body);
            ++publishCount;
            acksPerPublish.push_back(req.subscriptionAcknowledgements);
            waiting.push_back(requestId);
        } else if (type == NodeId(RepublishRequest::kBinaryEncodingId)) {
            auto req = decodeAs<RepublishRequest>(body);
            republished.push_back(req.retransmitSequenceNumber);
            auto it = retained.find(req.retransmitSequenceNumber);
            if (it == retained.end()) {
                fault(requestId, status::BadMessageNotAvailable);
            } else {
                RepublishResponse resp;
                resp.notificationMessage = it->second;
                reply(requestId, resp);
            }
        } else if (type == NodeId(DeleteSubscriptionsRequest::kBinaryEncodingId)) {
            auto req = decodeAs<DeleteSubscriptionsRequest>(body);
            DeleteSubscriptionsResponse resp;
            for (auto id : req.subscriptionIds) {
                deletedSubscriptions.push_back(id);
                resp.results.push_back(status::Good);
            }
            reply(requestId, resp);
        } else if (type == NodeId(ReadRequest::kBinaryEncodingId)) {
            ++readCount;
            ReadResponse resp;
            resp.results.push_back(DataValue{});
            reply(requestId, resp);
        } else {
            fault(requestId, status::BadServiceUnsupported);
        }
    }

    asio::awaitable<void> serve() {
        auto [ec] = co_await acceptor_.async_accept(socket_, kNoThrow);
        if (ec) co_return;
        auto hello = decodeHello(co_await readRawFrame(socket_));
        if (!hello) co_return;
        auto negotiated = negotiateAsServer(TransportLimits{}, *hello);
        if (!negotiated) co_return;
        const auto ack = encodeAcknowledge(negotiated->ack);
        co_await asio::async_write(socket_, asio::buffer(ack), kNoThrow);
        channel_.emplace(SecureChannel::Role::Server, negotiated->limits,
                         std::make_unique<SecurityPolicyNone>());
        for (;;) {
            auto frame = co_await readRawFrame(socket_);
            if (frame.empty()) co_return;
            auto message = channel_->receiveFrame(frame, std::chrono::steady_clock::now());
            if (!message || !message->has_value()) continue;
            auto& m = **message;
            if (m.type == MessageType::CloseChannel) continue;
            BinaryReader r(m.body);
            NodeId type;
            decode(r, type);
            if (m.type == MessageType::OpenChannel) {
                OpenSecureChannelRequest req;
                decode(r, req);
                auto resp = channel_->openOrRenew(req, 42, std::chrono::steady_clock::now());
                if (!resp) co_return;
                auto body = client_detail::encodeBody(*resp);
                send(MessageType::OpenChannel, m.requestId, *body);
                continue;
            }
            handle(m.requestId, type, m.body);
        }
    }

    asio::io_context& io_;
    tcp::acceptor acceptor_;
    tcp::socket socket_;
    std::optional<SecureChannel> channel_;
    std::deque<std::vector<std::uint8_t>> out_;
    bool writing_ = false;
};

/// Connects and creates one subscription; the test body continues with `sub`.
struct Fixture {
    explicit Fixture(SubscriptionSettings settings = SubscriptionSettings(100, 150, 50),
                     std::chrono::milliseconds requestTimeout = 5s)
        : server(io), client(io.get_executor()) {
        ClientConfig config;
        config.requestTimeout = requestTimeout;
        bool done = false;
        asio::co_spawn(
            io,
            [&]() -> asio::awaitable<void> {
                if ((co_await client.connect(server.url(), config)).isGood()) {
                    auto created = co_await client.createSubscription(
                        settings, [this](StatusCode s) { statuses.push_back(s); });
                    if (created) sub = *created;
                }
                done = true;
            },
            asio::detached);
        runUntil(io, [&] { return done; });
    }

    /// Runs `f` (a coroutine of the test) on the io_context to its end.
    template <class F>
    void run(F f) {
        bool done = false;
        asio::co_spawn(
            io,
            [&]() -> asio::awaitable<void> {
                co_await f();
                done = true;
            },
            asio::detached);
        ASSERT_TRUE(runUntil(io, [&] { return done; }));
    }

    asio::io_context io;
    FakeServer server;
    Client client;
    std::shared_ptr<Subscription> sub;
    std::vector<StatusCode> statuses;
};

bool hasAck(const std::vector<SubscriptionAcknowledgement>& acks, std::uint32_t seq) {
    return std::any_of(acks.begin(), acks.end(), [seq](const auto& a) {
        return a.subscriptionId == kSubscriptionId && a.sequenceNumber == seq;
    });
}

TEST(ClientSubscription, DataChangesReachTheirItemsAndAreAcknowledged) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    EXPECT_EQ(f.sub->id(), kSubscriptionId);
    ASSERT_EQ(f.server.createSubscriptions.size(), 1u);
    EXPECT_EQ(f.server.createSubscriptions[0].requestedPublishingInterval, 100);
    EXPECT_EQ(f.server.createSubscriptions[0].requestedMaxKeepAliveCount, 50u);

    std::vector<double> first;
    std::vector<double> second;
    std::optional<Result<Subscription::MonitoredItem>> a;
    std::optional<Result<Subscription::MonitoredItem>> b;
    f.run([&]() -> asio::awaitable<void> {
        a = co_await f.sub->monitorDataChange(
            NodeId(1, "a"), AttributeId::Value, 50, 1, std::nullopt,
            [&](const DataValue& dv) { first.push_back(*dv.value->get<double>()); });
        DataChangeFilter filter;
        filter.trigger = DataChangeTrigger::StatusValueTimestamp;
        b = co_await f.sub->monitorDataChange(
            NodeId(1, "b"), AttributeId::Value, 50, 4, filter,
            [&](const DataValue& dv) { second.push_back(*dv.value->get<double>()); });
    });
    ASSERT_TRUE(a && *a && b && *b);
    EXPECT_NE((*a)->clientHandle, (*b)->clientHandle);
    ASSERT_EQ(f.server.createdItems.size(), 2u);
    EXPECT_EQ(f.server.createdItems[1].requestedParameters.queueSize, 4u);
    DataChangeFilter sent;
    ASSERT_TRUE(
        fromExtensionObject(f.server.createdItems[1].requestedParameters.filter, sent).isGood());
    EXPECT_EQ(sent.trigger, DataChangeTrigger::StatusValueTimestamp);

    // At least two Publish requests wait at the server while a subscription exists.
    ASSERT_TRUE(runUntil(f.io, [&] { return f.server.waiting.size() >= 2; }));
    // One message for both items, in the other order than they were created.
    ASSERT_TRUE(
        f.server.publish(dataChange(1, {{(*b)->clientHandle, 2.5}, {(*a)->clientHandle, 1.5}})));
    ASSERT_TRUE(runUntil(f.io, [&] { return !first.empty() && !second.empty(); }));
    EXPECT_EQ(first, std::vector<double>{1.5});
    EXPECT_EQ(second, std::vector<double>{2.5});

    // The next Publish acknowledges sequence number 1; an unknown clientHandle is ignored.
    ASSERT_TRUE(runUntil(f.io, [&] {
        return !f.server.acksPerPublish.empty() && hasAck(f.server.acksPerPublish.back(), 1);
    }));
    ASSERT_TRUE(f.server.publish(dataChange(2, {{999, 9.0}, {(*a)->clientHandle, 3.5}})));
    ASSERT_TRUE(runUntil(f.io, [&] { return first.size() == 2; }));
    EXPECT_EQ(first.back(), 3.5);
    EXPECT_EQ(second.size(), 1u);
    ASSERT_TRUE(runUntil(f.io, [&] {
        return !f.server.acksPerPublish.empty() && hasAck(f.server.acksPerPublish.back(), 2);
    }));
    // A keep-alive is not acknowledged.
    NotificationMessage keepAlive;
    keepAlive.sequenceNumber = 3;
    const auto before = f.server.publishCount;
    ASSERT_TRUE(f.server.publish(keepAlive));
    ASSERT_TRUE(runUntil(f.io, [&] { return f.server.publishCount > before; }));
    EXPECT_TRUE(f.server.acksPerPublish.back().empty());
    EXPECT_TRUE(f.statuses.empty());

    // After delete, callbacks are gone and the subscription says so.
    std::optional<StatusCode> removed;
    f.run([&]() -> asio::awaitable<void> { removed = co_await f.sub->remove(); });
    EXPECT_EQ(removed, status::Good);
    EXPECT_EQ(f.server.deletedSubscriptions, std::vector<std::uint32_t>{kSubscriptionId});
    EXPECT_EQ(f.sub->status(), status::BadNoSubscription);
    f.server.publish(dataChange(3, {{(*a)->clientHandle, 7.0}}));
    std::optional<StatusCode> after;
    f.run([&]() -> asio::awaitable<void> {
        after = co_await f.sub->setPublishingMode(false);
        (void)co_await f.client.readValue(NodeId(1));  // a round trip after the late Publish
    });
    EXPECT_EQ(after, status::BadNoSubscription);
    EXPECT_EQ(first.size(), 2u);
}

TEST(ClientSubscription, EventFieldsReachTheirItem) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    std::vector<std::vector<Variant>> events;
    std::optional<Result<Subscription::MonitoredItem>> item;
    f.run([&]() -> asio::awaitable<void> {
        auto filter =
            makeEventFilter({"EventId", "EventType", "SourceName", "Time", "Message", "Severity"});
        item = co_await f.sub->monitorEvents(
            NodeId(2253), filter,
            [&](const std::vector<Variant>& fields) { events.push_back(fields); });
    });
    ASSERT_TRUE(item && *item);
    ASSERT_EQ(f.server.createdItems.size(), 1u);
    const auto& created = f.server.createdItems[0];
    EXPECT_EQ(created.itemToMonitor.nodeId, NodeId(2253));
    EXPECT_EQ(created.itemToMonitor.attributeId,
              static_cast<std::uint32_t>(AttributeId::EventNotifier));
    EventFilter sent;
    ASSERT_TRUE(fromExtensionObject(created.requestedParameters.filter, sent).isGood());
    ASSERT_EQ(sent.selectClauses.size(), 6u);
    EXPECT_EQ(sent.selectClauses[4].typeDefinitionId, NodeId(2041));
    ASSERT_EQ(sent.selectClauses[4].browsePath.size(), 1u);
    EXPECT_EQ(sent.selectClauses[4].browsePath[0].name, "Message");

    EventNotificationList list;
    EventFieldList fields;
    fields.clientHandle = (*item)->clientHandle;
    fields.eventFields = {Variant(ByteString{{1, 2, 3}}),
                          Variant(NodeId(2041)),
                          Variant(String("Cell")),
                          Variant(DateTime::now()),
                          Variant(LocalizedText{"", "hello"}),
                          Variant(std::uint16_t{500})};
    list.events.push_back(fields);
    NotificationMessage msg;
    msg.sequenceNumber = 1;
    msg.notificationData.push_back(toExtensionObject(list));
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.server.waiting.empty(); }));
    ASSERT_TRUE(f.server.publish(msg));
    ASSERT_TRUE(runUntil(f.io, [&] { return !events.empty(); }));
    ASSERT_EQ(events[0].size(), 6u);
    ASSERT_NE(events[0][4].get<LocalizedText>(), nullptr);
    EXPECT_EQ(events[0][4].get<LocalizedText>()->text, "hello");
    ASSERT_NE(events[0][5].get<std::uint16_t>(), nullptr);
    EXPECT_EQ(*events[0][5].get<std::uint16_t>(), 500);
}

TEST(ClientSubscription, GapIsRepublishedInOrder) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    std::vector<double> values;
    std::optional<Result<Subscription::MonitoredItem>> item;
    f.run([&]() -> asio::awaitable<void> {
        item = co_await f.sub->monitorDataChange(
            NodeId(1, "a"), AttributeId::Value, 0, 1, std::nullopt,
            [&](const DataValue& dv) { values.push_back(*dv.value->get<double>()); });
    });
    ASSERT_TRUE(item && *item);
    const auto h = (*item)->clientHandle;
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.server.waiting.empty(); }));
    ASSERT_TRUE(f.server.publish(dataChange(1, {{h, 1.0}})));
    ASSERT_TRUE(runUntil(f.io, [&] { return values.size() == 1 && !f.server.waiting.empty(); }));
    // 2 and 3 never arrive; the server still has 2, not 3.
    f.server.retained[2] = dataChange(2, {{h, 2.0}});
    ASSERT_TRUE(f.server.publish(dataChange(4, {{h, 4.0}})));
    ASSERT_TRUE(runUntil(f.io, [&] { return values.size() == 3; }));
    EXPECT_EQ(values, (std::vector<double>{1.0, 2.0, 4.0}));
    EXPECT_EQ(f.server.republished, (std::vector<std::uint32_t>{2, 3}));
    // The republished message is acknowledged as well as the new one.
    ASSERT_TRUE(runUntil(f.io, [&] {
        return !f.server.acksPerPublish.empty() && hasAck(f.server.acksPerPublish.back(), 2) &&
               hasAck(f.server.acksPerPublish.back(), 4);
    }));

    // A huge gap asks for a bounded number of messages.
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.server.waiting.empty(); }));
    ASSERT_TRUE(f.server.publish(dataChange(1000, {{h, 1000.0}})));
    ASSERT_TRUE(runUntil(f.io, [&] { return values.size() == 4; }));
    EXPECT_EQ(values.back(), 1000.0);
    EXPECT_LE(f.server.republished.size(), 2u + 8u);
}

TEST(ClientSubscription, SurvivesPublishTimeoutAndWatchdogReportsTheSilence) {
    // Keep-alive period 2 x 50 ms: the Publish timeout is 2 x 100 ms + 200 ms, the watchdog
    // allows 1.5 x 100 ms + 100 ms.
    Fixture f(SubscriptionSettings(50, 20, 2), 200ms);
    ASSERT_TRUE(f.sub);
    EXPECT_EQ(f.sub->keepAlivePeriod(), 100ms);
    std::vector<double> values;
    std::optional<Result<Subscription::MonitoredItem>> item;
    f.run([&]() -> asio::awaitable<void> {
        item = co_await f.sub->monitorDataChange(
            NodeId(1, "a"), AttributeId::Value, 0, 1, std::nullopt,
            [&](const DataValue& dv) { values.push_back(*dv.value->get<double>()); });
    });
    ASSERT_TRUE(item && *item);
    const auto h = (*item)->clientHandle;
    const auto start = std::chrono::steady_clock::now();
    // The first two Publish requests are never answered; the client must time them out and
    // ask again.
    ASSERT_TRUE(runUntil(f.io, [&] { return f.server.publishCount >= 3; }));
    const auto reissued = std::chrono::steady_clock::now() - start;
    EXPECT_GE(reissued, 300ms);
    ASSERT_GE(f.server.waiting.size(), 3u);
    f.server.waiting.pop_front();  // the timed-out requests: answering them would be moot
    f.server.waiting.pop_front();
    ASSERT_TRUE(f.server.publish(dataChange(1, {{h, 5.0}})));
    ASSERT_TRUE(runUntil(f.io, [&] { return !values.empty(); }));
    EXPECT_EQ(values[0], 5.0);
    // The silence was reported once, and its end too; nothing was torn down.
    ASSERT_TRUE(runUntil(f.io, [&] { return f.statuses.size() >= 2; }));
    EXPECT_EQ(f.statuses[0], status::BadTimeout);
    EXPECT_EQ(f.statuses[1], status::Good);
    EXPECT_EQ(f.sub->status(), status::Good);
    EXPECT_TRUE(f.client.isConnected());
}

TEST(ClientSubscription, LostSessionIsReportedAndPublishingStops) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    ASSERT_TRUE(runUntil(f.io, [&] { return f.server.waiting.size() >= 2; }));
    const auto publishes = f.server.publishCount;
    ASSERT_TRUE(f.server.publishFault(status::BadSessionIdInvalid));
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.statuses.empty(); }));
    EXPECT_EQ(f.statuses, std::vector<StatusCode>{status::BadSessionIdInvalid});
    EXPECT_EQ(f.sub->status(), status::BadSessionIdInvalid);
    // The other outstanding Publish fails the same way: still one report, no new Publish.
    ASSERT_TRUE(f.server.publishFault(status::BadSessionIdInvalid));
    std::optional<StatusCode> modify;
    f.run([&]() -> asio::awaitable<void> {
        (void)co_await f.client.readValue(NodeId(1));  // a round trip after both faults
        modify = co_await f.sub->setPublishingMode(true);
    });
    EXPECT_EQ(f.server.publishCount, publishes);
    EXPECT_EQ(f.statuses.size(), 1u);
    EXPECT_EQ(modify, status::BadSessionIdInvalid);
}

TEST(ClientSubscription, DroppedConnectionIsReported) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.server.waiting.empty(); }));
    f.server.drop();
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.statuses.empty(); }));
    EXPECT_EQ(f.statuses, std::vector<StatusCode>{status::BadConnectionClosed});
    EXPECT_EQ(f.sub->status(), status::BadConnectionClosed);
}

TEST(ClientSubscription, NoSubscriptionPausesPublishingUntilTheNextOne) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    ASSERT_TRUE(runUntil(f.io, [&] { return f.server.waiting.size() >= 2; }));
    ASSERT_TRUE(f.server.publishFault(status::BadNoSubscription));
    ASSERT_TRUE(f.server.publishFault(status::BadNoSubscription));
    const auto publishes = f.server.publishCount;
    f.run([&]() -> asio::awaitable<void> { (void)co_await f.client.readValue(NodeId(1)); });
    EXPECT_EQ(f.server.publishCount, publishes);  // paused
    EXPECT_TRUE(f.statuses.empty());              // not a loss
    std::shared_ptr<Subscription> second;
    f.run([&]() -> asio::awaitable<void> {
        auto created = co_await f.client.createSubscription(SubscriptionSettings(100, 150, 50));
        if (created) second = *created;
    });
    ASSERT_TRUE(second);
    ASSERT_TRUE(runUntil(f.io, [&] { return f.server.publishCount >= publishes + 2; }));
}

TEST(ClientSubscription, DisconnectEndsSubscriptionsQuietly) {
    Fixture f;
    ASSERT_TRUE(f.sub);
    ASSERT_TRUE(runUntil(f.io, [&] { return !f.server.waiting.empty(); }));
    f.run([&]() -> asio::awaitable<void> { co_await f.client.disconnect(); });
    EXPECT_TRUE(f.statuses.empty());
    EXPECT_EQ(f.sub->status(), status::BadSessionClosed);
}

TEST(BlockingClientSubscription, CallbacksRunOnTheClientThread) {
    asio::io_context serverIo;
    FakeServer server(serverIo);
    std::mutex m;
    std::condition_variable cv;
    std::vector<double> values;
    std::thread::id callbackThread;
    std::jthread serverThread([&serverIo] { serverIo.run_for(10s); });
    {
        BlockingClient client;
        ASSERT_EQ(client.connect(server.url()), status::Good);
        auto sub = client.createSubscription(SubscriptionSettings(100, 150, 50));
        ASSERT_TRUE(sub);
        auto item = client.monitorDataChange(*sub, NodeId(1, "a"), AttributeId::Value, 0, 1,
                                             std::nullopt, [&](const DataValue& dv) {
                                                 std::lock_guard lock(m);
                                                 callbackThread = std::this_thread::get_id();
                                                 values.push_back(*dv.value->get<double>());
                                                 cv.notify_all();
                                             });
        ASSERT_TRUE(item);
        // Two Publish requests wait at the server since createSubscription: answer one.
        asio::post(serverIo, [&server, h = item->clientHandle] {
            server.publish(dataChange(1, {{h, 6.5}}));
        });
        {
            std::unique_lock lock(m);
            ASSERT_TRUE(cv.wait_for(lock, 5s, [&] { return !values.empty(); }));
            EXPECT_EQ(values[0], 6.5);
            EXPECT_NE(callbackThread, std::this_thread::get_id());
        }
        EXPECT_EQ(client.deleteSubscription(*sub), status::Good);
    }
    serverIo.stop();
}

}  // namespace
}  // namespace skillcell::ua::client_subscription_test
