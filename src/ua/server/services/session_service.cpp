#include "ua/server/services/session_service.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace skillcell::ua {
namespace {

StatusCode createSession(ServiceContext& ctx, SessionManager& sessions,
                         const ServerDescription& description, const CreateSessionRequest& req,
                         CreateSessionResponse& resp) {
    auto session = sessions.create(req, ctx.channelId, ctx.now);
    if (!session) {
        spdlog::warn("channel {}: CreateSession '{}' refused: {}", ctx.channelId, req.sessionName,
                     statusName(session.status()));
        return session.status();
    }
    spdlog::info("channel {}: session {} '{}' created (timeout {} ms)", ctx.channelId,
                 (*session)->sessionId().toString(), req.sessionName,
                 (*session)->timeout().count());
    const String url = description.endpointUrlFor(ctx.endpointUrl);
    resp.sessionId = (*session)->sessionId();
    resp.authenticationToken = (*session)->authenticationToken();
    resp.revisedSessionTimeout = static_cast<double>((*session)->timeout().count());
    resp.serverNonce = sessions.randomBytes(32);
    resp.serverEndpoints = description.endpoints(url);
    resp.serverCertificate = description.certificate;
    resp.maxRequestMessageSize = ctx.limits->transport.maxMessageSize;
    return status::Good;
}

/// Anonymous is the one identity this server accepts for now (user tokens arrive with the
/// security issue). An absent token counts as anonymous, as OPC 10000-4 5.6.3.2 allows.
StatusCode checkIdentity(const ExtensionObject& token) {
    if (token.empty()) return status::Good;
    AnonymousIdentityToken anonymous;
    const StatusCode s = fromExtensionObject(token, anonymous);
    if (s == status::BadDataTypeIdUnknown) return status::BadIdentityTokenRejected;
    if (s.isBad()) return status::BadIdentityTokenInvalid;
    if (!anonymous.policyId.empty() && anonymous.policyId != kAnonymousPolicyId) {
        return status::BadIdentityTokenInvalid;
    }
    return status::Good;
}

StatusCode activateSession(ServiceContext& ctx, SessionManager& sessions,
                           const ActivateSessionRequest& req, ActivateSessionResponse& resp) {
    Session* session = sessions.find(req.requestHeader.authenticationToken);
    if (session == nullptr || session->isExpired(ctx.now)) return status::BadSessionIdInvalid;
    // Moving a session to another channel needs the client's signature over the server
    // nonce, which needs a secure policy; with None only the creating channel may activate.
    if (session->channelId() != ctx.channelId) return status::BadSecureChannelIdInvalid;
    if (const StatusCode s = checkIdentity(req.userIdentityToken); s.isBad()) {
        spdlog::warn("session {}: identity token refused: {}", session->sessionId().toString(),
                     statusName(s));
        return s;
    }
    session->activate(ctx.channelId);
    session->touch(ctx.now);
    resp.serverNonce = sessions.randomBytes(32);
    return status::Good;
}

}  // namespace

void registerSessionServices(ServiceTable& table, SessionManager& sessions,
                             const ServerDescription& description) {
    table.add<CreateSessionRequest, CreateSessionResponse>(
        ServiceTable::Access::NoSession,
        [&sessions, &description](ServiceContext& ctx, const CreateSessionRequest& req,
                                  CreateSessionResponse& resp) {
            return createSession(ctx, sessions, description, req, resp);
        });
    table.add<ActivateSessionRequest, ActivateSessionResponse>(
        ServiceTable::Access::NoSession,
        [&sessions](ServiceContext& ctx, const ActivateSessionRequest& req,
                    ActivateSessionResponse& resp) {
            return activateSession(ctx, sessions, req, resp);
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
