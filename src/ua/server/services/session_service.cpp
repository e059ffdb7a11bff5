#include "ua/server/services/session_service.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "ua/crypto/security_policy_profile.hpp"
#include "ua/transport/certificate_security_policy.hpp"

namespace skillcell::ua {
namespace {

constexpr std::size_t kMinClientNonce = 32;  // OPC 10000-4, 5.6.2.2: at least 32 bytes

bool secured(const ServiceContext& ctx) {
    return ctx.securityMode == MessageSecurityMode::Sign ||
           ctx.securityMode == MessageSecurityMode::SignAndEncrypt;
}

const crypto::SecurityPolicyProfile* channelProfile(const ServiceContext& ctx) {
    return crypto::findSecurityPolicyProfile(ctx.securityPolicyUri);
}

StatusCode createSession(ServiceContext& ctx, SessionManager& sessions,
                         const ServerDescription& description, const ServerSecurity& security,
                         const CreateSessionRequest& req, CreateSessionResponse& resp) {
    SignatureData serverSignature;
    if (secured(ctx)) {
        // The client proves nothing yet, but its certificate must be the one that opened
        // the channel, must name the application it claims to be, and its nonce is what we
        // sign to prove we hold our key (OPC 10000-4, 5.6.2).
        if (req.clientNonce.bytes.size() < kMinClientNonce) return status::BadNonceInvalid;
        if (ctx.clientCertificate == nullptr || leafCertificate(req.clientCertificate.bytes) !=
                                                    leafCertificate(ctx.clientCertificate->bytes)) {
            return status::BadCertificateInvalid;
        }
        if (security.validateCertificate) {
            std::string reason;
            const StatusCode s = security.validateCertificate(
                req.clientCertificate, req.clientDescription.applicationUri, &reason);
            if (s.isBad()) {
                spdlog::warn("channel {}: CreateSession refused, client certificate: {}: {}",
                             ctx.channelId, statusName(s), reason);
                return s;
            }
        }
        const auto* profile = channelProfile(ctx);
        if (profile == nullptr) return status::BadSecurityPolicyRejected;
        auto signature =
            crypto::sign(security.privateKeyFor(profile->uri), profile->asymmetricSignature,
                         certificateAndNonce(req.clientCertificate, req.clientNonce));
        if (!signature) return signature.status();
        serverSignature.algorithm = String(profile->asymmetricSignatureUri);
        serverSignature.signature = ByteString(std::move(*signature));
    }
    auto session = sessions.create(req, ctx.channelId, ctx.now);
    if (!session) {
        spdlog::warn("channel {}: CreateSession '{}' refused: {}", ctx.channelId, req.sessionName,
                     statusName(session.status()));
        return session.status();
    }
    spdlog::info("channel {}: session {} '{}' created (timeout {} ms, {})", ctx.channelId,
                 (*session)->sessionId().toString(), req.sessionName, (*session)->timeout().count(),
                 secured(ctx) ? std::string(channelProfile(ctx)->shortName) : "no security");
    const String url = description.endpointUrlFor(ctx.endpointUrl);
    resp.sessionId = (*session)->sessionId();
    resp.authenticationToken = (*session)->authenticationToken();
    resp.revisedSessionTimeout = static_cast<double>((*session)->timeout().count());
    resp.serverNonce = ByteString(crypto::randomBytes(32));
    (*session)->setServerNonce(resp.serverNonce);
    if (secured(ctx)) (*session)->setClientCertificate(req.clientCertificate);
    resp.serverEndpoints = description.endpoints(url);
    resp.serverCertificate = description.certificateFor(ctx.securityPolicyUri);
    resp.serverSignature = std::move(serverSignature);
    resp.maxRequestMessageSize = ctx.limits->transport.maxMessageSize;
    return status::Good;
}

/// The token policy the client names, of the expected type.
const UserTokenPolicy* findTokenPolicy(const ServerDescription& description, const String& policyId,
                                       UserTokenType type) {
    for (const auto& p : description.userTokenPolicies) {
        if (p.tokenType == type && (policyId.empty() || p.policyId == policyId)) return &p;
    }
    return nullptr;
}

/// The policy that secures a user token: its own securityPolicyUri, or the channel's.
const crypto::SecurityPolicyProfile* tokenProfile(const ServiceContext& ctx,
                                                  const UserTokenPolicy& policy) {
    return crypto::findSecurityPolicyProfile(
        ServerDescription::tokenSecurityPolicy(policy, ctx.securityPolicyUri));
}

/// The password of a UserNameIdentityToken, decrypted (OPC 10000-4, 7.41.2.2, legacy
/// format: length, password, server nonce, encrypted with the server's public key).
Result<std::string> decryptPassword(const ServiceContext& ctx, const ServerSecurity& security,
                                    const Session& session, const UserTokenPolicy& policy,
                                    const UserNameIdentityToken& token) {
    const auto* profile = tokenProfile(ctx, policy);
    if (profile == nullptr) {
        // Only on an encrypted channel may a password travel without its own encryption.
        if (ctx.securityMode != MessageSecurityMode::SignAndEncrypt ||
            !token.encryptionAlgorithm.empty()) {
            return status::BadIdentityTokenInvalid;
        }
        return std::string(token.password.bytes.begin(), token.password.bytes.end());
    }
    // ECC encrypts a password as an EccEncryptedSecret, which we do not implement (and do
    // not offer: ServerDescription::endpoints).
    if (profile->isEcc()) return status::BadIdentityTokenRejected;
    if (token.encryptionAlgorithm != profile->asymmetricEncryptionUri) {
        return status::BadIdentityTokenInvalid;
    }
    auto plain = crypto::rsaDecrypt(security.privateKeyFor(profile->uri),
                                    profile->asymmetricEncryption, token.password.bytes);
    if (!plain || plain->size() < 4) return status::BadIdentityTokenInvalid;
    const std::uint32_t length = std::uint32_t{(*plain)[0]} | (std::uint32_t{(*plain)[1]} << 8) |
                                 (std::uint32_t{(*plain)[2]} << 16) |
                                 (std::uint32_t{(*plain)[3]} << 24);
    const auto& nonce = session.serverNonce().bytes;
    if (length != plain->size() - 4 || length < nonce.size()) {
        return status::BadIdentityTokenInvalid;
    }
    const auto passwordEnd = plain->end() - static_cast<std::ptrdiff_t>(nonce.size());
    // The nonce ties the token to this activation: a recorded token cannot be replayed.
    if (!crypto::equalConstantTime(std::span(passwordEnd, plain->end()), nonce)) {
        return status::BadIdentityTokenInvalid;
    }
    return std::string(plain->begin() + 4, passwordEnd);
}

Result<UserIdentity> checkIdentity(const ServiceContext& ctx, const ServerDescription& description,
                                   const ServerSecurity& security, const Session& session,
                                   const ActivateSessionRequest& req) {
    const ExtensionObject& token = req.userIdentityToken;
    // An absent token counts as anonymous (OPC 10000-4, 5.6.3.2).
    AnonymousIdentityToken anonymous;
    if (token.empty() || fromExtensionObject(token, anonymous).isGood()) {
        if (!security.allowAnonymous ||
            findTokenPolicy(description, anonymous.policyId, UserTokenType::Anonymous) == nullptr) {
            return status::BadIdentityTokenRejected;
        }
        return UserIdentity{"anonymous", security.anonymousRoles};
    }
    UserNameIdentityToken userName;
    if (fromExtensionObject(token, userName).isGood()) {
        const auto* policy =
            findTokenPolicy(description, userName.policyId, UserTokenType::UserName);
        if (policy == nullptr || !security.users) return status::BadIdentityTokenRejected;
        auto password = decryptPassword(ctx, security, session, *policy, userName);
        if (!password) return password.status();
        auto user = security.users->authenticatePassword(userName.userName, *password);
        // The name is logged (an operator needs it to see who is locked out, or guessing);
        // the password never is.
        if (!user) spdlog::warn("user '{}': password refused", userName.userName);
        return user;
    }
    X509IdentityToken x509;
    if (fromExtensionObject(token, x509).isGood()) {
        const auto* policy =
            findTokenPolicy(description, x509.policyId, UserTokenType::Certificate);
        if (policy == nullptr || !security.users) return status::BadIdentityTokenRejected;
        const auto* profile = tokenProfile(ctx, *policy);
        if (profile == nullptr) return status::BadIdentityTokenRejected;
        // Possession of the user's private key: a signature over our certificate and nonce.
        auto key = publicKeyOf(x509.certificateData, ctx.clientCertificate, ctx.clientKey);
        if (!key) return status::BadIdentityTokenInvalid;
        if (req.userTokenSignature.algorithm != profile->asymmetricSignatureUri ||
            crypto::verify(*key, profile->asymmetricSignature,
                           certificateAndNonce(description.certificateFor(ctx.securityPolicyUri),
                                               session.serverNonce()),
                           req.userTokenSignature.signature.bytes)
                .isBad()) {
            return status::BadUserSignatureInvalid;
        }
        return security.users->authenticateCertificate(x509.certificateData);
    }
    return status::BadIdentityTokenInvalid;
}

StatusCode activateSession(ServiceContext& ctx, SessionManager& sessions,
                           const ServerDescription& description, const ServerSecurity& security,
                           const ActivateSessionRequest& req, ActivateSessionResponse& resp) {
    Session* session = sessions.find(req.requestHeader.authenticationToken);
    if (session == nullptr || session->isExpired(ctx.now)) return status::BadSessionIdInvalid;
    if (secured(ctx)) {
        // The client proves it holds the key of the certificate it gave in CreateSession by
        // signing our certificate and the last nonce we gave it.
        const auto* profile = channelProfile(ctx);
        auto key = publicKeyOf(session->clientCertificate(), ctx.clientCertificate, ctx.clientKey);
        if (profile == nullptr || !key ||
            req.clientSignature.algorithm != profile->asymmetricSignatureUri ||
            crypto::verify(*key, profile->asymmetricSignature,
                           certificateAndNonce(description.certificateFor(ctx.securityPolicyUri),
                                               session->serverNonce()),
                           req.clientSignature.signature.bytes)
                .isBad()) {
            spdlog::warn("session {}: client signature refused", session->sessionId().toString());
            return status::BadApplicationSignatureInvalid;
        }
    }
    // Moving a session to another channel needs the proof above from the same client
    // certificate; with None only the creating channel may activate.
    if (session->channelId() != ctx.channelId &&
        (!secured(ctx) || ctx.clientCertificate == nullptr ||
         leafCertificate(ctx.clientCertificate->bytes) !=
             leafCertificate(session->clientCertificate().bytes))) {
        return status::BadSecureChannelIdInvalid;
    }
    auto identity = checkIdentity(ctx, description, security, *session, req);
    if (!identity) {
        spdlog::warn("session {}: identity token refused: {}", session->sessionId().toString(),
                     statusName(identity.status()));
        // A failed attempt uses up the nonce: the next try must sign a fresh one.
        session->setServerNonce(ByteString(crypto::randomBytes(32)));
        return identity.status();
    }
    if (session->isActivated() && identity->name != session->identity().name) {
        spdlog::info("session {}: user changes from '{}' to '{}'", session->sessionId().toString(),
                     session->identity().name, identity->name);
    }
    spdlog::info("session {} activated for '{}' (roles {})", session->sessionId().toString(),
                 identity->name, identity->roles.toString());
    session->setIdentity(std::move(*identity));
    session->activate(ctx.channelId);
    session->touch(ctx.now);
    resp.serverNonce = ByteString(crypto::randomBytes(32));
    session->setServerNonce(resp.serverNonce);
    return status::Good;
}

}  // namespace

void registerSessionServices(ServiceTable& table, SessionManager& sessions,
                             const ServerDescription& description, const ServerSecurity& security) {
    table.add<CreateSessionRequest, CreateSessionResponse>(
        ServiceTable::Access::NoSession,
        [&sessions, &description, &security](ServiceContext& ctx, const CreateSessionRequest& req,
                                             CreateSessionResponse& resp) {
            return createSession(ctx, sessions, description, security, req, resp);
        });
    table.add<ActivateSessionRequest, ActivateSessionResponse>(
        ServiceTable::Access::NoSession,
        [&sessions, &description, &security](ServiceContext& ctx, const ActivateSessionRequest& req,
                                             ActivateSessionResponse& resp) {
            return activateSession(ctx, sessions, description, security, req, resp);
        });
    table.add<CloseSessionRequest, CloseSessionResponse>(
        ServiceTable::Access::NoSession,
        [&sessions](ServiceContext& ctx, const CloseSessionRequest& req, CloseSessionResponse&) {
            Session* session = sessions.find(req.requestHeader.authenticationToken);
            if (session == nullptr) return status::BadSessionIdInvalid;
            if (session->channelId() != ctx.channelId) return status::BadSecureChannelIdInvalid;
            spdlog::info("session {} '{}' closed", session->sessionId().toString(),
                         session->name());
            sessions.close(req.requestHeader.authenticationToken);
            return status::Good;
        });
}

void registerDiscoveryServices(ServiceTable& table, const ServerDescription& description) {
    table.add<GetEndpointsRequest, GetEndpointsResponse>(
        ServiceTable::Access::NoSession,
        [&description](ServiceContext& ctx, const GetEndpointsRequest& req,
                       GetEndpointsResponse& resp) {
            const String url = description.endpointUrlFor(
                req.endpointUrl.empty() ? ctx.endpointUrl : &req.endpointUrl);
            auto endpoints = description.endpoints(url);
            // profileUris filters by transport profile; an unknown one leaves nothing.
            if (!req.profileUris.empty()) {
                std::erase_if(endpoints, [&req](const EndpointDescription& ep) {
                    return std::find(req.profileUris.begin(), req.profileUris.end(),
                                     ep.transportProfileUri) == req.profileUris.end();
                });
            }
            resp.endpoints = std::move(endpoints);
            return status::Good;
        });
    table.add<FindServersRequest, FindServersResponse>(
        ServiceTable::Access::NoSession,
        [&description](ServiceContext& ctx, const FindServersRequest& req,
                       FindServersResponse& resp) {
            if (auto self = description.findServersEntry(req, ctx.endpointUrl)) {
                resp.servers.push_back(std::move(*self));
            }
            return status::Good;
        });
}

}  // namespace skillcell::ua
