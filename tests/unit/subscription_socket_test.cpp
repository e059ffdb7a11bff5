// Subscriptions over real sockets: a RawConnection client creates a session, subscribes,
// writes, and waits (bounded read) for the Publish response carrying the change; service
// level status codes; and a closed session taking its subscriptions with it.
#include <gtest/gtest.h>

#include "raw_connection.hpp"
#include "running_server.hpp"
#include "ua/messages/session.hpp"
#include "ua/messages/subscription.hpp"
#include "ua/server/service_table.hpp"

namespace subscription_socket_test {

using namespace skillcell;
using namespace skillcell::ua;
using test::RawConnection;
using test::RunningServer;

namespace {

const NodeId kValue(1, String("Sub.Value"));

void addNodes(Server& server) {
    ASSERT_TRUE(server.addressSpace().addVariable(NodeId(ns0::ObjectsFolder), kValue, "Sub.Value",
                                                  NodeId(ns0::Double), Variant(1.5),
                                                  access_level::kReadWrite));
}

/// A client speaking raw service messages on one session.
class RawSession {
public:
    explicit RawSession(std::uint16_t port) : c_(port) {
        c_.open();
        CreateSessionRequest create;
        create.requestedSessionTimeout = 60000;
        auto created = call<CreateSessionResponse>(create);
        EXPECT_TRUE(created) << statusName(created.status());
        if (created) token_ = created->authenticationToken;
        ActivateSessionRequest activate;
        EXPECT_TRUE(call<ActivateSessionResponse>(activate));
    }

    /// Sends `req` on the session and decodes the response; a ServiceFault gives its status.
    template <class Response, class Request>
    Result<Response> call(Request req) {
        req.requestHeader.authenticationToken = token_;
        req.requestHeader.requestHandle = ++handle_;
        std::vector<std::uint8_t> body;
        encodeServiceMessage(body, req);
        auto reply = c_.exchange(body);  // bounded by RawConnection's timeout
        if (!reply) return status::BadTimeout;
        BinaryReader r(*reply);
        NodeId type;
        decode(r, type);
        if (type == NodeId(ServiceFault::kBinaryEncodingId)) {
            ServiceFault f;
            decode(r, f);
            return f.responseHeader.serviceResult;
        }
        if (type != NodeId(Response::kBinaryEncodingId)) return status::BadUnknownResponse;
        Response resp;
        decode(r, resp);
        if (!r.ok()) return r.status();
        EXPECT_EQ(resp.responseHeader.requestHandle, handle_);
        return resp;
    }

private:
    RawConnection c_;
    NodeId token_;
    std::uint32_t handle_ = 0;
};

double changedValue(const PublishResponse& p) {
    for (const auto& eo : p.notificationMessage.notificationData) {
        DataChangeNotification n;
        if (fromExtensionObject(eo, n).isGood() && !n.monitoredItems.empty()) {
            return *n.monitoredItems.back().value.value->get<double>();
        }
    }
    return -1;
}

TEST(SubscriptionSocket, WriteIsPublished) {
    RunningServer server(RunningServer::defaultConfig(), addNodes);
    RawSession s(server.port());

    EXPECT_EQ(s.call<PublishResponse>(PublishRequest{}).status(), status::BadNoSubscription);

    CreateSubscriptionRequest create;
    create.requestedPublishingInterval = 20;
    create.requestedMaxKeepAliveCount = 100;
    create.requestedLifetimeCount = 1000;
    auto sub = s.call<CreateSubscriptionResponse>(create);
    ASSERT_TRUE(sub) << statusName(sub.status());
    EXPECT_EQ(sub->revisedPublishingInterval, 20);

    CreateMonitoredItemsRequest items;
    items.subscriptionId = sub->subscriptionId;
    MonitoredItemCreateRequest item;
    item.itemToMonitor.nodeId = kValue;
    item.requestedParameters.clientHandle = 42;
    items.itemsToCreate = {item};
    auto created = s.call<CreateMonitoredItemsResponse>(items);
    ASSERT_TRUE(created);
    ASSERT_EQ(created->results.size(), 1u);
    EXPECT_EQ(created->results[0].statusCode, status::Good);

    auto first = s.call<PublishResponse>(PublishRequest{});
    ASSERT_TRUE(first) << statusName(first.status());
    EXPECT_EQ(first->subscriptionId, sub->subscriptionId);
    EXPECT_EQ(changedValue(*first), 1.5);  // the initial value

    WriteRequest write;
    DataValue dv;
    dv.value = Variant(7.25);
    write.nodesToWrite = {WriteValue{kValue, 13, {}, dv}};
    auto written = s.call<WriteResponse>(write);
    ASSERT_TRUE(written);
    ASSERT_EQ(written->results, std::vector<StatusCode>{status::Good});

    PublishRequest publish;
    publish.subscriptionAcknowledgements = {
        {sub->subscriptionId, first->notificationMessage.sequenceNumber}};
    auto second = s.call<PublishResponse>(publish);
    ASSERT_TRUE(second) << statusName(second.status());
    EXPECT_EQ(changedValue(*second), 7.25);
    EXPECT_EQ(second->results, std::vector<StatusCode>{status::Good});

    RepublishRequest again;
    again.subscriptionId = sub->subscriptionId;
    again.retransmitSequenceNumber = second->notificationMessage.sequenceNumber;
    auto republished = s.call<RepublishResponse>(again);
    ASSERT_TRUE(republished);
    EXPECT_EQ(republished->notificationMessage.sequenceNumber,
              second->notificationMessage.sequenceNumber);
    again.retransmitSequenceNumber = first->notificationMessage.sequenceNumber;  // acknowledged
    EXPECT_EQ(s.call<RepublishResponse>(again).status(), status::BadMessageNotAvailable);
}

TEST(SubscriptionSocket, ServiceLevelStatusCodes) {
    auto config = RunningServer::defaultConfig();
    config.limits.maxSubscriptionsPerSession = 1;
    RunningServer server(config, addNodes);
    RawSession s(server.port());

    CreateMonitoredItemsRequest items;
    items.subscriptionId = 999;
    items.itemsToCreate.resize(1);
    EXPECT_EQ(s.call<CreateMonitoredItemsResponse>(items).status(),
              status::BadSubscriptionIdInvalid);
    RepublishRequest rep;
    rep.subscriptionId = 999;
    EXPECT_EQ(s.call<RepublishResponse>(rep).status(), status::BadSubscriptionIdInvalid);

    auto sub = s.call<CreateSubscriptionResponse>(CreateSubscriptionRequest{});
    ASSERT_TRUE(sub);
    EXPECT_EQ(s.call<CreateSubscriptionResponse>(CreateSubscriptionRequest{}).status(),
              status::BadTooManySubscriptions);

    SetMonitoringModeRequest mode;
    mode.subscriptionId = sub->subscriptionId;
    mode.monitoringMode = static_cast<MonitoringMode>(5);
    mode.monitoredItemIds = {1};
    EXPECT_EQ(s.call<SetMonitoringModeResponse>(mode).status(), status::BadMonitoringModeInvalid);
    mode.monitoringMode = MonitoringMode::Sampling;
    auto modeResult = s.call<SetMonitoringModeResponse>(mode);
    ASSERT_TRUE(modeResult);
    EXPECT_EQ(modeResult->results, std::vector<StatusCode>{status::BadMonitoredItemIdInvalid});

    rep.subscriptionId = sub->subscriptionId;
    rep.retransmitSequenceNumber = 5;
    EXPECT_EQ(s.call<RepublishResponse>(rep).status(), status::BadMessageNotAvailable);

    DeleteSubscriptionsRequest del;
    del.subscriptionIds = {sub->subscriptionId, 12345};
    auto deleted = s.call<DeleteSubscriptionsResponse>(del);
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->results,
              (std::vector<StatusCode>{status::Good, status::BadSubscriptionIdInvalid}));
}

TEST(SubscriptionSocket, ClosedSessionFreesItsSubscriptions) {
    RunningServer server(RunningServer::defaultConfig(), addNodes);
    {
        RawSession s(server.port());
        for (int i = 0; i < 3; ++i) {
            auto sub = s.call<CreateSubscriptionResponse>(CreateSubscriptionRequest{});
            ASSERT_TRUE(sub);
            CreateMonitoredItemsRequest items;
            items.subscriptionId = sub->subscriptionId;
            MonitoredItemCreateRequest item;
            item.itemToMonitor.nodeId = kValue;
            items.itemsToCreate = {item, item};
            ASSERT_TRUE(s.call<CreateMonitoredItemsResponse>(items));
        }
        EXPECT_EQ(
            server.inServer([](Server& srv) { return srv.subscriptions().subscriptionCount(); }),
            3u);
        CloseSessionRequest close;
        close.deleteSubscriptions = true;
        ASSERT_TRUE(s.call<CloseSessionResponse>(close));
    }
    EXPECT_EQ(server.inServer([](Server& srv) { return srv.subscriptions().subscriptionCount(); }),
              0u);
    // A write after the close must not reach freed items (ASan would report a use).
    EXPECT_EQ(server.inServer(
                  [](Server& srv) { return srv.addressSpace().setValue(kValue, Variant(3.0)); }),
              status::Good);
}

}  // namespace

}  // namespace subscription_socket_test
