// src/http on loopback: URLs, the SPARQL form of a request, the user gate against a user
// database, and a TLS server and client that judge each other as the cell's components do.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "http/http_client.hpp"
#include "http/web_server.hpp"
#include "kb/sparql_form.hpp"
#include "temp_dir.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/server/user_database.hpp"

namespace skillcell::http {
namespace {

using namespace std::chrono_literals;

TEST(HttpUrl, ParsesSchemeHostPortAndPath) {
    auto u = HttpUrl::parse("https://localhost:8870/sparql");
    ASSERT_TRUE(u) << u.error();
    EXPECT_TRUE(u->tls);
    EXPECT_EQ(u->host, "localhost");
    EXPECT_EQ(u->port, 8870);
    EXPECT_EQ(u->path, "/sparql");
    EXPECT_EQ(u->toString(), "https://localhost:8870/sparql");
    auto plain = HttpUrl::parse("http://127.0.0.1");
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->port, 80);
    EXPECT_EQ(plain->path, "/");
    auto v6 = HttpUrl::parse("http://[::1]:81/x");
    ASSERT_TRUE(v6);
    EXPECT_EQ(v6->host, "::1");
    EXPECT_EQ(v6->toString(), "http://[::1]:81/x");
    for (const char* bad : {"ftp://h/x", "http://", "http://h:0/", "http://h:70000/", "http://h:x/",
                            "http://u:p@h/", "http://[::1/"}) {
        EXPECT_FALSE(HttpUrl::parse(bad)) << bad;
    }
    EXPECT_NE(HttpUrl::parse("ftp://h/x").error().find("only http:// and https://"),
              std::string::npos);
}

TEST(SparqlForm, TheFirstKeywordAfterThePrologueDecides) {
    using kb::SparqlForm;
    using kb::sparqlForm;
    EXPECT_EQ(sparqlForm("SELECT * WHERE { ?s ?p ?o }"), SparqlForm::Select);
    EXPECT_EQ(sparqlForm("  # a comment\n  ask {}"), SparqlForm::Ask);
    EXPECT_EQ(sparqlForm("PREFIX p: <http://x/#a> BASE <http://b/>\nCONSTRUCT {} WHERE {}"),
              SparqlForm::Construct);
    EXPECT_EQ(sparqlForm("PREFIX : <http://x/> describe :a"), SparqlForm::Describe);
    // Updates, however they are dressed.
    for (const char* u :
         {"INSERT DATA { GRAPH <http://evil.example/> { <a:b> <c:d> <e:f> } }",
          "PREFIX p: <http://x/> DELETE WHERE { ?s ?p ?o }", "# SELECT\nDROP GRAPH <g:x>",
          "DEFINE get:soft \"replace\" SELECT * FROM <http://x/> {}", "SELECTX", "",
          "PREFIX p <http://x/> SELECT * {}", "PREFIX p: SELECT * {}", "LOAD <http://x/>",
          "CLEAR ALL"}) {
        EXPECT_EQ(sparqlForm(u), SparqlForm::Update) << u;
    }
}

class UserGateTest : public testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(
            users_->setPassword("olga", ua::RoleSet{ua::Role::Observer}, "secret-1").isGood());
        ASSERT_TRUE(
            users_->setPassword("emil", ua::RoleSet{ua::Role::Engineer}, "secret-2").isGood());
    }
    static std::string basic(const std::string& userColonPassword) {
        return "Basic " + base64(userColonPassword);
    }
    static std::string base64(const std::string& s) {
        std::string out(4 * ((s.size() + 2) / 3) + 1, '\0');
        const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()),
                                      reinterpret_cast<const unsigned char*>(s.data()),
                                      static_cast<int>(s.size()));
        out.resize(static_cast<std::size_t>(n));
        return out;
    }
    std::shared_ptr<ua::UserDatabase> users_ = std::make_shared<ua::UserDatabase>();
};

TEST_F(UserGateTest, KnowsUsersByBasicCredentialsAndNobodyElse) {
    UserGate gate(users_);
    auto olga = gate.identify(basic("olga:secret-1"), {});
    ASSERT_TRUE(olga);
    EXPECT_EQ(olga->name, "olga");
    EXPECT_TRUE(olga->roles.has(ua::Role::Observer));
    EXPECT_FALSE(olga->roles.atLeast(ua::Role::Engineer));
    // Remembered, and still checked: the wrong password of a remembered user is wrong.
    EXPECT_TRUE(gate.identify(basic("olga:secret-1"), {}));
    EXPECT_FALSE(gate.identify(basic("olga:secret-2"), {}));
    EXPECT_FALSE(gate.identify(basic("emil:secret-1"), {}));
    EXPECT_TRUE(gate.identify("bAsIc   " + base64("emil:secret-2"), {}));
    for (const std::string& bad :
         {std::string(), std::string("Basic"), std::string("Basic !!!!"), std::string("Bearer abc"),
          basic("olga"), basic(":secret-1"), std::string("Basic b2xnYTpzZWNyZXQtMQ")}) {
        EXPECT_EQ(gate.identify(bad, {}).status(), ua::status::BadUserAccessDenied) << bad;
    }
    // A certificate the database does not list identifies nobody, and does not stand in
    // the way of a password.
    const ua::ByteString unknown{std::vector<std::uint8_t>{1, 2, 3}};
    EXPECT_FALSE(gate.identify("", unknown));
    EXPECT_TRUE(gate.identify(basic("olga:secret-1"), unknown));
}

TEST_F(UserGateTest, ALoginIsASessionThatKeepsItsCredentialsUntilLogout) {
    UserGate gate(users_);
    EXPECT_FALSE(gate.login("olga", "wrong"));
    auto session = gate.login("olga", "secret-1");
    ASSERT_TRUE(session);
    EXPECT_EQ(session->first.name, "olga");
    const std::string cookie =
        "other=1; " + std::string(UserGate::kSessionCookie) + "=" + session->second;
    auto who = gate.identify("", {}, cookie);
    ASSERT_TRUE(who);
    EXPECT_EQ(who->name, "olga");
    const auto credentials = gate.sessionCredentials(cookie);
    ASSERT_TRUE(credentials);
    EXPECT_EQ(*credentials, (std::pair<std::string, std::string>{"olga", "secret-1"}));
    // A user known by Basic, or a token nobody issued, has no session to act with.
    EXPECT_FALSE(gate.sessionCredentials(""));
    EXPECT_FALSE(gate.sessionCredentials(std::string(UserGate::kSessionCookie) + "=abc"));
    EXPECT_FALSE(gate.identify("", {}, std::string(UserGate::kSessionCookie) + "=abc"));
    gate.logout(cookie);
    EXPECT_FALSE(gate.identify("", {}, cookie));
    EXPECT_FALSE(gate.sessionCredentials(cookie));
}

TEST(PasswordThrottle, AfterFiveWrongPasswordsANameWaitsLongerEachTime) {
    using namespace std::chrono_literals;
    PasswordThrottle t;
    auto now = PasswordThrottle::Clock::time_point{} + 1h;
    for (int i = 0; i < PasswordThrottle::kFreeFailures; ++i) {
        EXPECT_FALSE(t.refusedFor("olga", now)) << i;
        t.failed("olga", now);
    }
    EXPECT_FALSE(t.refusedFor("olga", now)) << "five wrong passwords are free";
    t.failed("olga", now);
    EXPECT_EQ(t.refusedFor("olga", now), 1s);
    EXPECT_FALSE(t.refusedFor("emil", now)) << "other names are not slowed";
    now += 1s;
    EXPECT_FALSE(t.refusedFor("olga", now));
    t.failed("olga", now);
    EXPECT_EQ(t.refusedFor("olga", now), 2s);
    EXPECT_EQ(t.refusedFor("olga", now + 1500ms), 1s) << "rounded up";
    for (int i = 0; i < 20; ++i) t.failed("olga", now);
    EXPECT_EQ(t.refusedFor("olga", now), PasswordThrottle::kMaxLockout);
    t.succeeded("olga");
    EXPECT_FALSE(t.refusedFor("olga", now)) << "a right password ends the series";
}

TEST_F(UserGateTest, ANameGuessedAtTooOftenIsRefusedWithoutHashingForAWhile) {
    UserGate gate(users_);
    for (int i = 0; i <= PasswordThrottle::kFreeFailures; ++i) {
        EXPECT_EQ(gate.identify(basic("olga:guess" + std::to_string(i)), {}).status(),
                  ua::status::BadUserAccessDenied);
    }
    std::chrono::seconds wait{0};
    EXPECT_EQ(gate.identify(basic("olga:secret-1"), {}, {}, &wait).status(),
              ua::status::BadTooManyOperations)
        << "even the right password, while locked";
    EXPECT_GE(wait.count(), 1);
    EXPECT_EQ(gate.login("olga", "secret-1", &wait).status(), ua::status::BadTooManyOperations);
    EXPECT_TRUE(gate.login("emil", "secret-2")) << "another user is not slowed";
}

TEST_F(UserGateTest, WithoutUsersEveryoneIsAnonymousWithTheGivenRoles) {
    UserGate gate(nullptr, ua::RoleSet{ua::Role::Anonymous, ua::Role::Observer});
    auto who = gate.identify("", {});
    ASSERT_TRUE(who);
    EXPECT_EQ(who->name, "anonymous");
    EXPECT_TRUE(who->roles.has(ua::Role::Observer));
    EXPECT_FALSE(gate.hasUsers());
}

// A server certificate for "localhost" (no IP address), its key, and a user database.
class HttpsLoopback : public UserGateTest {
protected:
    void SetUp() override {
        UserGateTest::SetUp();
        ua::pki::CertificateSubject subject;
        subject.applicationUri = "urn:test:https";
        subject.commonName = "https test";
        subject.dnsNames = {"localhost"};
        std::string error;
        auto issued = ua::pki::createSelfSignedCertificate(subject, &error);
        ASSERT_TRUE(issued) << error;
        certificate_ = issued->der;
        const auto keyFile = dir_.path() / "key.pem";
        std::ofstream(keyFile) << issued->privateKeyPem;
        auto key = ua::crypto::AsymmetricKey::fromPrivateKeyFile(keyFile);
        ASSERT_TRUE(key);
        key_ = *key;
    }
    std::unique_ptr<WebServer> start(bool tls, const std::string& host = "127.0.0.1") {
        WebServerConfig config;
        config.host = host;
        if (tls) config.tls = ServerTls{certificate_, key_, true};
        config.gate =
            std::make_shared<UserGate>(tls ? users_ : nullptr, ua::RoleSet{ua::Role::Anonymous});
        auto server = std::make_unique<WebServer>(std::move(config));
        server->get("/who",
                    [](const httplib::Request& q, httplib::Response& r, const ua::UserIdentity& u) {
                        r.set_content(u.name + " " + q.get_param_value("x"), "text/plain");
                    });
        server->post(
            "/echo", [](const httplib::Request& q, httplib::Response& r, const ua::UserIdentity&) {
                r.set_content(q.get_param_value("a") + "|" + q.get_param_value("b"), "text/plain");
            });
        return server;
    }
    ClientOptions trusting(bool trust) const {
        ClientOptions o;
        o.timeout = 5s;
        o.verifyServer = [trust, expected = certificate_](const ua::ByteString& der,
                                                          std::string* reason) {
            if (trust && der == expected) return true;
            *reason = "not the certificate this test trusts";
            return false;
        };
        return o;
    }
    HttpUrl url(const std::string& host, std::uint16_t port, bool tls) const {
        HttpUrl u;
        u.tls = tls;
        u.host = host;
        u.port = port;
        return u;
    }

    test::TempDir dir_{"skillcell-https"};
    ua::ByteString certificate_;
    ua::crypto::AsymmetricKey key_;
};

TEST_F(HttpsLoopback, ATrustedServerAnswersAKnownUser) {
    auto server = start(true);
    ASSERT_TRUE(server->start());
    auto options = trusting(true);
    options.auth = {ClientAuth::Kind::Basic, "olga", "secret-1"};
    HttpClient client(url("localhost", server->port(), true), options);
    auto reply = client.get("/who", {{"x", "a b&c"}}, "text/plain");
    ASSERT_TRUE(reply) << reply.error();
    EXPECT_EQ(reply->status, 200);
    EXPECT_EQ(reply->body, "olga a b&c");
    // A form body, with what a form must escape.
    auto echo = client.postForm("/echo", {{"a", "x=1&y"}, {"b", "+ %"}}, "");
    ASSERT_TRUE(echo) << echo.error();
    EXPECT_EQ(echo->body, "x=1&y|+ %");
}

TEST_F(HttpsLoopback, NoUserOrAWrongPasswordIs401) {
    auto server = start(true);
    ASSERT_TRUE(server->start());
    HttpClient anonymous(url("localhost", server->port(), true), trusting(true));
    auto reply = anonymous.get("/who", {}, "");
    ASSERT_TRUE(reply) << reply.error();
    EXPECT_EQ(reply->status, 401);
    auto options = trusting(true);
    options.auth = {ClientAuth::Kind::Basic, "olga", "wrong"};
    HttpClient wrong(url("localhost", server->port(), true), options);
    auto again = wrong.get("/who", {}, "");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 401);
    // Guessing on: after five wrong passwords, 429 (with Retry-After) instead of a hash each.
    int status = 0;
    for (int i = 0; i < PasswordThrottle::kFreeFailures + 1; ++i) {
        auto r = wrong.get("/who", {}, "");
        ASSERT_TRUE(r);
        status = r->status;
    }
    EXPECT_EQ(status, 429);
}

TEST_F(HttpsLoopback, AClientRefusesAServerItDoesNotTrustOrThatIsNotTheHostItAskedFor) {
    auto server = start(true);
    ASSERT_TRUE(server->start());
    auto options = trusting(false);
    options.auth = {ClientAuth::Kind::Basic, "olga", "secret-1"};
    HttpClient distrusting(url("localhost", server->port(), true), options);
    auto refused = distrusting.get("/who", {}, "");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.errorKind(), ErrorKind::Unavailable);
    EXPECT_NE(refused.error().find("not the certificate this test trusts"), std::string::npos)
        << refused.error();
    // The certificate names localhost, not 127.0.0.1.
    auto trusted = trusting(true);
    trusted.auth = options.auth;
    HttpClient byAddress(url("127.0.0.1", server->port(), true), trusted);
    auto wrongHost = byAddress.get("/who", {}, "");
    ASSERT_FALSE(wrongHost);
    EXPECT_NE(wrongHost.error().find("does not name the host 127.0.0.1"), std::string::npos)
        << wrongHost.error();
    // And a client without a verifier trusts nobody.
    HttpClient blind(url("localhost", server->port(), true), ClientOptions{});
    EXPECT_FALSE(blind.get("/who", {}, ""));
}

TEST_F(HttpsLoopback, PlainHttpOnlyOnLoopback) {
    auto local = start(false);
    ASSERT_TRUE(local->start());
    HttpClient client(url("127.0.0.1", local->port(), false), ClientOptions{});
    auto reply = client.get("/who", {{"x", "1"}}, "");
    ASSERT_TRUE(reply) << reply.error();
    EXPECT_EQ(reply->body, "anonymous 1");
    auto everywhere = start(false, "0.0.0.0");
    auto refused = everywhere->start();
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("only on a loopback address"), std::string::npos);
    // Plain HTTP to the TLS server is no way in either.
    auto secure = start(true);
    ASSERT_TRUE(secure->start());
    HttpClient plain(url("127.0.0.1", secure->port(), false), ClientOptions{});
    auto none = plain.get("/who", {}, "");
    EXPECT_TRUE(!none || none->status >= 400);
}

TEST_F(HttpsLoopback, AClosedPortIsAnErrorNamingTheServer) {
    std::uint16_t port = 0;
    {
        auto server = start(false);
        ASSERT_TRUE(server->start());
        port = server->port();
    }
    HttpClient client(url("127.0.0.1", port, false), ClientOptions{});
    auto reply = client.get("/who", {}, "");
    ASSERT_FALSE(reply);
    EXPECT_NE(reply.error().find("http://127.0.0.1:" + std::to_string(port)), std::string::npos);
}

}  // namespace
}  // namespace skillcell::http
