// The cell CA: creation, issuing components' certificates, mutual trust, revocation.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <optional>

#include "pki_test_support.hpp"
#include "ua/crypto/primitives.hpp"
#include "ua/pki/certificate.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/pki/certificate_validator.hpp"
#include "ua/pki/file_util.hpp"
#include "ua/pki/own_certificate.hpp"
#include "ua/pki/trust_list.hpp"

namespace skillcell::ua::pki::pki_ca_test {
namespace {

namespace fs = std::filesystem;

CertificateSubject subjectFor(const std::string& name) {
    CertificateSubject s;
    s.applicationUri = "urn:skillcell:" + name;
    s.commonName = name;
    s.dnsNames = {"localhost"};
    return s;
}

constexpr const CertificateAuthority* kSelfSigned = nullptr;  // a bare nullptr is ambiguous

mode_t modeOf(const fs::path& p) {
    struct stat st {};
    EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
    return st.st_mode & 0777;
}

TEST(CellCa, CreatesCaFilesAndRefusesToReplaceThem) {
    test::TempDir tmp;
    const fs::path dir = tmp.path() / "ca";
    std::string error;
    CaOptions options;
    options.name = "Cell 7 CA";
    auto ca = createCertificateAuthority(dir, options, &error);
    ASSERT_TRUE(ca) << error;
    EXPECT_EQ(modeOf(ca->keyFile()), 0600u);
    EXPECT_EQ(modeOf(dir / "private"), 0700u);
    auto info = inspectCertificate(ByteString(readWholeFile(ca->certificateFile())));
    ASSERT_TRUE(info);
    EXPECT_TRUE(info->isCa);
    EXPECT_TRUE(info->selfSigned);
    EXPECT_NE(info->subject.find("Cell 7 CA"), std::string::npos);
    EXPECT_EQ(readCrlFile(ca->crlFile()).size(), 1u);
    EXPECT_FALSE(createCertificateAuthority(dir, options, &error));
    EXPECT_NE(error.find("not replacing"), std::string::npos) << error;
    auto loaded = loadCertificateAuthority(dir, &error);
    ASSERT_TRUE(loaded) << error;
    EXPECT_EQ(certificateDer(loaded->certificate.get()), certificateDer(ca->certificate.get()));
    EXPECT_FALSE(loadCertificateAuthority(tmp.path() / "nothing", &error));
}

TEST(CellCa, ComponentsOfOneCaTrustEachOtherWithoutManualSteps) {
    test::TempDir tmp;
    auto ca = createCertificateAuthority(tmp.path() / "ca", {});
    ASSERT_TRUE(ca);
    std::string error;
    auto robot =
        loadOrCreateOwnCertificate(tmp.path() / "robot", subjectFor("robot"), &*ca, &error);
    ASSERT_TRUE(robot) << error;
    auto gripper =
        loadOrCreateOwnCertificate(tmp.path() / "gripper", subjectFor("gripper"), &*ca, &error);
    ASSERT_TRUE(gripper) << error;
    EXPECT_TRUE(robot->created);
    EXPECT_EQ(robot->issuer, ca->directory);
    EXPECT_TRUE(issuedBy(robot->der, *ca));
    EXPECT_EQ(modeOf(robot->privateKeyFile), 0600u);

    CertificateValidator atRobot(tmp.path() / "robot");
    CertificateValidator atGripper(tmp.path() / "gripper");
    const auto v1 = atRobot.validate(gripper->der, "urn:skillcell:gripper");
    EXPECT_EQ(v1.status, status::Good) << v1.reason;
    const auto v2 = atGripper.validate(robot->der, "urn:skillcell:robot");
    EXPECT_EQ(v2.status, status::Good) << v2.reason;
    // A stranger's self-signed certificate is still refused.
    const auto stranger = test::makeCertificate({});
    EXPECT_EQ(atRobot.validate(stranger.der()).status, status::BadCertificateUntrusted);
}

TEST(CellCa, IssuesP256CertificatesBesideTheRsaOnesThatPeersTrust) {
    // The second certificate of a component under the cell CA, for ECC_nistP256.
    test::TempDir tmp;
    auto ca = createCertificateAuthority(tmp.path() / "ca", {});
    ASSERT_TRUE(ca);
    auto subject = subjectFor("robot");
    subject.key = CertificateKey::EccNistP256;
    std::string error;
    auto ecc = loadOrCreateOwnCertificate(tmp.path() / "robot", subject, &*ca, &error);
    ASSERT_TRUE(ecc) << error;
    EXPECT_EQ(ecc->certificateFile.filename(), "cert-nistP256.der");
    EXPECT_EQ(ecc->privateKeyFile.filename(), "key-nistP256.pem");
    EXPECT_EQ(modeOf(ecc->privateKeyFile), 0600u);
    EXPECT_TRUE(issuedBy(ecc->der, *ca));
    auto key = crypto::AsymmetricKey::fromPrivateKeyFile(ecc->privateKeyFile,
                                                         crypto::AsymmetricKey::Kind::EccNistP256);
    ASSERT_TRUE(key);
    // The RSA certificate beside it is another file and stays as it is.
    auto rsa = loadOrCreateOwnCertificate(tmp.path() / "robot", subjectFor("robot"), &*ca, &error);
    ASSERT_TRUE(rsa) << error;
    EXPECT_NE(rsa->der, ecc->der);
    EXPECT_EQ(crypto::AsymmetricKey::fromPrivateKeyFile(rsa->privateKeyFile,
                                                        crypto::AsymmetricKey::Kind::EccNistP256)
                  .status(),
              status::BadConfigurationError);
    auto again = loadOrCreateOwnCertificate(tmp.path() / "robot", subject, &*ca, &error);
    ASSERT_TRUE(again) << error;
    EXPECT_FALSE(again->created);
    EXPECT_EQ(again->der, ecc->der);
    // A peer of the same CA accepts it: its key usage is an ECC key's (no keyEncipherment).
    ASSERT_TRUE(loadOrCreateOwnCertificate(tmp.path() / "gripper", subjectFor("gripper"), &*ca));
    CertificateValidator atGripper(tmp.path() / "gripper");
    const auto verdict = atGripper.validate(ecc->der, "urn:skillcell:robot");
    EXPECT_EQ(verdict.status, status::Good) << verdict.reason;
}

TEST(CellCa, ReplacesASelfSignedCertificateAndKeepsAnIssuedOne) {
    test::TempDir tmp;
    const fs::path pki = tmp.path() / "pki";
    auto self = loadOrCreateOwnCertificate(pki, subjectFor("tool"), kSelfSigned);
    ASSERT_TRUE(self);
    EXPECT_TRUE(inspectCertificate(self->der)->selfSigned);
    auto ca = createCertificateAuthority(tmp.path() / "ca", {});
    ASSERT_TRUE(ca);
    auto issued = loadOrCreateOwnCertificate(pki, subjectFor("tool"), &*ca);
    ASSERT_TRUE(issued);
    EXPECT_TRUE(issued->created);
    EXPECT_NE(issued->der, self->der);
    EXPECT_TRUE(issuedBy(issued->der, *ca));
    auto again = loadOrCreateOwnCertificate(pki, subjectFor("tool"), &*ca);
    ASSERT_TRUE(again);
    EXPECT_FALSE(again->created);
    EXPECT_EQ(again->der, issued->der);
    // Without a CA the issued certificate stays: `pki issue` results are kept too.
    auto plain = loadOrCreateOwnCertificate(pki, subjectFor("tool"), kSelfSigned);
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->der, issued->der);
    // A second CA replaces the first one's certificate.
    auto ca2 = createCertificateAuthority(tmp.path() / "ca2", {});
    ASSERT_TRUE(ca2);
    auto moved = loadOrCreateOwnCertificate(pki, subjectFor("tool"), &*ca2);
    ASSERT_TRUE(moved);
    EXPECT_TRUE(issuedBy(moved->der, *ca2));
}

/// A CA, and a PKI directory that links to it as `cell-ca` (as `cell up` commissions one).
class CellCaLink : public testing::Test {
protected:
    test::TempDir tmp;
    std::optional<CertificateAuthority> ca;
    fs::path pki = tmp.path() / "pki";

    void SetUp() override {
        if (std::getenv("SKILLCELL_CA_DIR") != nullptr) {
            GTEST_SKIP() << "SKILLCELL_CA_DIR is set: it overrides the cell-ca link";
        }
        auto made = createCertificateAuthority(tmp.path() / "ca", {});
        ASSERT_TRUE(made);
        ca = std::move(*made);
        fs::create_directories(pki);
        fs::create_directory_symlink(tmp.path() / "ca", pki / "cell-ca");
    }
};

TEST_F(CellCaLink, CellCaLinkInThePkiDirectoryIsUsed) {
    EXPECT_EQ(cellCaDirectory(pki), pki / "cell-ca");
    auto own = loadOrCreateOwnCertificate(pki, subjectFor("mes"));
    ASSERT_TRUE(own);
    EXPECT_TRUE(issuedBy(own->der, *ca));
    EXPECT_TRUE(cellCaDirectory(tmp.path() / "elsewhere").empty());
}

TEST_F(CellCaLink, AComponentReadsTheCaKeyOnlyToIssue) {
    auto first = loadOrCreateOwnCertificate(pki, subjectFor("ur5"));
    ASSERT_TRUE(first);
    ASSERT_TRUE(first->created);
    // The key away (where an operator keeps it when the cell is commissioned): a start with
    // the certificate the CA issued needs only the CA's certificate and CRL.
    fs::rename(ca->keyFile(), tmp.path() / "ca_key.pem");
    std::string error;
    auto again = loadOrCreateOwnCertificate(pki, subjectFor("ur5"), &error);
    ASSERT_TRUE(again) << error;
    EXPECT_FALSE(again->created);
    EXPECT_EQ(again->der, first->der);
    // Issuing does need it, and says which file it could not read.
    auto other = loadOrCreateOwnCertificate(pki, subjectFor("mes"), &error);
    EXPECT_FALSE(other);
    EXPECT_NE(error.find("ca_key.pem"), std::string::npos) << error;
    fs::rename(tmp.path() / "ca_key.pem", ca->keyFile());
    other = loadOrCreateOwnCertificate(pki, subjectFor("mes"), &error);
    ASSERT_TRUE(other) << error;
    EXPECT_TRUE(other->created);
    EXPECT_TRUE(issuedBy(other->der, *ca));
}

TEST(CellCa, RevokedComponentIsRefusedOnceTheCrlIsInstalled) {
    test::TempDir tmp;
    auto ca = createCertificateAuthority(tmp.path() / "ca", {});
    ASSERT_TRUE(ca);
    auto robot = loadOrCreateOwnCertificate(tmp.path() / "robot", subjectFor("robot"), &*ca);
    auto rogue = loadOrCreateOwnCertificate(tmp.path() / "rogue", subjectFor("rogue"), &*ca);
    ASSERT_TRUE(robot);
    ASSERT_TRUE(rogue);
    CertificateValidator atRobot(tmp.path() / "robot");
    EXPECT_EQ(atRobot.validate(rogue->der).status, status::Good);
    std::string error;
    ASSERT_TRUE(revokeCertificate(*ca, rogue->der, &error).isGood()) << error;
    ASSERT_TRUE(revokeCertificate(*ca, rogue->der, &error).isGood()) << error;  // idempotent
    ASSERT_TRUE(installCertificateAuthority(*ca, tmp.path() / "robot", &error).isGood()) << error;
    EXPECT_EQ(atRobot.validate(rogue->der).status, status::BadCertificateRevoked);
    const auto stranger = test::makeCertificate({});
    EXPECT_FALSE(revokeCertificate(*ca, stranger.der()).isGood());
}

}  // namespace
}  // namespace skillcell::ua::pki::pki_ca_test
