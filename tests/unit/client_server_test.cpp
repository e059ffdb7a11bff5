// Our client against our server over loopback: every service of the stack end to end.
#include <gtest/gtest.h>

#include "running_server.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/messages/view.hpp"

namespace client_server_test {

using namespace skillcell;
using namespace skillcell::ua;
using test::RunningServer;

namespace {

const NodeId kFolder(1, String("Plant"));
const NodeId kSpeed(1, String("Plant.Speed"));
const NodeId kFixed(1, String("Plant.Fixed"));
const NodeId kScale(1, String("Plant.Scale"));

void addPlant(Server& server) {
    auto& as = server.addressSpace();
    ASSERT_TRUE(as.addFolder(NodeId(ns0::ObjectsFolder), kFolder, "Plant"));
    ASSERT_TRUE(as.addVariable(kFolder, kSpeed, "Speed", NodeId(ns0::Double), Variant(1.0),
                               access_level::kReadWrite));
    ASSERT_TRUE(
        as.addVariable(kFolder, kFixed, "Fixed", NodeId(ns0::Int32), Variant(std::int32_t{3})));
    for (int i = 0; i < 30; ++i) {
        const std::string name = "Item" + std::to_string(i);
        ASSERT_TRUE(as.addVariable(kFolder, NodeId(1, String("Plant." + name)), name,
                                   NodeId(ns0::Int32), Variant(std::int32_t{i})));
    }
    Argument x{"x", NodeId(ns0::Double), -1, {}, {}};
    Argument factor{"factor", NodeId(ns0::Int32), -1, {}, {}};
    Argument y{"y", NodeId(ns0::Double), -1, {}, {}};
    ASSERT_TRUE(as.addMethod(
        kFolder, kScale, "Scale", {x, factor}, {y},
        [](const Caller&, const NodeId&, std::span<const Variant> in, std::vector<Variant>& out) {
            out.emplace_back(*in[0].get<double>() * *in[1].get<std::int32_t>());
            return StatusCode(status::Good);
        }));
}

class ClientServer : public ::testing::Test {
protected:
    ClientServer() : server_(RunningServer::defaultConfig(), addPlant) {
        EXPECT_EQ(client_.connect(server_.url()), status::Good);
    }
    RunningServer server_;
    BlockingClient client_;
};

}  // namespace

TEST_F(ClientServer, DiscoveryDescribesTheServer) {
    auto endpoints = client_.getEndpoints();
    ASSERT_TRUE(endpoints);
    ASSERT_EQ(endpoints->size(), 1u);
    const auto& ep = endpoints->front();
    EXPECT_EQ(ep.endpointUrl, server_.url());
    EXPECT_EQ(ep.securityMode, MessageSecurityMode::None);
    EXPECT_EQ(ep.securityPolicyUri, "http://opcfoundation.org/UA/SecurityPolicy#None");
    ASSERT_EQ(ep.userIdentityTokens.size(), 1u);
    EXPECT_EQ(ep.userIdentityTokens[0].tokenType, UserTokenType::Anonymous);

    auto servers = client_.findServers();
    ASSERT_TRUE(servers);
    ASSERT_EQ(servers->size(), 1u);
    EXPECT_EQ(servers->front().applicationUri, "urn:skillcell:server");
}

TEST_F(ClientServer, ReadWriteAndTypeChecks) {
    EXPECT_EQ(client_.writeValue(kSpeed, Variant(4.5)), status::Good);
    auto v = client_.readValue(kSpeed);
    ASSERT_TRUE(v);
    EXPECT_EQ(*v->get<double>(), 4.5);
    EXPECT_EQ(client_.writeValue(kSpeed, Variant(String("fast"))), status::BadTypeMismatch);
    EXPECT_EQ(client_.writeValue(kFixed, Variant(std::int32_t{4})), status::BadNotWritable);
    EXPECT_EQ(client_.readValue(NodeId(1, String("nope"))).status(), status::BadNodeIdUnknown);

    auto name = client_.readAttribute(kSpeed, AttributeId::BrowseName);
    ASSERT_TRUE(name);
    EXPECT_EQ(name->value->get<QualifiedName>()->name, "Speed");
    auto status = client_.readValue(NodeId(2259u));  // Server/ServerStatus/State
    ASSERT_TRUE(status);
    EXPECT_EQ(*status->get<std::int32_t>(), 0);  // Running
}

TEST_F(ClientServer, CallValidatesArguments) {
    auto out = client_.call(kFolder, kScale, {Variant(1.5), Variant(std::int32_t{4})});
    ASSERT_TRUE(out) << statusName(out.status());
    ASSERT_EQ(out->size(), 1u);
    EXPECT_EQ(*(*out)[0].get<double>(), 6.0);
    EXPECT_EQ(client_.call(kFolder, kScale, {Variant(1.5)}).status(), status::BadArgumentsMissing);
    EXPECT_EQ(client_.call(kFolder, kScale, {Variant(1.5), Variant(std::int32_t{1}), Variant(2.0)})
                  .status(),
              status::BadTooManyArguments);
    EXPECT_EQ(client_.call(kFolder, kScale, {Variant(1.5), Variant(2.0)}).status(),
              status::BadInvalidArgument);
    EXPECT_EQ(client_.call(NodeId(ns0::ObjectsFolder), kScale, {}).status(),
              status::BadMethodInvalid);
}

TEST_F(ClientServer, BrowseWithContinuationPoints) {
    BrowseRequest req;
    req.requestedMaxReferencesPerNode = 7;
    BrowseDescription d;
    d.nodeId = kFolder;
    d.referenceTypeId = NodeId(33u);
    req.nodesToBrowse.push_back(d);
    auto first = client_.browse(req);
    ASSERT_TRUE(first);
    ASSERT_EQ(first->results.size(), 1u);
    auto refs = first->results[0].references;
    EXPECT_EQ(refs.size(), 7u);
    ByteString cp = first->results[0].continuationPoint;
    int calls = 0;
    while (!cp.empty() && calls++ < 20) {
        auto next = client_.browseNext(cp);
        ASSERT_TRUE(next);
        refs.insert(refs.end(), next->references.begin(), next->references.end());
        cp = next->continuationPoint;
    }
    EXPECT_EQ(refs.size(), 33u);  // Speed, Fixed, 30 items, Scale
    // A released continuation point is gone.
    auto again = client_.browse(req);
    ASSERT_TRUE(again);
    const ByteString released = again->results[0].continuationPoint;
    ASSERT_FALSE(released.empty());
    ASSERT_TRUE(client_.browseNext(released, true));
    EXPECT_EQ(client_.browseNext(released).status(), status::BadContinuationPointInvalid);
}

TEST_F(ClientServer, TranslateBrowsePathAndRegisterNodes) {
    auto id = client_.translateBrowsePath(NodeId(ns0::ObjectsFolder),
                                          {QualifiedName{1, "Plant"}, QualifiedName{1, "Speed"}});
    ASSERT_TRUE(id);
    EXPECT_EQ(*id, kSpeed);
    EXPECT_EQ(client_.translateBrowsePath(NodeId(ns0::ObjectsFolder), {QualifiedName{1, "None"}})
                  .status(),
              status::BadNoMatch);
    auto registered = client_.registerNodes({kSpeed});
    ASSERT_TRUE(registered);
    EXPECT_EQ(client_.unregisterNodes(*registered), status::Good);
}

TEST_F(ClientServer, ClosedSessionCannotBeUsed) {
    EXPECT_EQ(client_.disconnect(), status::Good);
    EXPECT_EQ(client_.readValue(kSpeed).status(), status::BadServerNotConnected);
    EXPECT_EQ(client_.connect(server_.url()), status::Good);
    EXPECT_TRUE(client_.readValue(kSpeed));
    EXPECT_EQ(server_.inServer([](Server& s) { return s.sessionCount(); }), 1u);
}

TEST(ClientServerLimits, SessionLimitIsReported) {
    auto config = RunningServer::defaultConfig();
    config.limits.maxSessions = 1;
    RunningServer server(config);
    BlockingClient a;
    BlockingClient b;
    EXPECT_EQ(a.connect(server.url()), status::Good);
    EXPECT_EQ(b.connect(server.url()), status::BadTooManySessions);
}

TEST(ClientServerLimits, ConnectToAClosedPortFailsFast) {
    std::uint16_t port = 0;
    {
        RunningServer server;
        port = server.port();
    }
    BlockingClient c;
    ClientConfig config;
    config.connectTimeout = std::chrono::milliseconds(500);
    EXPECT_EQ(c.connect("opc.tcp://127.0.0.1:" + std::to_string(port), config),
              status::BadConnectionRejected);
}

}  // namespace client_server_test
