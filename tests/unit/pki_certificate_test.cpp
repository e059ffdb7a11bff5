// Certificate inspection: chains, thumbprints, names, validity, public keys.
#include <gtest/gtest.h>
#include <openssl/evp.h>

#include <algorithm>
#include <chrono>

#include "pki_test_support.hpp"
#include "ua/pki/certificate.hpp"
#include "ua/pki/own_certificate.hpp"
#include "ua/types/hex.hpp"

namespace skillcell::ua::pki::pki_certificate_test {
namespace {

TEST(Certificate, ParsesAConcatenatedChain) {
    const auto ca = test::makeCa("ca");
    const auto leaf = test::makeCertificate({}, &ca);
    auto parts = parseCertificateChain(test::concat(leaf.der(), ca.der()));
    ASSERT_TRUE(parts);
    ASSERT_EQ(parts->size(), 2u);
    EXPECT_EQ((*parts)[0].der, leaf.der());
    EXPECT_EQ((*parts)[1].der, ca.der());
    EXPECT_EQ(certificateDer((*parts)[0].cert.get()), leaf.der());
    EXPECT_EQ(certificateDer((*parts)[1].cert.get()), ca.der());
    EXPECT_EQ(parseCertificateChain(ByteString{}).status(), status::BadCertificateInvalid);
    EXPECT_EQ(parseCertificateChain(test::concat(leaf.der(), ByteString({0x30}))).status(),
              status::BadCertificateInvalid);
}

TEST(Certificate, ThumbprintIsSha1OfTheLeafOnly) {
    const auto ca = test::makeCa("ca");
    const auto leaf = test::makeCertificate({}, &ca);
    unsigned char expected[EVP_MAX_MD_SIZE];
    unsigned int len = 0;
    ASSERT_EQ(X509_digest(leaf.cert.get(), EVP_sha1(), expected, &len), 1);
    ASSERT_EQ(len, 20u);
    auto single = certificateThumbprint(leaf.der());
    auto chained = certificateThumbprint(test::concat(leaf.der(), ca.der()));
    ASSERT_TRUE(single);
    ASSERT_TRUE(chained);
    EXPECT_TRUE(std::equal(single->begin(), single->end(), expected));
    EXPECT_EQ(*single, *chained);
    EXPECT_EQ(certificateThumbprintHex(leaf.der()), toHex(std::span(expected, 20)));
    EXPECT_EQ(certificateThumbprintHex(leaf.der()).size(), 40u);
    EXPECT_EQ(certificateThumbprint(ByteString({1, 2})).status(), status::BadCertificateInvalid);
    // Of the parsed certificate, as the validator takes it, and as inspection reports it.
    EXPECT_EQ(certificateThumbprintHex(leaf.cert.get()), certificateThumbprintHex(leaf.der()));
    EXPECT_EQ(inspectCertificate(leaf.cert.get()).thumbprint, certificateThumbprintHex(leaf.der()));
    EXPECT_EQ(certificateThumbprintHex(static_cast<X509*>(nullptr)), "");
}

TEST(Certificate, InspectReadsNamesValidityAndKey) {
    test::CertSpec spec;
    spec.commonName = "gripper";
    spec.applicationUri = "urn:skillcell:gripper";
    spec.dnsNames = {"gripper.local", "localhost"};
    spec.notAfterDays = 100;
    const auto c = test::makeCertificate(spec);
    auto info = inspectCertificate(c.der());
    ASSERT_TRUE(info);
    EXPECT_NE(info->subject.find("gripper"), std::string::npos) << info->subject;
    EXPECT_EQ(info->subject, info->issuer);
    EXPECT_EQ(info->applicationUri, "urn:skillcell:gripper");
    EXPECT_EQ(info->dnsNames, (std::vector<std::string>{"gripper.local", "localhost"}));
    EXPECT_TRUE(info->selfSigned);
    EXPECT_FALSE(info->isCa);
    EXPECT_EQ(info->keyBits, 2048);
    const auto days = std::chrono::duration_cast<std::chrono::hours>(info->notAfter - Clock::now());
    EXPECT_NEAR(static_cast<double>(days.count()), 100.0 * 24, 2.0);
    EXPECT_LT(info->notBefore, Clock::now());
    EXPECT_EQ(certificateApplicationUri(c.der()), "urn:skillcell:gripper");
    EXPECT_EQ(inspectCertificate(ByteString({0})).status(), status::BadCertificateInvalid);
}

TEST(Certificate, PublicKeyMatchesThePrivateKey) {
    const auto c = test::makeCertificate({});
    auto key = certificatePublicKey(c.der());
    ASSERT_TRUE(key);
    EXPECT_EQ(EVP_PKEY_eq(key->get(), c.key.get()), 1);
    EXPECT_EQ(*certificateKeyBits(c.der()), 2048);
    const auto other = test::makeCertificate({});
    EXPECT_NE(EVP_PKEY_eq(key->get(), other.key.get()), 1);
}

}  // namespace
}  // namespace skillcell::ua::pki::pki_certificate_test
