#include "application_identity.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <mutex>

#include "ua/discovery/network_interfaces.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/pki/certificate_validator.hpp"

namespace skillcell::apps {

// The validator reloads its trust list as files change and is not thread-safe; a component's
// server and its clients (some on threads of their own, like WorldLink's) share it.
struct ApplicationIdentity::SharedValidator {
    explicit SharedValidator(const std::filesystem::path& pkiDir) : validator(pkiDir) {}
    std::mutex mutex;
    ua::pki::CertificateValidator validator;

    ua::pki::CertificateVerdict validate(const ua::ByteString& der, std::string_view uri) {
        std::lock_guard lock(mutex);
        return validator.validate(der, uri);
    }
};

ua::Result<ApplicationIdentity> ApplicationIdentity::load(
    std::filesystem::path pkiDir, const std::string& applicationUri,
    const std::string& applicationName, std::string* error,
    const std::vector<std::string>& moreAddresses) {
    if (pkiDir.empty()) pkiDir = ua::pki::defaultPkiDirectory(applicationUri);
    ua::pki::CertificateSubject subject;
    subject.applicationUri = applicationUri;
    subject.commonName = applicationName;
    std::array<char, 256> hostname{};
    if (gethostname(hostname.data(), hostname.size() - 1) == 0) {
        subject.dnsNames.emplace_back(hostname.data());
    }
    subject.dnsNames.emplace_back("localhost");
    for (const auto& nic : ua::mdns::listIpv4Interfaces()) {
        subject.ipAddresses.push_back(ua::mdns::toString(nic.address));
    }
    for (const auto& a : moreAddresses) {
        if (std::find(subject.ipAddresses.begin(), subject.ipAddresses.end(), a) ==
            subject.ipAddresses.end()) {
            subject.ipAddresses.push_back(a);
        }
    }
    ApplicationIdentity identity;
    identity.pkiDir_ = pkiDir;
    // The ECC certificate only under a cell CA: peers trust it through the CA, where a
    // self-signed one would need trusting by hand beside the RSA one.
    // The cell CA's certificate, read once for both (its key only when one must be issued).
    std::string why;
    auto ca = ua::pki::loadCellCaCertificate(pkiDir, &why);
    if (!ca) {
        if (error != nullptr) *error = "application certificate in " + pkiDir.string() + ": " + why;
        return ca.status();
    }
    std::vector<ua::pki::CertificateKey> kinds{ua::pki::CertificateKey::Rsa2048};
    if (*ca) kinds.push_back(ua::pki::CertificateKey::EccNistP256);
    const ua::pki::CertificateAuthority* issuer = *ca ? &**ca : nullptr;
    for (const auto kind : kinds) {
        subject.key = kind;
        const bool ecc = kind == ua::pki::CertificateKey::EccNistP256;
        auto certificate = ua::pki::loadOrCreateOwnCertificate(pkiDir, subject, issuer, &why);
        if (!certificate) {
            if (error != nullptr) {
                *error = std::string(ecc ? "ECC " : "") + "application certificate in " +
                         pkiDir.string() + ": " + why;
            }
            return certificate.status();
        }
        const auto wanted = ecc ? ua::crypto::AsymmetricKey::Kind::EccNistP256
                                : ua::crypto::AsymmetricKey::Kind::Rsa;
        auto key =
            ua::crypto::AsymmetricKey::fromPrivateKeyFile(certificate->privateKeyFile, wanted);
        if (!key) {
            if (error != nullptr) {
                *error = "cannot read the private key " + certificate->privateKeyFile.string();
            }
            return key.status();
        }
        spdlog::info("{} application certificate {}", certificate->created ? "created" : "using",
                     certificate->certificateFile.string());
        (ecc ? identity.eccCertificate_ : identity.certificate_) = std::move(*certificate);
        (ecc ? identity.eccPrivateKey_ : identity.privateKey_) = std::move(*key);
    }
    identity.validator_ = std::make_shared<SharedValidator>(pkiDir);
    return identity;
}

void ApplicationIdentity::prepareForPeers() const {
    {
        std::lock_guard lock(validator_->mutex);
        validator_->validator.preload();
    }
    const auto ecdsa = ua::crypto::ecdsaAlgorithmFor(eccPrivateKey_.kind());
    if (!eccPrivateKey_.valid() || !ecdsa) return;
    // Both results are thrown away: only OpenSSL's caches of the algorithms are wanted.
    (void)ua::crypto::EphemeralKey::generate(eccPrivateKey_.kind());
    static constexpr std::array<std::uint8_t, 1> kAnything{0};
    (void)ua::crypto::sign(eccPrivateKey_, *ecdsa, kAnything);
}

ua::CertificateCheck ApplicationIdentity::clientCertificateCheck() const {
    return [validator = validator_](const ua::ByteString& der, std::string_view applicationUri,
                                    std::string* reason) {
        auto verdict = validator->validate(der, applicationUri);
        if (reason != nullptr) *reason = verdict.reason;
        return verdict.status;
    };
}

ua::ServerCertificateValidator ApplicationIdentity::serverCertificateCheck() const {
    return [validator = validator_](const ua::ByteString& der, std::string* reason) {
        auto verdict = validator->validate(der, {});
        // The reason says where the certificate was copied and how to trust it.
        if (!verdict.ok()) spdlog::warn("server certificate refused: {}", verdict.reason);
        if (reason != nullptr) *reason = verdict.reason;
        return verdict.status;
    };
}

}  // namespace skillcell::apps
