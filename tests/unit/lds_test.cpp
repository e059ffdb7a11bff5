// The Local Discovery Server: the registration table and the FindServersOnNetwork
// directory as logic, then the services over a real connection (RegisterServer,
// RegisterServer2, FindServers, FindServersOnNetwork) with their status codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "running_server.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/discovery/local_discovery_server.hpp"
#include "ua/discovery/registered_server_table.hpp"
#include "ua/discovery/server_on_network_directory.hpp"

namespace skillcell::ua::lds::lds_test {
namespace {

using namespace std::chrono_literals;

RegisteredServer sampleServer(std::string uri = "urn:test:pump") {
    RegisteredServer s;
    s.serverUri = std::move(uri);
    s.productUri = "urn:test";
    s.serverNames = {{"en", "Pump"}, {"de", "Pumpe"}};
    s.discoveryUrls = {"opc.tcp://198.18.0.5:4841"};
    return s;
}

TEST(RegisteredServerTable, ValidatesEveryFieldWithItsStatusCode) {
    RegisteredServerTable table(60s);
    EXPECT_EQ(table.validate(sampleServer()), status::Good);
    auto s = sampleServer("");
    EXPECT_EQ(table.validate(s), status::BadServerUriInvalid);
    s = sampleServer();
    s.serverNames = {{"en", ""}};
    EXPECT_EQ(table.validate(s), status::BadServerNameMissing);
    s = sampleServer();
    s.discoveryUrls.clear();
    EXPECT_EQ(table.validate(s), status::BadDiscoveryUrlMissing);
    s = sampleServer();
    s.discoveryUrls = {"not a url"};
    EXPECT_EQ(table.validate(s), status::BadInvalidArgument);
    s = sampleServer();
    s.serverType = ApplicationType::Client;
    EXPECT_EQ(table.validate(s), status::BadInvalidArgument);
    s = sampleServer();
    s.serverType = static_cast<ApplicationType>(17);
    EXPECT_EQ(table.validate(s), status::BadInvalidArgument);
    s = sampleServer();
    s.semaphoreFilePath = "/nonexistent/skillcell/semaphore";
    EXPECT_EQ(table.validate(s), status::BadSemaphoreFileMissing);
    s = sampleServer();
    s.discoveryUrls.assign(100, "opc.tcp://a:1");
    EXPECT_EQ(table.validate(s), status::BadInvalidArgument);
    // Going offline needs only the serverUri.
    RegisteredServer offline;
    offline.serverUri = "urn:x";
    offline.isOnline = false;
    EXPECT_EQ(table.validate(offline), status::Good);
}

TEST(RegisteredServerTable, AddsRenewsUpdatesRemovesAndExpires) {
    RegisteredServerTable table(60s);
    const auto t0 = Clock::now();
    EXPECT_EQ(*table.apply(sampleServer(), std::nullopt, t0), RegisteredServerTable::Change::Added);
    EXPECT_EQ(*table.apply(sampleServer(), std::nullopt, t0 + 30s),
              RegisteredServerTable::Change::Renewed);
    auto moved = sampleServer();
    moved.discoveryUrls = {"opc.tcp://198.18.0.6:4841"};
    EXPECT_EQ(*table.apply(moved, std::nullopt, t0 + 40s), RegisteredServerTable::Change::Updated);
    EXPECT_TRUE(table.expire(t0 + 90s).empty());  // renewed at 40 s
    EXPECT_EQ(table.expire(t0 + 101s).size(), 1u);
    EXPECT_EQ(table.size(), 0u);

    (void)table.apply(sampleServer(), std::nullopt, t0);
    auto offline = sampleServer();
    offline.isOnline = false;
    EXPECT_EQ(*table.apply(offline, std::nullopt, t0), RegisteredServerTable::Change::Removed);
    EXPECT_EQ(*table.apply(offline, std::nullopt, t0), RegisteredServerTable::Change::NotFound);
}

TEST(RegisteredServerTable, EndsARegistrationWhenItsSemaphoreFileGoes) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("skillcell-semaphore-" + std::to_string(::getpid()));
    std::ofstream(path).put('x');
    RegisteredServerTable table(600s);
    auto s = sampleServer();
    s.semaphoreFilePath = path.string();
    ASSERT_EQ(table.validate(s), status::Good);
    (void)table.apply(s, std::nullopt, Clock::now());
    EXPECT_TRUE(table.expire(Clock::now()).empty());
    std::filesystem::remove(path);
    EXPECT_EQ(table.expire(Clock::now()).size(), 1u);
}

TEST(RegisteredServerTable, IsBoundedAndDescribesInTheAskedLocale) {
    RegistrationLimits limits;
    limits.maxServers = 2;
    RegisteredServerTable table(60s, limits);
    const auto now = Clock::now();
    (void)table.apply(sampleServer("urn:a"), std::nullopt, now);
    (void)table.apply(sampleServer("urn:b"), std::nullopt, now);
    EXPECT_EQ(table.apply(sampleServer("urn:c"), std::nullopt, now).status(),
              status::BadResourceUnavailable);
    auto described = table.describe({"urn:b"}, {"de"});
    ASSERT_EQ(described.size(), 1u);
    EXPECT_EQ(described[0].applicationUri, "urn:b");
    EXPECT_EQ(described[0].applicationName.text, "Pumpe");
    EXPECT_EQ(table.describe({}, {}).size(), 2u);
}

mdns::ServiceEvent announced(std::string name, std::uint16_t port, std::vector<std::string> caps) {
    mdns::ServiceEvent e;
    e.instance.name = std::move(name);
    e.instance.port = port;
    e.instance.address = {198, 18, 0, 1};
    e.instance.capabilities = std::move(caps);
    return e;
}

TEST(ServerOnNetworkDirectory, NumbersRecordsAndFilters) {
    ServerOnNetworkDirectory dir(DateTime::now());
    dir.apply(announced("lds", 4840, {"LDS"}));
    dir.apply(announced("pump", 4841, {"DA", "NA"}));
    dir.apply(announced("valve", 4842, {"da"}));
    FindServersOnNetworkRequest all;
    auto records = dir.find(all);
    ASSERT_EQ(records.size(), 3u);
    EXPECT_EQ(records[0].recordId, 1u);
    EXPECT_EQ(records[2].discoveryUrl, "opc.tcp://198.18.0.1:4842");

    FindServersOnNetworkRequest byCaps;
    byCaps.serverCapabilityFilter = {"DA"};
    EXPECT_EQ(dir.find(byCaps).size(), 2u);  // case-insensitive
    byCaps.serverCapabilityFilter = {"DA", "NA"};
    EXPECT_EQ(dir.find(byCaps).size(), 1u);

    FindServersOnNetworkRequest page;
    page.startingRecordId = 2;
    page.maxRecordsToReturn = 1;
    records = dir.find(page);
    ASSERT_EQ(records.size(), 1u);
    EXPECT_EQ(records[0].serverName, "pump");

    // A change gets a new record id; a gone server leaves.
    dir.apply(announced("pump", 4999, {"DA"}));
    mdns::ServiceEvent gone = announced("valve", 4842, {});
    gone.kind = mdns::ServiceEvent::Kind::Gone;
    dir.apply(gone);
    page.startingRecordId = 4;
    page.maxRecordsToReturn = 0;
    records = dir.find(page);
    ASSERT_EQ(records.size(), 1u);
    EXPECT_EQ(records[0].recordId, 4u);
    EXPECT_EQ(dir.size(), 2u);
}

// The services over a connection, on an LDS without mDNS.
class LdsServices : public testing::Test {
protected:
    void SetUp() override {
        auto config = test::RunningServer::defaultConfig();
        config.description.applicationUri = "urn:test:lds";
        config.description.applicationType = ApplicationType::DiscoveryServer;
        server_ = std::make_unique<test::RunningServer>(config);
        server_->inServer([this](Server& s) {
            lds_ = LocalDiscoveryServer::create(s, nullptr);
            lds_->start(server_->io().get_executor());
            return 0;
        });
        ASSERT_EQ(client_.connect(server_->url(), channelOnly()), status::Good);
    }
    void TearDown() override {
        client_.disconnect();
        server_->inServer([this](Server&) {
            lds_->stop();
            lds_.reset();
            return 0;
        });
    }
    static ClientConfig channelOnly() {
        ClientConfig c;
        c.createSession = false;
        return c;
    }
    Result<RegisterServer2Response> register2(RegisteredServer s,
                                              std::vector<ExtensionObject> config = {}) {
        RegisterServer2Request req;
        req.server = std::move(s);
        req.discoveryConfiguration = std::move(config);
        return client_.request<RegisterServer2Request, RegisterServer2Response>(req);
    }
    std::vector<String> registeredUris() {
        auto servers = client_.findServers(server_->url());
        std::vector<String> uris;
        if (servers) {
            for (const auto& s : *servers) uris.push_back(s.applicationUri);
        }
        return uris;
    }

    std::unique_ptr<test::RunningServer> server_;
    std::shared_ptr<LocalDiscoveryServer> lds_;
    BlockingClient client_;
};

TEST_F(LdsServices, RegisterServer2ListsTheServerUntilItGoesOffline) {
    MdnsDiscoveryConfiguration mdns;
    mdns.mdnsServerName = "pump";
    mdns.serverCapabilities = {"DA"};
    ExtensionObject unknown;
    unknown.typeId = NodeId(99999);
    unknown.encoding = ExtensionObject::Encoding::Binary;
    auto resp = register2(sampleServer(), {toExtensionObject(mdns), unknown});
    ASSERT_TRUE(resp.ok()) << statusName(resp.status());
    EXPECT_EQ(resp->configurationResults,
              (std::vector<StatusCode>{status::Good, status::BadNotSupported}));
    EXPECT_EQ(registeredUris(), (std::vector<String>{"urn:test:lds", "urn:test:pump"}));

    // The serverUris filter.
    FindServersRequest filtered;
    filtered.serverUris = {"urn:test:pump"};
    auto only = client_.request<FindServersRequest, FindServersResponse>(filtered);
    ASSERT_TRUE(only.ok());
    ASSERT_EQ(only->servers.size(), 1u);
    EXPECT_EQ(only->servers[0].applicationName.text, "Pump");

    auto offline = sampleServer();
    offline.isOnline = false;
    ASSERT_TRUE(register2(offline).ok());
    EXPECT_EQ(registeredUris(), (std::vector<String>{"urn:test:lds"}));
}

TEST_F(LdsServices, PlainRegisterServerWorksToo) {
    RegisterServerRequest req;
    req.server = sampleServer("urn:test:plain");
    ASSERT_TRUE((client_.request<RegisterServerRequest, RegisterServerResponse>(req).ok()));
    EXPECT_EQ(registeredUris(), (std::vector<String>{"urn:test:lds", "urn:test:plain"}));
}

TEST_F(LdsServices, BadRegistrationsGetTheirStatusAndLeaveNoEntry) {
    auto s = sampleServer();
    s.serverUri.clear();
    EXPECT_EQ(register2(s).status(), status::BadServerUriInvalid);
    s = sampleServer();
    s.serverNames.clear();
    EXPECT_EQ(register2(s).status(), status::BadServerNameMissing);
    s = sampleServer();
    s.discoveryUrls.clear();
    EXPECT_EQ(register2(s).status(), status::BadDiscoveryUrlMissing);
    s = sampleServer();
    s.semaphoreFilePath = "/nonexistent/semaphore";
    EXPECT_EQ(register2(s).status(), status::BadSemaphoreFileMissing);
    MdnsDiscoveryConfiguration badName;
    badName.mdnsServerName = "has.a.dot";
    auto resp = register2(sampleServer(), {toExtensionObject(badName)});
    ASSERT_TRUE(resp.ok());
    EXPECT_EQ(resp->configurationResults, (std::vector<StatusCode>{status::BadInvalidArgument}));
    // Only that last (valid) registration is listed.
    EXPECT_EQ(registeredUris(), (std::vector<String>{"urn:test:lds", "urn:test:pump"}));
    EXPECT_TRUE(client_.isConnected());
}

TEST_F(LdsServices, FindServersOnNetworkNeedsTheMulticastExtension) {
    FindServersOnNetworkRequest req;
    auto resp = client_.request<FindServersOnNetworkRequest, FindServersOnNetworkResponse>(req);
    EXPECT_EQ(resp.status(), status::BadServiceUnsupported);
}

}  // namespace
}  // namespace skillcell::ua::lds::lds_test
