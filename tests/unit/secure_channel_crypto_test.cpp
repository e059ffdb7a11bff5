// The security policies on a client and a server SecureChannel wired back to back: every
// policy with Sign and SignAndEncrypt, RSA keys of 2048 and 4096 bits (the latter need the
// extra padding byte) and P-256 keys for ECC_nistP256, multi-chunk messages, renewal, and
// the attacks a channel must refuse.
#include <gtest/gtest.h>

#include <openssl/core_names.h>
#include <openssl/x509.h>
#include <algorithm>
#include <array>
#include <memory>

#include "service_codec.hpp"
#include "test_certificate.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/transport/ecc_security_policy.hpp"
#include "ua/transport/rsa_security_policy.hpp"
#include "ua/transport/secure_channel.hpp"

namespace secure_channel_crypto_test {

using namespace skillcell::ua;
using skillcell::test::makeTestCertificate;
using skillcell::test::makeTestEccCertificate;
using skillcell::test::TestCertificate;
using Bytes = std::vector<std::uint8_t>;
using skillcell::test::decodeService;
using skillcell::test::encodeService;

namespace {

constexpr std::uint32_t kChannelId = 42;

constexpr int kP256 = 256;  // "bits" of the P-256 certificates below
constexpr int kP384 = 384;  // and of the P-384 ones

/// Key generation is the slow part: each size is made once for the whole test program.
const TestCertificate& certificate(int bits, int which) {
    static const TestCertificate c2048a = makeTestCertificate(2048, "urn:test:client");
    static const TestCertificate c2048b = makeTestCertificate(2048, "urn:test:server");
    static const TestCertificate c4096 = makeTestCertificate(4096, "urn:test:big");
    static const TestCertificate p256a = makeTestEccCertificate("urn:test:client");
    static const TestCertificate p256b = makeTestEccCertificate("urn:test:server");
    using Kind = crypto::AsymmetricKey::Kind;
    static const TestCertificate p384a =
        makeTestEccCertificate(Kind::EccNistP384, "urn:test:client");
    static const TestCertificate p384b =
        makeTestEccCertificate(Kind::EccNistP384, "urn:test:server");
    if (bits == 4096) return c4096;
    if (bits == kP256) return which == 0 ? p256a : p256b;
    if (bits == kP384) return which == 0 ? p384a : p384b;
    return which == 0 ? c2048a : c2048b;
}

struct Case {
    const crypto::SecurityPolicyProfile* profile;
    MessageSecurityMode mode;
    int clientBits;
    int serverBits;
};

std::string caseName(const testing::TestParamInfo<Case>& info) {
    std::string name(info.param.profile->shortName);
    name += info.param.mode == MessageSecurityMode::Sign ? "_Sign" : "_SignAndEncrypt";
    name +=
        "_" + std::to_string(info.param.clientBits) + "_" + std::to_string(info.param.serverBits);
    return name;
}

struct SecuredPair {
    TestCertificate clientCert;
    TestCertificate serverCert;
    std::optional<SecureChannel> client;
    std::optional<SecureChannel> server;
    SteadyTime t0{std::chrono::hours(1)};
    std::string selectedUri;

    SecuredPair(const Case& c, TransportLimits limits = {})
        : clientCert(certificate(c.clientBits, 0)), serverCert(certificate(c.serverBits, 1)) {
        SecureChannelConfig clientConfig;
        clientConfig.securityMode = c.mode;
        auto policy = createCertificateSecurityPolicy(*c.profile, clientCert.der, clientCert.key,
                                                      serverCert.der, c.mode);
        EXPECT_TRUE(policy.ok()) << statusName(policy.status());
        client.emplace(SecureChannel::Role::Client, limits, std::move(*policy), clientConfig);
        auto selector =
            [this](
                const AsymmetricSecurityHeader& header) -> Result<std::unique_ptr<SecurityPolicy>> {
            selectedUri = header.securityPolicyUri;
            const auto* profile = crypto::findSecurityPolicyProfile(header.securityPolicyUri);
            if (profile == nullptr) return status::BadSecurityPolicyRejected;
            auto p = createCertificateSecurityPolicy(*profile, serverCert.der, serverCert.key,
                                                     header.senderCertificate,
                                                     MessageSecurityMode::Invalid);
            if (!p) return p.status();
            return std::unique_ptr<SecurityPolicy>(std::move(*p));
        };
        server.emplace(limits, selector, SecureChannelConfig{});
    }

    static Result<ChannelMessage> deliver(SecureChannel& to, const std::vector<Bytes>& frames,
                                          SteadyTime now) {
        std::optional<ChannelMessage> got;
        for (const auto& f : frames) {
            auto r = to.receiveFrame(f, now);
            if (!r) return r.status();
            if (r->has_value()) got = std::move(**r);
        }
        if (!got) return status::BadInternalError;
        return std::move(*got);
    }

    StatusCode handshake(SecurityTokenRequestType type, SteadyTime now) {
        auto frames = client->encodeMessage(MessageType::OpenChannel, 1,
                                            encodeService(client->makeOpenRequest(type)));
        if (!frames) return frames.status();
        auto request = deliver(*server, *frames, now);
        if (!request) return request.status();
        auto response = server->openOrRenew(decodeService<OpenSecureChannelRequest>(request->body),
                                            kChannelId, now);
        if (!response) return response.status();
        auto back = server->encodeMessage(MessageType::OpenChannel, 1, encodeService(*response));
        if (!back) return back.status();
        auto reply = deliver(*client, *back, now);
        if (!reply) return reply.status();
        return client->acceptOpenResponse(decodeService<OpenSecureChannelResponse>(reply->body),
                                          now);
    }

    static void roundTrip(SecureChannel& from, SecureChannel& to, const Bytes& body,
                          SteadyTime now) {
        auto frames = from.encodeMessage(MessageType::Message, 9, body);
        ASSERT_TRUE(frames.ok()) << statusName(frames.status());
        auto m = deliver(to, *frames, now);
        ASSERT_TRUE(m.ok()) << statusName(m.status());
        EXPECT_EQ(m->requestId, 9u);
        EXPECT_EQ(m->body, body);
    }
};

Bytes pattern(std::size_t n) {
    Bytes b(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(i * 7 + 3);
    return b;
}

class SecuredChannel : public testing::TestWithParam<Case> {};

std::vector<Case> allCases() {
    std::vector<Case> cases;
    for (const auto& profile : crypto::securityPolicyProfiles()) {
        if (profile.isEcc()) {
            const int bits =
                profile.keyKind == crypto::AsymmetricKey::Kind::EccNistP384 ? kP384 : kP256;
            for (auto mode : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
                cases.push_back({&profile, mode, bits, bits});
            }
            continue;
        }
        for (auto mode : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
            cases.push_back({&profile, mode, 2048, 2048});
        }
        // Mixed key sizes: 4096 bits on one side exercises ExtraPaddingSize and signatures
        // of another length than the peer's blocks.
        cases.push_back({&profile, MessageSecurityMode::SignAndEncrypt, 4096, 2048});
        cases.push_back({&profile, MessageSecurityMode::Sign, 2048, 4096});
    }
    return cases;
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(AllPolicies, SecuredChannel, testing::ValuesIn(allCases()), caseName);

TEST_P(SecuredChannel, OpensExchangesRenewsAndExchangesAgain) {
    SecuredPair p(GetParam());
    ASSERT_EQ(p.handshake(SecurityTokenRequestType::Issue, p.t0), status::Good);
    EXPECT_EQ(p.selectedUri, GetParam().profile->uri);
    EXPECT_EQ(p.server->securityMode(), GetParam().mode);
    for (std::size_t size : {0u, 1u, 15u, 16u, 17u, 1000u, 200'000u}) {
        SecuredPair::roundTrip(*p.client, *p.server, pattern(size), p.t0);
        SecuredPair::roundTrip(*p.server, *p.client, pattern(size), p.t0);
    }
    const auto later = p.t0 + std::chrono::minutes(8);
    ASSERT_EQ(p.handshake(SecurityTokenRequestType::Renew, later), status::Good);
    // The server answers with the old token's keys until the client uses the new one.
    SecuredPair::roundTrip(*p.server, *p.client, pattern(100), later);
    SecuredPair::roundTrip(*p.client, *p.server, pattern(70'000), later);
    SecuredPair::roundTrip(*p.server, *p.client, pattern(70'000), later);
}

TEST_P(SecuredChannel, EncryptsOnlyInSignAndEncrypt) {
    SecuredPair p(GetParam());
    ASSERT_EQ(p.handshake(SecurityTokenRequestType::Issue, p.t0), status::Good);
    const std::string secret = "the quick brown robot jumps over the lazy gripper";
    auto frames =
        p.client->encodeMessage(MessageType::Message, 3, Bytes(secret.begin(), secret.end()));
    ASSERT_TRUE(frames.ok());
    const auto& f = frames->front();
    const bool visible = std::search(f.begin(), f.end(), secret.begin(), secret.end()) != f.end();
    EXPECT_EQ(visible, GetParam().mode == MessageSecurityMode::Sign);
}

TEST_P(SecuredChannel, RefusesAnyFlippedByte) {
    SecuredPair p(GetParam());
    ASSERT_EQ(p.handshake(SecurityTokenRequestType::Issue, p.t0), status::Good);
    auto frames = p.client->encodeMessage(MessageType::Message, 3, pattern(300));
    ASSERT_TRUE(frames.ok());
    // Every byte after the clear headers is covered by the signature: flipping one of them
    // (sequence header, body, padding or signature) must fail the chunk.
    const Bytes original = frames->front();
    for (std::size_t i = 16; i < original.size(); i += 37) {
        Bytes tampered = original;
        tampered[i] ^= 0x01;
        EXPECT_EQ(p.server->receiveFrame(tampered, p.t0).status(), status::BadSecurityChecksFailed)
            << "byte " << i;
    }
    // The untouched chunk still goes through: failed chunks changed nothing.
    EXPECT_TRUE(p.server->receiveFrame(original, p.t0).ok());
}

TEST_P(SecuredChannel, RefusesAReplayedChunk) {
    SecuredPair p(GetParam());
    ASSERT_EQ(p.handshake(SecurityTokenRequestType::Issue, p.t0), status::Good);
    auto frames = p.client->encodeMessage(MessageType::Message, 3, pattern(10));
    ASSERT_TRUE(frames.ok());
    ASSERT_TRUE(p.server->receiveFrame(frames->front(), p.t0).ok());
    EXPECT_EQ(p.server->receiveFrame(frames->front(), p.t0).status(),
              status::BadSequenceNumberInvalid);
}

TEST(SecuredChannelHandshake, RefusesAnOpenForAnotherCertificate) {
    const Case c{crypto::findSecurityPolicyProfile(crypto::kPolicyBasic256Sha256),
                 MessageSecurityMode::SignAndEncrypt, 2048, 2048};
    SecuredPair p(c);
    // The client thinks the server has another certificate: its OPN names that one.
    const auto& other = certificate(4096, 0);
    auto policy = RsaSecurityPolicy::create(*c.profile, p.clientCert.der, p.clientCert.key,
                                            other.der, c.mode);
    ASSERT_TRUE(policy.ok());
    SecureChannelConfig config;
    config.securityMode = c.mode;
    SecureChannel wrong(SecureChannel::Role::Client, {}, std::move(*policy), config);
    auto frames =
        wrong.encodeMessage(MessageType::OpenChannel, 1,
                            encodeService(wrong.makeOpenRequest(SecurityTokenRequestType::Issue)));
    ASSERT_TRUE(frames.ok());
    EXPECT_EQ(p.server->receiveFrame(frames->front(), p.t0).status(),
              status::BadCertificateInvalid);
}

TEST(SecuredChannelHandshake, SelectorDecidesPolicyAndTrust) {
    const Case c{crypto::findSecurityPolicyProfile(crypto::kPolicyAes256Sha256RsaPss),
                 MessageSecurityMode::Sign, 2048, 2048};
    SecuredPair p(c);
    // A server whose selector does not trust the client.
    SecureChannel distrustful(
        {}, [](const AsymmetricSecurityHeader&) -> Result<std::unique_ptr<SecurityPolicy>> {
            return StatusCode(0x801A0000);  // BadCertificateUntrusted
        });
    auto frames = p.client->encodeMessage(
        MessageType::OpenChannel, 1,
        encodeService(p.client->makeOpenRequest(SecurityTokenRequestType::Issue)));
    ASSERT_TRUE(frames.ok());
    EXPECT_EQ(distrustful.receiveFrame(frames->front(), p.t0).status(), StatusCode(0x801A0000));
    // Without a selector nothing is accepted, and nothing can be sent.
    SecureChannel none({}, SecurityPolicySelector{});
    EXPECT_EQ(none.receiveFrame(frames->front(), p.t0).status(), status::BadSecurityPolicyRejected);
    EXPECT_EQ(none.encodeMessage(MessageType::Message, 1, Bytes{1}).status(),
              status::BadInvalidState);
}

TEST(SecuredChannelHandshake, RefusesWrongNonceAndModeChangeOnRenew) {
    const Case c{crypto::findSecurityPolicyProfile(crypto::kPolicyAes128Sha256RsaOaep),
                 MessageSecurityMode::SignAndEncrypt, 2048, 2048};
    SecuredPair p(c);
    auto request = p.client->makeOpenRequest(SecurityTokenRequestType::Issue);
    auto frames = p.client->encodeMessage(MessageType::OpenChannel, 1, encodeService(request));
    ASSERT_TRUE(frames.ok());
    ASSERT_TRUE(p.server->receiveFrame(frames->front(), p.t0).ok());
    auto shortNonce = request;
    shortNonce.clientNonce.bytes.resize(16);
    EXPECT_EQ(p.server->openOrRenew(shortNonce, kChannelId, p.t0).status(),
              status::BadNonceInvalid);
    auto none = request;
    none.securityMode = MessageSecurityMode::None;
    EXPECT_EQ(p.server->openOrRenew(none, kChannelId, p.t0).status(),
              status::BadSecurityModeRejected);
    ASSERT_TRUE(p.server->openOrRenew(request, kChannelId, p.t0).ok());
    auto renew = request;
    renew.requestType = SecurityTokenRequestType::Renew;
    renew.securityMode = MessageSecurityMode::Sign;
    EXPECT_EQ(p.server->openOrRenew(renew, kChannelId, p.t0).status(),
              status::BadSecurityModeRejected);
}

TEST(CryptoPrimitives, PSha256FollowsItsDefinition) {
    const Bytes secret = pattern(32);
    const Bytes seed = pattern(20);
    // A(1) = HMAC(secret, seed); first block = HMAC(secret, A(1) + seed).
    Bytes a1 = crypto::hmacSha256(secret, seed);
    Bytes input = a1;
    input.insert(input.end(), seed.begin(), seed.end());
    const Bytes first = crypto::hmacSha256(secret, input);
    const Bytes out = crypto::pSha256(secret, seed, 80);
    ASSERT_EQ(out.size(), 80u);
    EXPECT_TRUE(std::equal(first.begin(), first.end(), out.begin()));
    const Bytes a2 = crypto::hmacSha256(secret, a1);
    input = a2;
    input.insert(input.end(), seed.begin(), seed.end());
    const Bytes second = crypto::hmacSha256(secret, input);
    EXPECT_TRUE(std::equal(second.begin(), second.end(), out.begin() + 32));
}

TEST(CryptoPrimitives, RsaRoundTripsAndRefusesForeignSignatures) {
    const auto& a = certificate(2048, 0);
    const auto& b = certificate(2048, 1);
    auto pubA = crypto::AsymmetricKey::fromCertificate(a.der.bytes);
    ASSERT_TRUE(pubA.ok());
    for (auto enc : {crypto::RsaEncryption::OaepSha1, crypto::RsaEncryption::OaepSha256}) {
        const Bytes plain = pattern(700);  // several blocks
        auto cipher = crypto::rsaEncrypt(*pubA, enc, plain);
        ASSERT_TRUE(cipher.ok());
        EXPECT_EQ(cipher->size() % 256, 0u);
        auto back = crypto::rsaDecrypt(a.key, enc, *cipher);
        ASSERT_TRUE(back.ok());
        EXPECT_EQ(*back, plain);
        EXPECT_FALSE(crypto::rsaDecrypt(b.key, enc, *cipher).ok());
    }
    for (auto sig :
         {crypto::SignatureAlgorithm::Pkcs1v15Sha256, crypto::SignatureAlgorithm::PssSha256}) {
        auto s = crypto::sign(b.key, sig, pattern(99));
        ASSERT_TRUE(s.ok());
        EXPECT_EQ(crypto::verify(*pubA, sig, pattern(99), *s), status::BadSecurityChecksFailed);
        EXPECT_EQ(crypto::verify(b.key, sig, pattern(99), *s), status::Good);
    }
    EXPECT_FALSE(crypto::AsymmetricKey::fromCertificate(pattern(50)).ok());
}

// fromCertificate reads an ECC certificate's key from its SubjectPublicKeyInfo alone (d2i_X509
// costs 240 us in OpenSSL 3.0): the key must be the one OpenSSL reads, and a point off the
// curve or DER cut short must give no key.
TEST(CryptoPrimitives, AnEccCertificatesKeyIsTheOneOpenSslReadsFromIt) {
    for (const int bits : {kP256, kP384}) {
        const auto& c = certificate(bits, 0);
        auto key = crypto::AsymmetricKey::fromCertificate(c.der.bytes);
        ASSERT_TRUE(key.ok()) << bits;
        EXPECT_EQ(key->kind(), c.key.kind());
        const unsigned char* p = c.der.bytes.data();
        const std::unique_ptr<X509, void (*)(X509*)> x509(
            d2i_X509(nullptr, &p, static_cast<long>(c.der.bytes.size())), X509_free);
        ASSERT_NE(x509, nullptr);
        EXPECT_EQ(EVP_PKEY_eq(key->get(), X509_get0_pubkey(x509.get())), 1) << bits;
        EXPECT_EQ(EVP_PKEY_eq(key->get(), c.key.get()), 1) << bits;

        // The first certificate of a chain.
        Bytes chain = c.der.bytes;
        const auto& other = certificate(bits, 1);
        chain.insert(chain.end(), other.der.bytes.begin(), other.der.bytes.end());
        auto first = crypto::AsymmetricKey::fromCertificate(chain);
        ASSERT_TRUE(first.ok());
        EXPECT_EQ(EVP_PKEY_eq(first->get(), c.key.get()), 1);

        // The point moved off the curve: its last byte changed.
        std::array<unsigned char, 1 + 2 * 48> point{};
        std::size_t length = 0;
        ASSERT_EQ(EVP_PKEY_get_octet_string_param(c.key.get(), OSSL_PKEY_PARAM_PUB_KEY,
                                                  point.data(), point.size(), &length),
                  1);
        const auto at = std::search(c.der.bytes.begin(), c.der.bytes.end(), point.begin(),
                                    point.begin() + static_cast<std::ptrdiff_t>(length));
        ASSERT_NE(at, c.der.bytes.end());
        Bytes offCurve = c.der.bytes;
        offCurve[static_cast<std::size_t>(at - c.der.bytes.begin()) + length - 1] ^= 0x01;
        EXPECT_FALSE(crypto::AsymmetricKey::fromCertificate(offCurve).ok()) << bits;

        // Cut inside the key.
        const Bytes cut(c.der.bytes.begin(), at + 10);
        EXPECT_FALSE(crypto::AsymmetricKey::fromCertificate(cut).ok()) << bits;
    }
}

TEST(SecuredChannelHandshake, EccOpensWithEphemeralKeysSignedNotEncrypted) {
    const Case c{crypto::findSecurityPolicyProfile(crypto::kPolicyEccNistP256),
                 MessageSecurityMode::SignAndEncrypt, kP256, kP256};
    SecuredPair p(c);
    const auto request = p.client->makeOpenRequest(SecurityTokenRequestType::Issue);
    // The nonce is a point of P-256 (X || Y), not random bytes: a second one differs.
    ASSERT_EQ(request.clientNonce.bytes.size(), 64u);
    auto frames = p.client->encodeMessage(MessageType::OpenChannel, 1, encodeService(request));
    ASSERT_TRUE(frames.ok());
    // Signed only (6.8.1): the nonce is readable in the chunk, the signature is r || s.
    const Bytes& f = frames->front();
    EXPECT_NE(std::search(f.begin(), f.end(), request.clientNonce.bytes.begin(),
                          request.clientNonce.bytes.end()),
              f.end());
    // Any flipped byte of the sequence header, body or signature fails the chunk.
    for (std::size_t i = f.size() - 100; i < f.size(); i += 9) {
        Bytes tampered = f;
        tampered[i] ^= 0x01;
        EXPECT_EQ(p.server->receiveFrame(tampered, p.t0).status(), status::BadSecurityChecksFailed)
            << "byte " << i;
    }
    auto received = p.server->receiveFrame(f, p.t0);
    ASSERT_TRUE(received.ok());
    // A nonce that is not a point of the curve yields no keys and changes nothing.
    auto offCurve = request;
    offCurve.clientNonce.bytes.assign(64, 0x07);
    EXPECT_EQ(p.server->openOrRenew(offCurve, kChannelId, p.t0).status(), status::BadNonceInvalid);
    EXPECT_EQ(p.server->openOrRenew(request, kChannelId, p.t0).status(), status::Good);
}

TEST(SecuredChannelHandshake, EccRefusesRsaCertificatesAndRsaRefusesEcc) {
    const auto* ecc = crypto::findSecurityPolicyProfile(crypto::kPolicyEccNistP256);
    const auto* rsa = crypto::findSecurityPolicyProfile(crypto::kPolicyAes256Sha256RsaPss);
    const auto& rsaCert = certificate(2048, 0);
    const auto& eccCert = certificate(kP256, 1);
    const auto mode = MessageSecurityMode::Sign;
    // Our key of the wrong kind is our configuration's fault; the peer's, its certificate's.
    EXPECT_EQ(EccSecurityPolicy::create(*ecc, rsaCert.der, rsaCert.key, eccCert.der, mode).status(),
              status::BadConfigurationError);
    EXPECT_EQ(EccSecurityPolicy::create(*ecc, eccCert.der, eccCert.key, rsaCert.der, mode).status(),
              status::BadCertificateInvalid);
    EXPECT_EQ(RsaSecurityPolicy::create(*rsa, rsaCert.der, rsaCert.key, eccCert.der, mode).status(),
              status::BadCertificateInvalid);
    EXPECT_TRUE(createCertificateSecurityPolicy(*ecc, eccCert.der, eccCert.key,
                                                certificate(kP256, 0).der, mode)
                    .ok());
}

TEST(CryptoPrimitives, HkdfSha256MatchesRfc5869) {
    // RFC 5869, A.1 (test case 1).
    const Bytes ikm(22, 0x0b);
    Bytes salt;
    for (std::uint8_t i = 0; i <= 0x0c; ++i) salt.push_back(i);
    Bytes info;
    for (std::uint8_t i = 0xf0; i <= 0xf9; ++i) info.push_back(i);
    const Bytes expected = {0x3c, 0xb2, 0x5f, 0x25, 0xfa, 0xac, 0xd5, 0x7a, 0x90, 0x43, 0x4f,
                            0x64, 0xd0, 0x36, 0x2f, 0x2a, 0x2d, 0x2d, 0x0a, 0x90, 0xcf, 0x1a,
                            0x5a, 0x4c, 0x5d, 0xb0, 0x2d, 0x56, 0xec, 0xc4, 0xc5, 0xbf, 0x34,
                            0x00, 0x72, 0x08, 0xd5, 0xb8, 0x87, 0x18, 0x58, 0x65};
    auto okm = crypto::hkdfSha256(salt, ikm, info, 42);
    ASSERT_TRUE(okm.ok());
    EXPECT_EQ(*okm, expected);
}

TEST(CryptoPrimitives, EcdhAgreesAndEcdsaSignaturesAreRAndS) {
    auto a = crypto::EphemeralKey::generateNistP256();
    auto b = crypto::EphemeralKey::generateNistP256();
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->publicKey().size(), 64u);
    auto ab = a->agree(b->publicKey());
    auto ba = b->agree(a->publicKey());
    ASSERT_TRUE(ab.ok() && ba.ok());
    EXPECT_EQ(ab->size(), 32u);
    EXPECT_EQ(*ab, *ba);
    EXPECT_EQ(a->agree(Bytes(64, 0x07)).status(), status::BadNonceInvalid);
    EXPECT_EQ(a->agree(Bytes(63, 0x07)).status(), status::BadNonceInvalid);

    const auto& signer = certificate(kP256, 0);
    auto pub = crypto::AsymmetricKey::fromCertificate(signer.der.bytes);
    ASSERT_TRUE(pub.ok());
    EXPECT_EQ(pub->kind(), crypto::AsymmetricKey::Kind::EccNistP256);
    const auto alg = crypto::SignatureAlgorithm::EcdsaSha256;
    for (std::size_t n = 99; n < 119; ++n) {  // r and s with leading zero bytes stay 32 each
        auto s = crypto::sign(signer.key, alg, pattern(n));
        ASSERT_TRUE(s.ok());
        ASSERT_EQ(s->size(), 64u);
        EXPECT_EQ(crypto::verify(*pub, alg, pattern(n), *s), status::Good);
        Bytes bad = *s;
        bad[10] ^= 0x01;
        EXPECT_EQ(crypto::verify(*pub, alg, pattern(n), bad), status::BadSecurityChecksFailed);
    }
    // A key of the wrong kind for the algorithm signs and verifies nothing.
    EXPECT_FALSE(crypto::sign(certificate(2048, 0).key, alg, pattern(9)).ok());
    EXPECT_FALSE(crypto::sign(signer.key, crypto::SignatureAlgorithm::PssSha256, pattern(9)).ok());
}

TEST(CryptoPrimitives, P384AgreesAndSignsWithSha384) {
    using Kind = crypto::AsymmetricKey::Kind;
    auto a = crypto::EphemeralKey::generate(Kind::EccNistP384);
    auto b = crypto::EphemeralKey::generate(Kind::EccNistP384);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->publicKey().size(), 96u);
    auto ab = a->agree(b->publicKey());
    auto ba = b->agree(a->publicKey());
    ASSERT_TRUE(ab.ok() && ba.ok());
    EXPECT_EQ(ab->size(), 48u);
    EXPECT_EQ(*ab, *ba);
    // A P-256 point is no P-384 nonce, nor is a point off the curve.
    auto p256 = crypto::EphemeralKey::generateNistP256();
    ASSERT_TRUE(p256.ok());
    EXPECT_EQ(a->agree(p256->publicKey()).status(), status::BadNonceInvalid);
    EXPECT_EQ(a->agree(Bytes(96, 0x07)).status(), status::BadNonceInvalid);

    const auto& signer = certificate(kP384, 0);
    auto pub = crypto::AsymmetricKey::fromCertificate(signer.der.bytes);
    ASSERT_TRUE(pub.ok());
    EXPECT_EQ(pub->kind(), Kind::EccNistP384);
    EXPECT_EQ(pub->sizeBytes(), 96u);
    const auto alg = crypto::SignatureAlgorithm::EcdsaSha384;
    auto s = crypto::sign(signer.key, alg, pattern(100));
    ASSERT_TRUE(s.ok());
    ASSERT_EQ(s->size(), 96u);
    EXPECT_EQ(crypto::verify(*pub, alg, pattern(100), *s), status::Good);
    EXPECT_EQ(crypto::verify(*pub, alg, pattern(101), *s), status::BadSecurityChecksFailed);
    // Each curve signs with its own hash only.
    EXPECT_FALSE(
        crypto::sign(signer.key, crypto::SignatureAlgorithm::EcdsaSha256, pattern(9)).ok());
    EXPECT_FALSE(crypto::sign(certificate(kP256, 0).key, alg, pattern(9)).ok());

    // HKDF-SHA384: as long as asked, and not the SHA-256 derivation.
    const Bytes salt(16, 0x01);
    const Bytes secret(48, 0x02);
    auto k384 = crypto::hkdf(crypto::HashAlgorithm::Sha384, salt, secret, salt, 96);
    auto k256 = crypto::hkdf(crypto::HashAlgorithm::Sha256, salt, secret, salt, 96);
    ASSERT_TRUE(k384.ok() && k256.ok());
    EXPECT_EQ(k384->size(), 96u);
    EXPECT_NE(*k384, *k256);
    EXPECT_EQ(crypto::hmac(crypto::HashAlgorithm::Sha384, salt, secret).size(), 48u);
}

TEST(CertificateChain, TheLeafIsTheFirstDerElementAndNothingElse) {
    const Bytes leaf = certificate(2048, 0).der.bytes;
    const Bytes issuer = certificate(2048, 1).der.bytes;
    ASSERT_GT(leaf.size(), 256u);  // a two-octet length: 0x30 0x82 hi lo
    EXPECT_EQ(leafCertificate(leaf), leaf);
    Bytes chain = leaf;
    chain.insert(chain.end(), issuer.begin(), issuer.end());
    EXPECT_EQ(leafCertificate(chain), leaf);
    // Truncated inside the leaf, or its length field cut short: nothing.
    EXPECT_TRUE(leafCertificate(std::span(leaf).first(leaf.size() - 1)).empty());
    EXPECT_TRUE(leafCertificate(std::span(leaf).first(3)).empty());
    EXPECT_TRUE(leafCertificate(Bytes{}).empty());
    // Not a SEQUENCE; an indefinite length (BER, not DER); a length in more octets than
    // DER allows; a long form for a length the short form holds.
    EXPECT_TRUE(leafCertificate(pattern(50)).empty());
    EXPECT_TRUE(leafCertificate(Bytes{0x30, 0x80, 0x00, 0x00}).empty());
    EXPECT_TRUE(leafCertificate(Bytes{0x30, 0x82, 0x00, 0x02, 0x05, 0x00}).empty());
    EXPECT_TRUE(leafCertificate(Bytes{0x30, 0x81, 0x02, 0x05, 0x00}).empty());
    EXPECT_EQ(leafCertificate(Bytes{0x30, 0x02, 0x05, 0x00, 0xFF}),
              (Bytes{0x30, 0x02, 0x05, 0x00}));
}

}  // namespace secure_channel_crypto_test
