// CertificateValidator against PKI directories built in temporary directories.
#include <gtest/gtest.h>

#include <openssl/pem.h>

#include <chrono>
#include <filesystem>

#include "pki_test_support.hpp"
#include "ua/pki/certificate.hpp"
#include "ua/pki/certificate_validator.hpp"
#include "ua/pki/file_util.hpp"
#include "ua/pki/trust_list.hpp"

namespace skillcell::ua::pki::pki_validator_test {
namespace {

namespace fs = std::filesystem;
using test::CertSpec;
using test::KeyAndCert;

class ValidatorTest : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_TRUE(createPkiLayout(dir.path()).isGood()); }
    [[nodiscard]] PkiPaths paths() const { return PkiPaths{dir.path()}; }
    void trust(const KeyAndCert& c, const std::string& name) const {
        test::writeFile(paths().trustedCerts() / (name + ".der"), c.der());
    }
    void trustCrl(const KeyAndCert& ca, const std::vector<const KeyAndCert*>& revoked,
                  const std::string& name) const {
        test::writeCrl(paths().trustedCrl() / (name + ".crl"), test::makeCrl(ca, revoked).get());
    }
    [[nodiscard]] std::size_t rejectedCount() const {
        return listCertificates(paths().rejectedCerts()).size();
    }

    test::TempDir dir;
};

TEST_F(ValidatorTest, TrustedSelfSignedIsAccepted) {
    const auto peer = test::makeCertificate({});
    trust(peer, "peer");
    CertificateValidator validator(dir.path());
    const auto v = validator.validate(peer.der(), "urn:test:peer");
    EXPECT_EQ(v.status, status::Good) << v.reason;
    EXPECT_EQ(v.thumbprint, certificateThumbprintHex(peer.der()));
    EXPECT_EQ(rejectedCount(), 0u);
}

TEST_F(ValidatorTest, UnknownSelfSignedIsUntrustedAndCopiedToRejected) {
    const auto peer = test::makeCertificate({});
    CertificateValidator validator(dir.path());
    const auto v = validator.validate(peer.der(), "urn:test:peer");
    EXPECT_EQ(v.status, status::BadCertificateUntrusted) << v.reason;
    ASSERT_FALSE(v.rejectedFile.empty());
    EXPECT_EQ(v.rejectedFile, paths().rejectedCerts() / (v.thumbprint + ".der"));
    EXPECT_EQ(readWholeFile(v.rejectedFile), peer.der().bytes);
    EXPECT_NE(v.reason.find("trust"), std::string::npos) << v.reason;
}

TEST_F(ValidatorTest, MovingTheRejectedFileToTrustedAcceptsWithoutRestart) {
    const auto peer = test::makeCertificate({});
    CertificateValidator validator(dir.path());
    const auto first = validator.validate(peer.der(), "urn:test:peer");
    ASSERT_EQ(first.status, status::BadCertificateUntrusted);
    auto moved = moveCertificateFile(first.rejectedFile, paths().trustedCerts());
    ASSERT_TRUE(moved);
    const auto second = validator.validate(peer.der(), "urn:test:peer");
    EXPECT_EQ(second.status, status::Good) << second.reason;
    // And back: removing it from trusted/ withdraws the trust.
    fs::remove(*moved);
    EXPECT_EQ(validator.validate(peer.der(), "urn:test:peer").status,
              status::BadCertificateUntrusted);
}

TEST_F(ValidatorTest, ExpiredAndNotYetValidAreTimeInvalid) {
    CertSpec expired;
    expired.notBeforeDays = -30;
    expired.notAfterDays = -1;
    CertSpec future;
    future.notBeforeDays = 2;
    future.notAfterDays = 30;
    const auto a = test::makeCertificate(expired);
    const auto b = test::makeCertificate(future);
    trust(a, "a");
    trust(b, "b");
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(a.der()).status, status::BadCertificateTimeInvalid);
    EXPECT_EQ(validator.validate(b.der()).status, status::BadCertificateTimeInvalid);
    // The clock is an input: at a time inside its period the expired one is fine.
    PeerExpectations then;
    then.now = Clock::now() - std::chrono::hours(24 * 10);
    EXPECT_EQ(validator.validate(a.der(), then).status, status::Good);
}

TEST_F(ValidatorTest, AGoodVerdictHoldsOnlyForItsPeriodAndItsExpectations) {
    // Good verdicts are remembered (a channel's certificate comes again as its user token);
    // what was remembered must not answer another question.
    CertSpec spec;
    spec.notBeforeDays = -1;
    spec.notAfterDays = 5;
    const auto peer = test::makeCertificate(spec);
    trust(peer, "peer");
    CertificateValidator validator(dir.path());
    ASSERT_EQ(validator.validate(peer.der(), "urn:test:peer").status, status::Good);
    ASSERT_EQ(validator.validate(peer.der(), "urn:test:peer").status, status::Good);
    EXPECT_EQ(validator.validate(peer.der(), "urn:test:someone-else").status,
              status::BadCertificateUriInvalid);
    PeerExpectations later;
    later.applicationUri = "urn:test:peer";
    later.now = Clock::now() + std::chrono::hours(24 * 6);
    EXPECT_EQ(validator.validate(peer.der(), later).status, status::BadCertificateTimeInvalid);
    PeerExpectations earlier = later;
    earlier.now = Clock::now() - std::chrono::hours(24 * 2);
    EXPECT_EQ(validator.validate(peer.der(), earlier).status, status::BadCertificateTimeInvalid);
    EXPECT_EQ(validator.validate(peer.der(), "urn:test:peer").status, status::Good);
}

TEST_F(ValidatorTest, ARememberedVerdictAnswersOtherExpectationsTheLeafMeets) {
    // A server checks a client's certificate without its application URI when the channel
    // opens, then with it when the session is created: one verification of the chain.
    const auto peer = test::makeCertificate({});
    trust(peer, "peer");
    CertificateValidator validator(dir.path());
    ASSERT_EQ(validator.validate(peer.der()).status, status::Good);
    ASSERT_EQ(validator.fullValidations(), 1U);
    EXPECT_EQ(validator.validate(peer.der(), "urn:test:peer").status, status::Good);
    PeerExpectations host;
    host.hostName = "localhost";
    host.minimumKeyBits = 2048;
    host.maximumKeyBits = 4096;
    EXPECT_EQ(validator.validate(peer.der(), host).status, status::Good);
    EXPECT_EQ(validator.fullValidations(), 1U);
    // One the leaf misses is refused as in full, with its reason.
    const auto uri = validator.validate(peer.der(), "urn:test:someone-else");
    EXPECT_EQ(uri.status, status::BadCertificateUriInvalid);
    EXPECT_NE(uri.reason.find("urn:test:peer"), std::string::npos) << uri.reason;
    host.hostName = "robot.example";
    EXPECT_EQ(validator.validate(peer.der(), host).status, status::BadCertificateHostNameInvalid);
    host.hostName.clear();
    host.minimumKeyBits = 3072;
    EXPECT_EQ(validator.validate(peer.der(), host).status, status::BadCertificatePolicyCheckFailed);
    EXPECT_EQ(validator.fullValidations(), 4U);
    // Another certificate is verified in full.
    const auto other = test::makeCertificate({});
    trust(other, "other");
    EXPECT_EQ(validator.validate(other.der()).status, status::Good);
    EXPECT_EQ(validator.fullValidations(), 5U);
}

TEST_F(ValidatorTest, WrongApplicationUriIsUriInvalid) {
    const auto peer = test::makeCertificate({});
    trust(peer, "peer");
    CertificateValidator validator(dir.path());
    const auto v = validator.validate(peer.der(), "urn:test:someone-else");
    EXPECT_EQ(v.status, status::BadCertificateUriInvalid);
    EXPECT_NE(v.reason.find("urn:test:peer"), std::string::npos) << v.reason;
    EXPECT_EQ(validator.validate(peer.der(), "").status, status::Good);  // empty: unchecked
}

TEST_F(ValidatorTest, HostNameIsCheckedWhenGiven) {
    const auto peer = test::makeCertificate({});
    trust(peer, "peer");
    CertificateValidator validator(dir.path());
    PeerExpectations e;
    e.hostName = "localhost";
    EXPECT_EQ(validator.validate(peer.der(), e).status, status::Good);
    e.hostName = "robot.example";
    EXPECT_EQ(validator.validate(peer.der(), e).status, status::BadCertificateHostNameInvalid);
}

TEST_F(ValidatorTest, KeyLengthOutsideThePolicyIsPolicyCheckFailed) {
    CertSpec spec;
    spec.keyBits = 1024;
    const auto small = test::makeCertificate(spec);
    const auto fine = test::makeCertificate({});
    trust(small, "small");
    trust(fine, "fine");
    CertificateValidator validator(dir.path());
    PeerExpectations basic256Sha256;
    basic256Sha256.minimumKeyBits = 2048;
    basic256Sha256.maximumKeyBits = 4096;
    const auto v = validator.validate(small.der(), basic256Sha256);
    EXPECT_EQ(v.status, status::BadCertificatePolicyCheckFailed) << v.reason;
    EXPECT_EQ(validator.validate(fine.der(), basic256Sha256).status, status::Good);
    EXPECT_EQ(validator.validate(small.der()).status, status::Good);  // no bounds given
    // The policy check comes before the trust list: an untrusted small key is not rejected/.
    const auto stranger = test::makeCertificate(spec);
    EXPECT_EQ(validator.validate(stranger.der(), basic256Sha256).status,
              status::BadCertificatePolicyCheckFailed);
    EXPECT_EQ(rejectedCount(), 0u);
}

TEST_F(ValidatorTest, CaIssuedLeafIsAcceptedWhenTheCaIsTrusted) {
    const auto ca = test::makeCa("cell CA");
    const auto leaf = test::makeCertificate({}, &ca);
    trust(ca, "ca");
    trustCrl(ca, {}, "ca");
    CertificateValidator validator(dir.path());
    const auto alone = validator.validate(leaf.der(), "urn:test:peer");
    EXPECT_EQ(alone.status, status::Good) << alone.reason;
    const auto chained = validator.validate(test::concat(leaf.der(), ca.der()), "urn:test:peer");
    EXPECT_EQ(chained.status, status::Good) << chained.reason;
}

TEST_F(ValidatorTest, IntermediateSentInTheChainCompletesIt) {
    const auto root = test::makeCa("root");
    const auto intermediate = test::makeCa("intermediate", &root);
    const auto leaf = test::makeCertificate({}, &intermediate);
    trust(root, "root");
    trustCrl(root, {}, "root");
    test::writeCrl(paths().issuersCrl() / "intermediate.crl",
                   test::makeCrl(intermediate, {}).get());
    CertificateValidator validator(dir.path());
    const auto chained = validator.validate(test::concat(leaf.der(), intermediate.der()));
    EXPECT_EQ(chained.status, status::Good) << chained.reason;
    // Without the intermediate the chain cannot be built; issuers/certs completes it too.
    const auto alone = validator.validate(leaf.der());
    EXPECT_EQ(alone.status, status::BadCertificateChainIncomplete) << alone.reason;
    EXPECT_FALSE(alone.rejectedFile.empty());
    test::writeFile(paths().issuersCerts() / "intermediate.der", intermediate.der());
    EXPECT_EQ(validator.validate(leaf.der()).status, status::Good);
}

TEST_F(ValidatorTest, CaOnlyInIssuersIsNotTrusted) {
    const auto ca = test::makeCa("issuer only");
    const auto leaf = test::makeCertificate({}, &ca);
    test::writeFile(paths().issuersCerts() / "ca.der", ca.der());
    test::writeCrl(paths().issuersCrl() / "ca.crl", test::makeCrl(ca, {}).get());
    CertificateValidator validator(dir.path());
    const auto v = validator.validate(test::concat(leaf.der(), ca.der()));
    EXPECT_EQ(v.status, status::BadCertificateUntrusted) << v.reason;
    EXPECT_EQ(readWholeFile(v.rejectedFile), leaf.der().bytes);  // the leaf, not the chain
}

TEST_F(ValidatorTest, RevokedLeafAndRevokedIssuer) {
    const auto root = test::makeCa("root");
    const auto intermediate = test::makeCa("intermediate", &root);
    const auto good = test::makeCertificate({}, &root);
    const auto bad = test::makeCertificate({}, &root);
    const auto underIntermediate = test::makeCertificate({}, &intermediate);
    trust(root, "root");
    trustCrl(root, {&bad}, "root");
    test::writeCrl(paths().issuersCrl() / "intermediate.crl",
                   test::makeCrl(intermediate, {}).get());
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(good.der()).status, status::Good);
    const auto v = validator.validate(bad.der());
    EXPECT_EQ(v.status, status::BadCertificateRevoked) << v.reason;
    EXPECT_TRUE(v.rejectedFile.empty());  // revoked is not "to be trusted by an operator"
    const auto chain = test::concat(underIntermediate.der(), intermediate.der());
    EXPECT_EQ(validator.validate(chain).status, status::Good);
    trustCrl(root, {&bad, &intermediate}, "root");  // replaced: the lists reload
    EXPECT_EQ(validator.validate(chain).status, status::BadCertificateIssuerRevoked);
}

TEST_F(ValidatorTest, MissingCrlIsRevocationUnknownUnlessRelaxed) {
    const auto ca = test::makeCa("no crl");
    const auto leaf = test::makeCertificate({}, &ca);
    trust(ca, "ca");
    CertificateValidator strict(dir.path());
    EXPECT_EQ(strict.validate(leaf.der()).status, status::BadCertificateRevocationUnknown);
    ValidatorOptions relaxed;
    relaxed.requireRevocationLists = false;
    CertificateValidator lenient(dir.path(), relaxed);
    EXPECT_EQ(lenient.validate(leaf.der()).status, status::Good);
    // A leaf trusted itself needs no CRL of its issuer.
    const auto other = test::makeCa("other");
    const auto pinned = test::makeCertificate({}, &other);
    trust(pinned, "pinned");
    EXPECT_EQ(strict.validate(pinned.der()).status, status::Good);
}

TEST_F(ValidatorTest, ExpiredIssuerIsIssuerTimeInvalid) {
    const auto root = test::makeCa("root");
    const auto ca = test::makeCa("intermediate", &root);
    CertSpec spec;
    spec.commonName = "expired intermediate";
    spec.ca = true;
    spec.keyUsage = "critical,keyCertSign,cRLSign";
    spec.notBeforeDays = -30;
    spec.notAfterDays = -1;
    const auto expired = test::makeCertificate(spec, &root);
    const auto leaf = test::makeCertificate({}, &expired);
    trust(root, "root");
    trustCrl(root, {}, "root");
    test::writeCrl(paths().issuersCrl() / "expired.crl", test::makeCrl(expired, {}).get());
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(test::concat(leaf.der(), expired.der())).status,
              status::BadCertificateIssuerTimeInvalid);
}

TEST_F(ValidatorTest, GarbageIsInvalid) {
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(ByteString{}).status, status::BadCertificateInvalid);
    EXPECT_EQ(validator.validate(ByteString({0x30, 0x82, 0x01, 0x00, 0x01})).status,
              status::BadCertificateInvalid);
    const auto peer = test::makeCertificate({});
    trust(peer, "peer");
    auto truncated = peer.der();
    truncated.bytes.resize(truncated.bytes.size() / 2);
    EXPECT_EQ(validator.validate(truncated).status, status::BadCertificateInvalid);
    EXPECT_EQ(validator.validate(test::concat(peer.der(), ByteString({1, 2, 3}))).status,
              status::BadCertificateInvalid);
    EXPECT_EQ(rejectedCount(), 0u);
}

TEST_F(ValidatorTest, TamperedSignatureIsInvalid) {
    const auto ca = test::makeCa("ca");
    const auto leaf = test::makeCertificate({}, &ca);
    const auto self = test::makeCertificate({});
    trust(ca, "ca");
    trustCrl(ca, {}, "ca");
    trust(self, "self");
    CertificateValidator validator(dir.path());
    for (const auto* c : {&leaf, &self}) {
        auto der = c->der();
        der.bytes[der.bytes.size() - 10] ^= 0x01;  // inside the signature value
        const auto v = validator.validate(der);
        EXPECT_EQ(v.status, status::BadCertificateInvalid) << v.reason;
        EXPECT_TRUE(v.rejectedFile.empty());
    }
    // An untrusted self-signed certificate with a broken signature is invalid, not untrusted.
    const auto stranger = test::makeCertificate({});
    auto der = stranger.der();
    der.bytes[der.bytes.size() - 10] ^= 0x01;
    EXPECT_EQ(validator.validate(der).status, status::BadCertificateInvalid);
    EXPECT_EQ(rejectedCount(), 0u);
}

TEST_F(ValidatorTest, KeyUsageWithoutKeyEnciphermentIsUseNotAllowed) {
    CertSpec spec;
    spec.keyUsage = "critical,digitalSignature,keyCertSign";
    const auto peer = test::makeCertificate(spec);
    trust(peer, "peer");
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(peer.der()).status, status::BadCertificateUseNotAllowed);
}

TEST_F(ValidatorTest, CaCertificateAsApplicationCertificateIsUseNotAllowed) {
    const auto root = test::makeCa("root");
    const auto sub = test::makeCa("sub", &root);
    trust(root, "root");
    trustCrl(root, {}, "root");
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(sub.der()).status, status::BadCertificateUseNotAllowed);
}

TEST_F(ValidatorTest, RejectedDirectoryIsBounded) {
    ValidatorOptions options;
    options.maxRejectedFiles = 3;
    CertificateValidator validator(dir.path(), options);
    std::vector<std::string> thumbprints;
    for (int i = 0; i < 5; ++i) {
        const auto peer = test::makeCertificate({});
        const auto v = validator.validate(peer.der());
        ASSERT_EQ(v.status, status::BadCertificateUntrusted);
        thumbprints.push_back(v.thumbprint);
        // Distinct mtimes, so that "oldest" is well defined.
        fs::last_write_time(v.rejectedFile,
                            fs::file_time_type::clock::now() - std::chrono::seconds(100 - i));
    }
    EXPECT_EQ(rejectedCount(), 3u);
    EXPECT_FALSE(fs::exists(paths().rejectedCerts() / (thumbprints[0] + ".der")));
    EXPECT_TRUE(fs::exists(paths().rejectedCerts() / (thumbprints[4] + ".der")));
}

TEST_F(ValidatorTest, PemFilesInTrustedAreRead) {
    const auto peer = test::makeCertificate({});
    const ossl::Bio bio(BIO_new(BIO_s_mem()));
    ASSERT_EQ(PEM_write_bio_X509(bio.get(), peer.cert.get()), 1);
    char* data = nullptr;
    const long len = BIO_get_mem_data(bio.get(), &data);
    test::writeFile(paths().trustedCerts() / "peer.pem",
                    ByteString(std::vector<std::uint8_t>(data, data + len)));
    CertificateValidator validator(dir.path());
    EXPECT_EQ(validator.validate(peer.der()).status, status::Good);
}

// Some stacks leave keyCertSign out of self-signed application certificates, which OpenSSL
// treats differently when building chains. Trusted they must pass; untrusted they must land in
// rejected/ like any other unknown self-signed certificate.
TEST_F(ValidatorTest, SelfSignedWithoutKeyCertSign) {
    CertSpec spec;
    spec.keyUsage = "critical,digitalSignature,nonRepudiation,keyEncipherment,dataEncipherment";
    const auto peer = test::makeCertificate(spec);
    CertificateValidator validator(dir.path());
    const auto untrusted = validator.validate(peer.der());
    EXPECT_EQ(untrusted.status, status::BadCertificateUntrusted) << untrusted.reason;
    EXPECT_FALSE(untrusted.rejectedFile.empty());
    trust(peer, "peer");
    const auto trusted = validator.validate(peer.der());
    EXPECT_EQ(trusted.status, status::Good) << trusted.reason;
}

}  // namespace
}  // namespace skillcell::ua::pki::pki_validator_test
