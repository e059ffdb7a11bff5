// Interop, security: our Client against node-opcua's server (server.js --secure) with every
// policy and mode it offers, a user name and password encrypted for node-opcua, and the
// refusals node-opcua gives for a wrong password and for anonymous users.
#include <gtest/gtest.h>

#include "node_server_suite.hpp"
#include "test_certificate.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/crypto/security_policy_profile.hpp"

namespace {

using namespace skillcell;
using ua::BlockingClient;
using ua::MessageSecurityMode;
using ua::NodeId;
using ua::StatusCode;
using ua::Variant;

class SecureNodeServerTest : public test::NodeServerSuite {
protected:
    static void SetUpTestSuite() { startServer({"--secure"}); }

    static const test::TestCertificate& certificate() {
        static const auto cert =
            test::makeTestCertificate(2048, "urn:skillcell:interop:secure-client");
        return cert;
    }

    static ua::ClientConfig config(std::string_view policy, MessageSecurityMode mode) {
        ua::ClientConfig c;
        c.applicationUri = "urn:skillcell:interop:secure-client";
        c.security.policyUri = std::string(policy);
        c.security.mode = mode;
        c.security.certificate = certificate().der;
        c.security.privateKey = certificate().key;
        c.security.user.kind = ua::UserCredentials::Kind::UserName;
        c.security.user.userName = "operator";
        c.security.user.password = "op-pw";
        c.connectTimeout = std::chrono::milliseconds(10'000);
        return c;
    }
};

TEST_F(SecureNodeServerTest, EveryPolicyAndModeWithAPassword) {
    for (const auto& profile : ua::crypto::securityPolicyProfiles()) {
        // node-opcua offers no ECC policy (none up to 2.186.4): the ECC policies are proven
        // between our client and server (EccSession in client_security_test.cpp).
        if (profile.isEcc()) continue;
        for (auto mode : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
            SCOPED_TRACE(std::string(profile.shortName) +
                         (mode == MessageSecurityMode::Sign ? " Sign" : " SignAndEncrypt"));
            BlockingClient client;
            const StatusCode s = client.connect(url(), config(profile.uri, mode));
            ASSERT_TRUE(s.isGood()) << ua::statusName(s);
            auto state = client.readValue(NodeId(2259));  // ServerStatus.State
            ASSERT_TRUE(state.ok()) << ua::statusName(state.status());
            ASSERT_NE(state->get<std::int32_t>(), nullptr);
            EXPECT_EQ(*state->get<std::int32_t>(), 0);  // Running
            // Enough data to need several chunks, each signed (and encrypted).
            auto big = client.browse(NodeId(85));
            EXPECT_TRUE(big.ok()) << ua::statusName(big.status());
            EXPECT_TRUE(client.disconnect().isGood());
        }
    }
}

TEST_F(SecureNodeServerTest, WrongPasswordAndAnonymousAreRefused) {
    auto wrong = config(ua::crypto::kPolicyAes256Sha256RsaPss, MessageSecurityMode::SignAndEncrypt);
    wrong.security.user.password = "not-it";
    BlockingClient a;
    const StatusCode refused = a.connect(url(), wrong);
    EXPECT_TRUE(refused.isBad());
    EXPECT_TRUE(refused == ua::status::BadUserAccessDenied ||
                refused == ua::status::BadIdentityTokenRejected)
        << ua::statusName(refused);
    auto anonymous = config(ua::crypto::kPolicyBasic256Sha256, MessageSecurityMode::Sign);
    anonymous.security.user = ua::UserCredentials{};
    BlockingClient b;
    EXPECT_TRUE(b.connect(url(), anonymous).isBad());
}

}  // namespace
