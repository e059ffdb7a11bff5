// Our client against our server with security on, in one process: every policy with Sign
// and SignAndEncrypt, user names with passwords and X.509 user certificates, roles on Call
// and Write, and the refusals (untrusted certificates on either side, wrong passwords,
// anonymous users, a None channel used for more than discovery); a server with a P-256
// certificate and ECC_nistP256.
#include <gtest/gtest.h>

#include "running_server.hpp"
#include "test_certificate.hpp"
#include "test_nodes.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/server/user_database.hpp"
#include "ua/transport/certificate_security_policy.hpp"

namespace client_security_test {

using namespace skillcell::ua;
using skillcell::test::makeTestCertificate;
using skillcell::test::makeTestEccCertificate;
using skillcell::test::RunningServer;
using skillcell::test::TestCertificate;

namespace {

constexpr std::uint16_t kNs = 2;  // 1 is the server's own namespace
const NodeId kTarget(kNs, String("Target"));
const NodeId kTwice(kNs, String("Target.Twice"));

struct Certificates {
    TestCertificate server = makeTestCertificate(2048, "urn:skillcell:server");
    TestCertificate client = makeTestCertificate(2048, "urn:skillcell:client");
    TestCertificate stranger = makeTestCertificate(2048, "urn:skillcell:client");
    TestCertificate userCert = makeTestCertificate(2048, "urn:skillcell:user:robot-cell");
};

const Certificates& certs() {
    static const Certificates c;  // RSA key generation dominates the test's run time
    return c;
}

/// A user who is an X.509 certificate, as a component is its application certificate.
UserCredentials certificateUser(const TestCertificate& certificate) {
    UserCredentials user;
    user.kind = UserCredentials::Kind::Certificate;
    user.certificate = certificate.der;
    user.privateKey = certificate.key;
    return user;
}

ServerConfig secureConfig() {
    ServerConfig config = RunningServer::defaultConfig();
    config.description.certificate = certs().server.der;
    config.description.securityEndpoints = allSecurityEndpoints(false);
    UserTokenPolicy password;
    password.policyId = std::string(kUserNamePolicyId);
    password.tokenType = UserTokenType::UserName;
    UserTokenPolicy x509;
    x509.policyId = std::string(kCertificatePolicyId);
    x509.tokenType = UserTokenType::Certificate;
    config.description.userTokenPolicies = {password, x509};
    config.security.privateKey = certs().server.key;
    // Trusts our client's certificate and nothing else.
    config.security.validateCertificate = [](const ByteString& der, std::string_view,
                                             std::string* reason) {
        if (leafCertificate(der.bytes) == leafCertificate(certs().client.der.bytes)) {
            return status::Good;
        }
        *reason = "not in the trust list";
        return StatusCode(0x801A0000);  // BadCertificateUntrusted
    };
    config.security.allowAnonymous = false;
    auto users = std::make_shared<UserDatabase>();
    EXPECT_TRUE(users->setPassword("olga", RoleSet{Role::Operator}, "operator-pw").isGood());
    EXPECT_TRUE(users->setPassword("otto", RoleSet{Role::Observer}, "observer-pw").isGood());
    EXPECT_TRUE(
        users->setCertificate("cell-mes", RoleSet{Role::Operator}, certs().userCert.der).isGood());
    config.security.users = users;
    return config;
}

void addTargets(Server& server) {
    auto& as = server.addressSpace();
    ASSERT_EQ(as.registerNamespace("urn:test:security"), kNs);
    ASSERT_TRUE(as.addVariable(NodeId(85), kTarget, "Target", NodeId(11), Variant(1.0),
                               access_level::kCurrentRead | access_level::kCurrentWrite)
                    .ok());
    ASSERT_EQ(skillcell::test::addDoublingMethod(as, kTwice), status::Good);
}

ClientConfig clientConfig(std::string_view policy, MessageSecurityMode mode) {
    ClientConfig c;
    c.security.policyUri = std::string(policy);
    c.security.mode = mode;
    c.security.certificate = certs().client.der;
    c.security.privateKey = certs().client.key;
    c.applicationUri = "urn:skillcell:client";
    c.security.user.kind = UserCredentials::Kind::UserName;
    c.security.user.userName = "olga";
    c.security.user.password = "operator-pw";
    return c;
}

/// The server's endpoints, asked for on a None channel as a client does before it chooses.
Result<std::vector<EndpointDescription>> endpointsOverNone(const std::string& url) {
    BlockingClient discovery;
    ClientConfig none;
    none.createSession = false;
    if (const auto s = discovery.connect(url, none); s.isBad()) return s;
    return discovery.getEndpoints();
}

class SecureSession : public testing::Test {
protected:
    RunningServer server{secureConfig(), addTargets};
};

}  // namespace

TEST_F(SecureSession, EveryPolicyAndModeReadsWritesAndCalls) {
    for (const auto& profile : crypto::securityPolicyProfiles()) {
        if (profile.isEcc()) continue;  // this server's certificate is RSA: EccSession below
        for (auto mode : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
            SCOPED_TRACE(std::string(profile.shortName) +
                         (mode == MessageSecurityMode::Sign ? " Sign" : " SignAndEncrypt"));
            BlockingClient client;
            ASSERT_EQ(client.connect(server.url(), clientConfig(profile.uri, mode)), status::Good);
            auto state = client.readValue(NodeId(2259));
            ASSERT_TRUE(state.ok());
            EXPECT_EQ(client.writeValue(kTarget, Variant(4.5)), status::Good);
            auto twice = client.call(NodeId(85), kTwice, {Variant(21.0)});
            ASSERT_TRUE(twice.ok()) << statusName(twice.status());
            EXPECT_EQ(*(*twice)[0].get<double>(), 42.0);
            EXPECT_EQ(client.disconnect(), status::Good);
        }
    }
}

TEST_F(SecureSession, ObserverReadsButMayNotWriteOrCall) {
    auto config =
        clientConfig(crypto::kPolicyAes256Sha256RsaPss, MessageSecurityMode::SignAndEncrypt);
    config.security.user.userName = "otto";
    config.security.user.password = "observer-pw";
    BlockingClient client;
    ASSERT_EQ(client.connect(server.url(), config), status::Good);
    EXPECT_TRUE(client.readValue(kTarget).ok());
    EXPECT_EQ(client.writeValue(kTarget, Variant(9.0)), status::BadUserAccessDenied);
    EXPECT_EQ(client.call(NodeId(85), kTwice, {Variant(1.0)}).status(),
              status::BadUserAccessDenied);
    // The refusals changed nothing and the server serves on.
    EXPECT_EQ(*client.readValue(kTarget)->get<double>(), 1.0);
}

TEST_F(SecureSession, WrongPasswordUnknownUserAndAnonymousAreRefused) {
    auto config = clientConfig(crypto::kPolicyBasic256Sha256, MessageSecurityMode::Sign);
    config.security.user.password = "wrong";
    BlockingClient a;
    EXPECT_EQ(a.connect(server.url(), config), status::BadUserAccessDenied);
    config.security.user.userName = "nobody";
    BlockingClient b;
    EXPECT_EQ(b.connect(server.url(), config), status::BadUserAccessDenied);
    config.security.user = UserCredentials{};
    BlockingClient c;
    EXPECT_EQ(c.connect(server.url(), config), status::BadIdentityTokenRejected);
}

TEST_F(SecureSession, X509UserTokenNeedsAKnownCertificateAndItsKey) {
    auto config =
        clientConfig(crypto::kPolicyAes128Sha256RsaOaep, MessageSecurityMode::SignAndEncrypt);
    config.security.user = certificateUser(certs().userCert);
    BlockingClient known;
    ASSERT_EQ(known.connect(server.url(), config), status::Good);
    EXPECT_EQ(known.writeValue(kTarget, Variant(2.0)), status::Good);
    // The right certificate signed with another key proves nothing.
    config.security.user.privateKey = certs().stranger.key;
    BlockingClient forged;
    EXPECT_EQ(forged.connect(server.url(), config), status::BadUserSignatureInvalid);
    // A certificate the user database does not know.
    config.security.user.certificate = certs().stranger.der;
    BlockingClient unknown;
    EXPECT_EQ(unknown.connect(server.url(), config), status::BadUserAccessDenied);
}

TEST_F(SecureSession, UntrustedClientCertificateIsRefusedAtOpenSecureChannel) {
    auto config = clientConfig(crypto::kPolicyBasic256Sha256, MessageSecurityMode::SignAndEncrypt);
    config.security.certificate = certs().stranger.der;
    config.security.privateKey = certs().stranger.key;
    BlockingClient client;
    EXPECT_EQ(client.connect(server.url(), config), StatusCode(0x801A0000));
    // Others are still served.
    BlockingClient good;
    EXPECT_EQ(good.connect(server.url(),
                           clientConfig(crypto::kPolicyBasic256Sha256, MessageSecurityMode::Sign)),
              status::Good);
}

TEST_F(SecureSession, ClientRefusesAServerItDoesNotTrust) {
    auto config = clientConfig(crypto::kPolicyBasic256Sha256, MessageSecurityMode::SignAndEncrypt);
    config.security.validateServerCertificate = [](const ByteString&, std::string* reason) {
        *reason = "unknown server";
        return StatusCode(0x801A0000);
    };
    BlockingClient client;
    EXPECT_EQ(client.connect(server.url(), config), StatusCode(0x801A0000));
    // A server that presents another certificate than its endpoint's.
    auto impostor =
        clientConfig(crypto::kPolicyBasic256Sha256, MessageSecurityMode::SignAndEncrypt);
    impostor.serverCertificate = certs().stranger.der;
    BlockingClient fooled;
    EXPECT_TRUE(fooled.connect(server.url(), impostor).isBad());
}

TEST_F(SecureSession, NoneChannelServesDiscoveryOnly) {
    auto endpoints = endpointsOverNone(server.url());
    ASSERT_TRUE(endpoints.ok());
    EXPECT_EQ(endpoints->size(), 6u);
    for (const auto& ep : *endpoints) {
        EXPECT_NE(ep.securityMode, MessageSecurityMode::None);
        EXPECT_EQ(ep.serverCertificate, certs().server.der);
    }
    BlockingClient session;
    EXPECT_EQ(session.connect(server.url(), ClientConfig{}), status::BadSecurityPolicyRejected);
}

TEST_F(SecureSession, BestSecurityChoosesTheStrongestEndpoint) {
    auto config = clientConfig(kBestSecurity, MessageSecurityMode::None);
    BlockingClient client;
    ASSERT_EQ(client.connect(server.url(), config), status::Good);
    const auto [policy, mode] = client.security();
    EXPECT_EQ(policy, crypto::kPolicyAes256Sha256RsaPss);
    EXPECT_EQ(mode, MessageSecurityMode::SignAndEncrypt);
    EXPECT_TRUE(client.readValue(NodeId(2259)).ok());
}

TEST_F(SecureSession, BestSecurityChoosesAmongTheEndpointsItWasGiven) {
    // A caller that asked GetEndpoints already (a watcher describing an announced server)
    // hands the answer on: the client chooses among it and does not ask again, so the
    // endpoint chosen is the best of those given, not the best the server has.
    auto endpoints = endpointsOverNone(server.url());
    ASSERT_TRUE(endpoints.ok());
    auto config = clientConfig(kBestSecurity, MessageSecurityMode::None);
    for (const auto& ep : *endpoints) {
        if (ep.securityPolicyUri == crypto::kPolicyBasic256Sha256) config.endpoints.push_back(ep);
    }
    ASSERT_EQ(config.endpoints.size(), 2u);  // Sign, SignAndEncrypt
    BlockingClient client;
    ASSERT_EQ(client.connect(server.url(), config), status::Good);
    const auto [policy, mode] = client.security();
    EXPECT_EQ(policy, crypto::kPolicyBasic256Sha256);
    EXPECT_EQ(mode, MessageSecurityMode::SignAndEncrypt);
    EXPECT_TRUE(client.readValue(NodeId(2259)).ok());
}

TEST_F(SecureSession, BestSecurityNeedsOurCertificate) {
    auto config = clientConfig(kBestSecurity, MessageSecurityMode::None);
    config.security.certificate = ByteString{};
    BlockingClient client;
    EXPECT_EQ(client.connect(server.url(), config), status::BadSecurityPolicyRejected);
}

TEST(BestSecurity, NoneOnlyWhenAllowed) {
    RunningServer insecure;  // offers SecurityPolicy None only
    auto config = clientConfig(kBestSecurity, MessageSecurityMode::None);
    config.security.user = UserCredentials{};
    BlockingClient refused;
    EXPECT_EQ(refused.connect(insecure.url(), config), status::BadSecurityPolicyRejected);
    config.security.allowNone = true;
    BlockingClient allowed;
    ASSERT_EQ(allowed.connect(insecure.url(), config), status::Good);
    EXPECT_EQ(allowed.security().first, kSecurityPolicyNoneUri);
}

namespace {

struct EccCertificates {
    TestCertificate server = makeTestEccCertificate("urn:skillcell:server");
    TestCertificate client = makeTestEccCertificate("urn:skillcell:client");
};

const EccCertificates& eccCerts() {
    static const EccCertificates c;
    return c;
}

/// The secured server above with a P-256 certificate: it offers ECC_nistP256 only, and
/// knows the ECC client's certificate as the user "cell-mes".
ServerConfig eccConfig() {
    ServerConfig config = secureConfig();
    config.description.certificate = eccCerts().server.der;
    config.description.securityEndpoints =
        allSecurityEndpoints(false, {crypto::AsymmetricKey::Kind::EccNistP256});
    config.security.privateKey = eccCerts().server.key;
    config.security.validateCertificate = [](const ByteString& der, std::string_view,
                                             std::string* reason) {
        if (leafCertificate(der.bytes) == leafCertificate(eccCerts().client.der.bytes)) {
            return status::Good;
        }
        *reason = "not in the trust list";
        return StatusCode(0x801A0000);
    };
    auto users = std::make_shared<UserDatabase>();
    EXPECT_TRUE(users->setPassword("olga", RoleSet{Role::Operator}, "operator-pw").isGood());
    EXPECT_TRUE(
        users->setCertificate("cell-mes", RoleSet{Role::Operator}, eccCerts().client.der).isGood());
    config.security.users = users;
    return config;
}

ClientConfig eccClientConfig() {
    ClientConfig c;
    c.security.policyUri = std::string(kBestSecurity);
    c.security.certificate = eccCerts().client.der;
    c.security.privateKey = eccCerts().client.key;
    c.applicationUri = "urn:skillcell:client";
    c.security.user = certificateUser(eccCerts().client);
    return c;
}

}  // namespace

TEST(EccSession, AnEccClientChoosesEccNistP256AndActsAsItsCertificatesUser) {
    RunningServer server{eccConfig(), addTargets};
    BlockingClient client;
    ASSERT_EQ(client.connect(server.url(), eccClientConfig()), status::Good);
    const auto [policy, mode] = client.security();
    EXPECT_EQ(policy, crypto::kPolicyEccNistP256);
    EXPECT_EQ(mode, MessageSecurityMode::SignAndEncrypt);
    EXPECT_EQ(client.writeValue(kTarget, Variant(4.0)), status::Good);  // an Operator
    auto doubled = client.call(NodeId(85), kTwice, {Variant(21.0)});
    ASSERT_TRUE(doubled.ok()) << statusName(doubled.status());
    ASSERT_EQ(doubled->size(), 1u);
    EXPECT_EQ((*doubled)[0], Variant(42.0));
    for (const auto m : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
        auto explicitPolicy = eccClientConfig();
        explicitPolicy.security.policyUri = std::string(crypto::kPolicyEccNistP256);
        explicitPolicy.security.mode = m;
        BlockingClient c;
        ASSERT_EQ(c.connect(server.url(), explicitPolicy), status::Good);
        EXPECT_TRUE(c.readValue(kTarget).ok());
    }
}

TEST(EccSession, P384PeersUseEccNistP384) {
    // Server and client with P-384 certificates: the server offers ECC_nistP384 (ECDSA with
    // SHA-384, HKDF-SHA384, HMAC-SHA384, 96-byte nonces), the client chooses it and acts as
    // its certificate's user.
    using Kind = crypto::AsymmetricKey::Kind;
    static const TestCertificate server384 =
        skillcell::test::makeTestEccCertificate(Kind::EccNistP384, "urn:skillcell:server");
    static const TestCertificate client384 =
        skillcell::test::makeTestEccCertificate(Kind::EccNistP384, "urn:skillcell:client");
    ServerConfig config = eccConfig();
    config.description.certificate = server384.der;
    config.description.securityEndpoints = allSecurityEndpoints(false, {Kind::EccNistP384});
    config.security.privateKey = server384.key;
    config.security.validateCertificate = [](const ByteString& der, std::string_view,
                                             std::string* reason) {
        if (leafCertificate(der.bytes) == leafCertificate(client384.der.bytes)) {
            return status::Good;
        }
        *reason = "not in the trust list";
        return StatusCode(0x801A0000);
    };
    auto users = std::make_shared<UserDatabase>();
    EXPECT_TRUE(users->setCertificate("cell-mes", RoleSet{Role::Operator}, client384.der).isGood());
    config.security.users = users;
    RunningServer server{config, addTargets};
    for (const auto m : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
        ClientConfig c = eccClientConfig();
        c.security.certificate = client384.der;
        c.security.privateKey = client384.key;
        c.security.user = certificateUser(client384);
        if (m == MessageSecurityMode::Sign) {
            c.security.policyUri = std::string(crypto::kPolicyEccNistP384);
            c.security.mode = m;
        }
        BlockingClient client;
        ASSERT_EQ(client.connect(server.url(), c), status::Good);
        EXPECT_EQ(client.security().first, crypto::kPolicyEccNistP384);
        EXPECT_EQ(client.security().second, m);
        EXPECT_EQ(client.writeValue(kTarget, Variant(5.0)), status::Good);  // an Operator
        auto read = client.readValue(kTarget);
        ASSERT_TRUE(read.ok());
    }
    // A P-256 client finds no endpoint it can use.
    BlockingClient p256;
    EXPECT_EQ(p256.connect(server.url(), eccClientConfig()), status::BadSecurityPolicyRejected);
}

TEST(EccSession, PasswordsAndRsaClientsAreNotServedOverEcc) {
    RunningServer server{eccConfig(), addTargets};
    // No password travels over ECC (it would need an EccEncryptedSecret): the endpoints
    // offer certificates only; a client with a password finds no endpoint it can use, or,
    // pinned to ECC_nistP256, no token.
    auto endpoints = endpointsOverNone(server.url());
    ASSERT_TRUE(endpoints.ok());
    ASSERT_EQ(endpoints->size(), 2u);
    for (const auto& ep : *endpoints) {
        EXPECT_EQ(ep.securityPolicyUri, crypto::kPolicyEccNistP256);
        for (const auto& token : ep.userIdentityTokens) {
            EXPECT_NE(token.tokenType, UserTokenType::UserName);
        }
    }
    auto withPassword = eccClientConfig();
    withPassword.security.user = clientConfig(kBestSecurity, {}).security.user;  // olga's password
    BlockingClient password;
    EXPECT_EQ(password.connect(server.url(), withPassword), status::BadSecurityPolicyRejected);
    withPassword.security.policyUri = std::string(crypto::kPolicyEccNistP256);
    withPassword.security.mode = MessageSecurityMode::SignAndEncrypt;
    BlockingClient pinned;
    EXPECT_EQ(pinned.connect(server.url(), withPassword), status::BadIdentityTokenRejected);
    // A client with an RSA certificate finds no endpoint it can use.
    BlockingClient rsa;
    EXPECT_EQ(rsa.connect(server.url(), clientConfig(kBestSecurity, MessageSecurityMode::None)),
              status::BadSecurityPolicyRejected);
}

TEST(EccSession, AServerWithBothCertificatesServesEachClientItsPolicy) {
    // As a component under a cell CA: RSA and ECC endpoints, each with its certificate; the
    // client that has both certificates is one user by either.
    ServerConfig config = secureConfig();
    config.description.eccCertificate = eccCerts().server.der;
    config.security.eccPrivateKey = eccCerts().server.key;
    config.description.securityEndpoints = allSecurityEndpoints(
        false, {crypto::AsymmetricKey::Kind::Rsa, crypto::AsymmetricKey::Kind::EccNistP256});
    config.security.validateCertificate = [](const ByteString& der, std::string_view,
                                             std::string* reason) {
        for (const auto* known : {&certs().client.der, &eccCerts().client.der}) {
            if (leafCertificate(der.bytes) == leafCertificate(known->bytes)) return status::Good;
        }
        *reason = "not in the trust list";
        return StatusCode(0x801A0000);
    };
    auto users = std::make_shared<UserDatabase>();
    ASSERT_TRUE(users->setPassword("olga", RoleSet{Role::Operator}, "operator-pw").isGood());
    ASSERT_TRUE(users
                    ->setCertificates("cell-mes", RoleSet{Role::Operator},
                                      {certs().client.der, eccCerts().client.der})
                    .isGood());
    ASSERT_TRUE(users->setCertificate("robot-cell", RoleSet{Role::Operator}, certs().userCert.der)
                    .isGood());
    config.security.users = users;
    RunningServer server{config, addTargets};

    auto endpoints = endpointsOverNone(server.url());
    ASSERT_TRUE(endpoints.ok());
    EXPECT_EQ(endpoints->size(), 8u);
    for (const auto& ep : *endpoints) {
        const bool ecc = ep.securityPolicyUri == crypto::kPolicyEccNistP256;
        EXPECT_EQ(ep.serverCertificate, ecc ? eccCerts().server.der : certs().server.der);
    }

    // Both certificates, the user the (RSA) application certificate: ECC, as its P-256 user.
    ClientConfig both = clientConfig(kBestSecurity, MessageSecurityMode::None);
    both.security.eccCertificate = eccCerts().client.der;
    both.security.eccPrivateKey = eccCerts().client.key;
    both.security.user = certificateUser(certs().client);
    BlockingClient component;
    ASSERT_EQ(component.connect(server.url(), both), status::Good);
    EXPECT_EQ(component.security().first, crypto::kPolicyEccNistP256);
    EXPECT_EQ(component.writeValue(kTarget, Variant(5.0)), status::Good);  // cell-mes, Operator

    // The same client with a password: the RSA endpoints.
    both.security.user = clientConfig(kBestSecurity, {}).security.user;  // olga's password
    BlockingClient person;
    ASSERT_EQ(person.connect(server.url(), both), status::Good);
    EXPECT_EQ(person.security().first, crypto::kPolicyAes256Sha256RsaPss);

    // The same client acting for a person's RSA user certificate, which cannot sign for
    // ECC: the RSA endpoints.
    both.security.user = certificateUser(certs().userCert);
    BlockingClient personByCertificate;
    ASSERT_EQ(personByCertificate.connect(server.url(), both), status::Good);
    EXPECT_EQ(personByCertificate.security().first, crypto::kPolicyAes256Sha256RsaPss);

    // A client with an RSA certificate only: the RSA endpoints.
    BlockingClient rsaOnly;
    ASSERT_EQ(rsaOnly.connect(server.url(), clientConfig(kBestSecurity, MessageSecurityMode::None)),
              status::Good);
    EXPECT_EQ(rsaOnly.security().first, crypto::kPolicyAes256Sha256RsaPss);
}

TEST(UserDatabaseCertificates, AnApplicationIsOneUserByEachOfItsCertificates) {
    UserDatabase users;
    ASSERT_TRUE(users
                    .setCertificates("cell-mes", RoleSet{Role::Operator},
                                     {certs().client.der, eccCerts().client.der})
                    .isGood());
    for (const auto* der : {&certs().client.der, &eccCerts().client.der}) {
        auto who = users.authenticateCertificate(*der);
        ASSERT_TRUE(who.ok());
        EXPECT_EQ(who->name, "cell-mes");
    }
    EXPECT_FALSE(users.authenticateCertificate(certs().stranger.der).ok());
    // A list with a file that is no certificate changes nothing.
    EXPECT_EQ(
        users.setCertificates("cell-mes", RoleSet{Role::Operator},
                              {certs().stranger.der, ByteString(std::vector<std::uint8_t>{1, 2})}),
        status::BadInvalidArgument);
    EXPECT_TRUE(users.authenticateCertificate(eccCerts().client.der).ok());
    EXPECT_FALSE(users.authenticateCertificate(certs().stranger.der).ok());
    // Setting them again replaces both lines.
    ASSERT_TRUE(
        users.setCertificate("cell-mes", RoleSet{Role::Operator}, certs().stranger.der).isGood());
    EXPECT_FALSE(users.authenticateCertificate(eccCerts().client.der).ok());
    EXPECT_EQ(users.users().size(), 1u);
}

}  // namespace client_security_test
