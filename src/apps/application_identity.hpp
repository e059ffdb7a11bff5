#pragma once
// ApplicationIdentity: who an application is on the network. Its application instance
// certificate and key (created in its PKI directory on first start, or issued by the cell
// CA, see ua/pki/own_certificate.hpp) and the trust list it judges its peers by. A component
// uses one identity both as a server and for every connection it makes as a client, so a
// peer that trusts the component trusts it in both roles.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ua/client/client.hpp"
#include "ua/crypto/primitives.hpp"
#include "ua/pki/own_certificate.hpp"
#include "ua/server/server_security.hpp"

namespace skillcell::apps {

class ApplicationIdentity {
public:
    /// Loads or creates the certificate in `pkiDir` (empty: ua::pki::defaultPkiDirectory of
    /// the URI), naming the host's DNS names and IPv4 addresses, and `moreAddresses` (where
    /// it will serve on another host of ours: a cell's host, CellHosts). The error says what
    /// failed.
    [[nodiscard]] static ua::Result<ApplicationIdentity> load(
        std::filesystem::path pkiDir, const std::string& applicationUri,
        const std::string& applicationName, std::string* error,
        const std::vector<std::string>& moreAddresses = {});

    [[nodiscard]] const std::filesystem::path& pkiDirectory() const { return pkiDir_; }
    [[nodiscard]] const ua::pki::OwnCertificate& certificate() const { return certificate_; }
    [[nodiscard]] const ua::crypto::AsymmetricKey& privateKey() const { return privateKey_; }
    /// The second certificate, with a P-256 key, for ECC_nistP256 (own/certs/cert-nistP256.der),
    /// issued by the cell CA; empty without one. The cell's components secure their
    /// connections to each other with it, an ECDSA signature costing a fraction of an RSA one.
    [[nodiscard]] const ua::pki::OwnCertificate& eccCertificate() const { return eccCertificate_; }
    [[nodiscard]] const ua::crypto::AsymmetricKey& eccPrivateKey() const { return eccPrivateKey_; }

    /// Does now what a peer's first connection would otherwise wait for: reads the trust
    /// list, and has OpenSSL fetch the algorithms of an ECC handshake on our ECC key's curve
    /// (a key pair, an ECDSA signature), which it does once per process. For the moments
    /// after a server announced itself, before the first peer connects.
    void prepareForPeers() const;

    /// Checks a client's certificate (server side); untrusted ones land in rejected/.
    [[nodiscard]] ua::CertificateCheck clientCertificateCheck() const;
    /// Checks a server's certificate (client side); untrusted ones land in rejected/.
    [[nodiscard]] ua::ServerCertificateValidator serverCertificateCheck() const;

private:
    struct SharedValidator;  // the validator and the lock that lets both roles share it
    std::filesystem::path pkiDir_;
    ua::pki::OwnCertificate certificate_;
    ua::crypto::AsymmetricKey privateKey_;
    ua::pki::OwnCertificate eccCertificate_;
    ua::crypto::AsymmetricKey eccPrivateKey_;
    std::shared_ptr<SharedValidator> validator_;
};

}  // namespace skillcell::apps
