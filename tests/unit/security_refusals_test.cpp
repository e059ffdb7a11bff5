// The refusals security promises, end to end against a server whose trust comes from a real
// PKI directory (CertificateValidator, as `skillcell server` uses it): an untrusted, an
// expired and a wrong-URI certificate, a tampered chunk and a replayed one (through a man in
// the middle, TamperingProxy), a wrong password and an Observer calling a method. Each is
// refused with its status code and logged, and the server goes on serving everyone else.
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "pki_test_support.hpp"
#include "running_server.hpp"
#include "tampering_proxy.hpp"
#include "test_certificate.hpp"
#include "test_nodes.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/pki/certificate_validator.hpp"
#include "ua/pki/trust_list.hpp"
#include "ua/server/user_database.hpp"

namespace security_refusals_test {

using namespace skillcell::ua;
using skillcell::test::makeTestCertificate;
using skillcell::test::RunningServer;
using skillcell::test::TamperingProxy;
using skillcell::test::TestCertificate;

namespace {

constexpr std::uint16_t kNs = 2;
const NodeId kTwice(kNs, String("Twice"));
const NodeId kConfigure(kNs, String("Configure"));  // needs Engineer
constexpr long kDay = 24L * 3600;

struct Certificates {
    TestCertificate server = makeTestCertificate(2048, "urn:skillcell:server");
    TestCertificate client = makeTestCertificate(2048, "urn:skillcell:client");
    TestCertificate untrusted = makeTestCertificate(2048, "urn:skillcell:client");
    TestCertificate expired = makeTestCertificate(2048, "urn:skillcell:client", -2 * kDay, -kDay);
    TestCertificate otherUri = makeTestCertificate(2048, "urn:skillcell:someone-else");
};

const Certificates& certs() {
    static const Certificates c;  // key generation dominates the run time: once per process
    return c;
}

/// Captures what the server logs, to check that a refusal says why.
class LogCapture {
public:
    LogCapture() : sink_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(256)) {
        spdlog::default_logger()->sinks().push_back(sink_);
    }
    ~LogCapture() {
        auto& sinks = spdlog::default_logger()->sinks();
        sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
    }
    LogCapture(const LogCapture&) = delete;
    LogCapture& operator=(const LogCapture&) = delete;

    [[nodiscard]] bool contains(std::string_view text) const {
        for (const auto& line : sink_->last_formatted()) {
            if (line.find(text) != std::string::npos) return true;
        }
        return false;
    }

private:
    std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> sink_;
};

class SecurityRefusals : public testing::Test {
protected:
    SecurityRefusals() {
        EXPECT_TRUE(pki::createPkiLayout(pkiDir.path()).isGood());
        const auto trusted = pki::PkiPaths{pkiDir.path()}.trustedCerts();
        pki::test::writeFile(trusted / "client.der", certs().client.der);
        pki::test::writeFile(trusted / "expired.der", certs().expired.der);
        pki::test::writeFile(trusted / "other-uri.der", certs().otherUri.der);
        server = std::make_unique<RunningServer>(config(), addMethod);
    }

    ServerConfig config() {
        ServerConfig c = RunningServer::defaultConfig();
        c.description.certificate = certs().server.der;
        c.description.securityEndpoints = allSecurityEndpoints(false);
        UserTokenPolicy password;
        password.policyId = std::string(kUserNamePolicyId);
        password.tokenType = UserTokenType::UserName;
        c.description.userTokenPolicies = {password};
        c.security.privateKey = certs().server.key;
        auto validator = std::make_shared<pki::CertificateValidator>(pkiDir.path());
        c.security.validateCertificate = [validator](const ByteString& der, std::string_view uri,
                                                     std::string* reason) {
            auto verdict = validator->validate(der, uri);
            *reason = verdict.reason;
            return verdict.status;
        };
        auto users = std::make_shared<UserDatabase>();
        EXPECT_TRUE(users->setPassword("olga", RoleSet{Role::Operator}, "operator-pw").isGood());
        EXPECT_TRUE(users->setPassword("otto", RoleSet{Role::Observer}, "observer-pw").isGood());
        EXPECT_TRUE(users->setPassword("erik", RoleSet{Role::Engineer}, "engineer-pw").isGood());
        c.security.users = users;
        return c;
    }

    static void addMethod(Server& s) {
        auto& as = s.addressSpace();
        ASSERT_EQ(as.registerNamespace("urn:test:refusals"), kNs);
        ASSERT_EQ(skillcell::test::addDoublingMethod(as, kTwice), status::Good);
        ASSERT_TRUE(as.addMethod(NodeId(85), kConfigure, "Configure", {}, {},
                                 [](const Caller&, const NodeId&, std::span<const Variant>,
                                    std::vector<Variant>&) { return status::Good; })
                        .ok());
        as.find(kConfigure)->requiredRole = Role::Engineer;
    }

    /// A client with `identity`, as user `user`, knowing the server's certificate (so it
    /// makes exactly one connection: the proxy counts its frames).
    static ClientConfig clientConfig(const TestCertificate& identity, const std::string& user,
                                     const std::string& password) {
        ClientConfig c;
        c.security.policyUri = std::string(crypto::kPolicyAes256Sha256RsaPss);
        c.security.mode = MessageSecurityMode::SignAndEncrypt;
        c.security.certificate = identity.der;
        c.security.privateKey = identity.key;
        c.serverCertificate = certs().server.der;
        c.applicationUri = "urn:skillcell:client";
        c.security.user.kind = UserCredentials::Kind::UserName;
        c.security.user.userName = user;
        c.security.user.password = password;
        return c;
    }

    /// The server still serves a well-behaved operator.
    void expectOthersServed() {
        BlockingClient good;
        ASSERT_EQ(good.connect(server->url(), clientConfig(certs().client, "olga", "operator-pw")),
                  status::Good);
        auto twice = good.call(NodeId(85), kTwice, {Variant(21.0)});
        ASSERT_TRUE(twice.ok()) << statusName(twice.status());
        EXPECT_EQ(*(*twice)[0].get<double>(), 42.0);
        EXPECT_EQ(good.disconnect(), status::Good);
    }

    [[nodiscard]] std::string proxyUrl(const TamperingProxy& proxy) const {
        return "opc.tcp://127.0.0.1:" + std::to_string(proxy.port());
    }

    pki::test::TempDir pkiDir;
    LogCapture log;
    std::unique_ptr<RunningServer> server;
};

}  // namespace

TEST_F(SecurityRefusals, UntrustedCertificateIsRefusedAndKeptForTheOperator) {
    BlockingClient client;
    EXPECT_EQ(client.connect(server->url(), clientConfig(certs().untrusted, "olga", "operator-pw")),
              status::BadCertificateUntrusted);
    EXPECT_TRUE(log.contains("BadCertificateUntrusted"));
    const auto rejected = pki::listCertificates(pki::PkiPaths{pkiDir.path()}.rejectedCerts());
    ASSERT_EQ(rejected.size(), 1u);
    EXPECT_EQ(rejected[0].der, certs().untrusted.der);
    expectOthersServed();
}

TEST_F(SecurityRefusals, ExpiredCertificateIsTimeInvalidEvenWhenTrusted) {
    BlockingClient client;
    EXPECT_EQ(client.connect(server->url(), clientConfig(certs().expired, "olga", "operator-pw")),
              status::BadCertificateTimeInvalid);
    EXPECT_TRUE(log.contains("BadCertificateTimeInvalid"));
    expectOthersServed();
}

TEST_F(SecurityRefusals, CertificateOfAnotherApplicationUriIsUriInvalid) {
    // The channel opens (the certificate is trusted); CreateSession names an application
    // URI the certificate does not carry.
    BlockingClient client;
    EXPECT_EQ(client.connect(server->url(), clientConfig(certs().otherUri, "olga", "operator-pw")),
              status::BadCertificateUriInvalid);
    EXPECT_TRUE(log.contains("BadCertificateUriInvalid"));
    expectOthersServed();
}

TEST_F(SecurityRefusals, TamperedChunkIsSecurityChecksFailed) {
    // Frames of one connection: 0 Hello, 1 OpenSecureChannel, 2 CreateSession,
    // 3 ActivateSession, 4 the first request after connect.
    TamperingProxy proxy(server->port(), [](std::size_t index, TamperingProxy::Frame frame) {
        if (index == 4) frame[frame.size() - 40] ^= 0x01;  // inside the encrypted part
        return std::vector<TamperingProxy::Frame>{std::move(frame)};
    });
    BlockingClient client;
    ASSERT_EQ(client.connect(proxyUrl(proxy), clientConfig(certs().client, "olga", "operator-pw")),
              status::Good);
    auto state = client.readValue(NodeId(2259));
    EXPECT_FALSE(state.ok());
    EXPECT_TRUE(log.contains("BadSecurityChecksFailed"));
    expectOthersServed();
}

TEST_F(SecurityRefusals, ReplayedChunkIsSequenceNumberInvalid) {
    TamperingProxy proxy(server->port(), [](std::size_t index, TamperingProxy::Frame frame) {
        std::vector<TamperingProxy::Frame> out{frame};
        if (index == 4) out.push_back(std::move(frame));  // the attacker sends it again
        return out;
    });
    BlockingClient client;
    ASSERT_EQ(client.connect(proxyUrl(proxy), clientConfig(certs().client, "olga", "operator-pw")),
              status::Good);
    // The original is answered; the copy ends the channel.
    auto state = client.readValue(NodeId(2259));
    EXPECT_TRUE(state.ok()) << statusName(state.status());
    auto again = client.readValue(NodeId(2259));
    EXPECT_FALSE(again.ok());
    EXPECT_TRUE(log.contains("BadSequenceNumberInvalid"));
    expectOthersServed();
}

TEST_F(SecurityRefusals, WrongPasswordIsRefused) {
    BlockingClient client;
    EXPECT_EQ(client.connect(server->url(), clientConfig(certs().client, "olga", "not-it")),
              status::BadUserAccessDenied);
    EXPECT_TRUE(log.contains("olga"));
    expectOthersServed();
}

TEST_F(SecurityRefusals, ObserverMayReadButNotCall) {
    BlockingClient client;
    ASSERT_EQ(client.connect(server->url(), clientConfig(certs().client, "otto", "observer-pw")),
              status::Good);
    EXPECT_TRUE(client.readValue(NodeId(2259)).ok());
    auto call = client.call(NodeId(85), kTwice, {Variant(1.0)});
    EXPECT_EQ(call.status(), status::BadUserAccessDenied);
    EXPECT_TRUE(log.contains("BadUserAccessDenied"));
    expectOthersServed();
}

TEST_F(SecurityRefusals, ConfigurationNeedsAnEngineer) {
    BlockingClient operatorClient;
    ASSERT_EQ(
        operatorClient.connect(server->url(), clientConfig(certs().client, "olga", "operator-pw")),
        status::Good);
    EXPECT_EQ(operatorClient.call(NodeId(85), kConfigure, {}).status(),
              status::BadUserAccessDenied);
    EXPECT_TRUE(log.contains("needs Engineer"));
    BlockingClient engineer;
    ASSERT_EQ(engineer.connect(server->url(), clientConfig(certs().client, "erik", "engineer-pw")),
              status::Good);
    EXPECT_TRUE(engineer.call(NodeId(85), kConfigure, {}).ok());
    EXPECT_TRUE(engineer.call(NodeId(85), kTwice, {Variant(1.0)}).ok());  // and what operators do
}

}  // namespace security_refusals_test
