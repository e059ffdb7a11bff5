#include "ua/server/server_security.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "ua/crypto/security_policy_profile.hpp"
#include "ua/transport/certificate_security_policy.hpp"

namespace skillcell::ua {

std::vector<SecurityEndpoint> allSecurityEndpoints(
    bool withNone, const std::vector<crypto::AsymmetricKey::Kind>& keyKinds) {
    std::vector<SecurityEndpoint> out;
    const auto profiles = crypto::securityPolicyProfiles();
    for (auto it = profiles.rbegin(); it != profiles.rend(); ++it) {
        if (std::find(keyKinds.begin(), keyKinds.end(), it->keyKind) == keyKinds.end()) continue;
        out.push_back({std::string(it->uri), MessageSecurityMode::SignAndEncrypt});
        out.push_back({std::string(it->uri), MessageSecurityMode::Sign});
    }
    if (withNone) out.push_back({std::string(kSecurityPolicyNoneUri), MessageSecurityMode::None});
    return out;
}

const crypto::AsymmetricKey& ServerSecurity::privateKeyFor(std::string_view policyUri) const {
    const auto* profile = crypto::findSecurityPolicyProfile(policyUri);
    return profile != nullptr && profile->isEcc() && eccPrivateKey.valid() ? eccPrivateKey
                                                                           : privateKey;
}

Result<std::unique_ptr<SecurityPolicy>> selectPolicy(const std::vector<SecurityEndpoint>& offered,
                                                     const ServerSecurity& security,
                                                     const ByteString& ownCertificate,
                                                     const AsymmetricSecurityHeader& header,
                                                     std::string_view peer) {
    // A None channel is always opened: a client needs GetEndpoints before it can choose a
    // secured endpoint. The connection limits it to the discovery services when None is not
    // offered (Connection::handleMessage).
    if (header.securityPolicyUri == kSecurityPolicyNoneUri) {
        return std::unique_ptr<SecurityPolicy>(std::make_unique<SecurityPolicyNone>());
    }
    const bool offersPolicy = std::any_of(
        offered.begin(), offered.end(),
        [&](const SecurityEndpoint& e) { return e.policyUri == header.securityPolicyUri; });
    if (!offersPolicy) {
        spdlog::warn("{}: security policy '{}' is not offered", peer, header.securityPolicyUri);
        return status::BadSecurityPolicyRejected;
    }
    const auto* profile = crypto::findSecurityPolicyProfile(header.securityPolicyUri);
    if (profile == nullptr) return status::BadSecurityPolicyRejected;
    const auto& privateKey = security.privateKeyFor(profile->uri);
    if (!privateKey.valid()) {
        spdlog::error("{}: {} offered but the server has no private key", peer, profile->shortName);
        return status::BadConfigurationError;
    }
    if (security.validateCertificate) {
        std::string reason;
        const StatusCode s = security.validateCertificate(header.senderCertificate, {}, &reason);
        if (s.isBad()) {
            spdlog::warn("{}: client certificate refused ({}): {}", peer, statusName(s), reason);
            return s;
        }
    }
    auto policy =
        createCertificateSecurityPolicy(*profile, ownCertificate, privateKey,
                                        header.senderCertificate, MessageSecurityMode::Invalid);
    if (!policy) {
        spdlog::warn("{}: client certificate unusable with {}: {}", peer, profile->shortName,
                     statusName(policy.status()));
        return policy.status();
    }
    return std::unique_ptr<SecurityPolicy>(std::move(*policy));
}

}  // namespace skillcell::ua
