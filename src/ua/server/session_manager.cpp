#include "ua/server/session_manager.hpp"

#include <algorithm>

#include "ua/crypto/primitives.hpp"
#include "ua/server/service_context.hpp"

namespace skillcell::ua {

SessionManager::SessionManager(const ServerLimits& limits) : limits_(limits) {}

ByteString SessionManager::randomBytes(std::size_t n) {
    // Authentication tokens are bearer secrets: a predictable generator would let anyone on
    // the network take over a session.
    return ByteString(crypto::randomBytes(n));
}

Result<Session*> SessionManager::create(const CreateSessionRequest& request,
                                        std::uint32_t channelId, Clock::time_point now) {
    if (sessions_.size() >= limits_.maxSessions) return status::BadTooManySessions;
    double timeoutMs = request.requestedSessionTimeout;
    if (!(timeoutMs >= limits_.minSessionTimeoutMs)) timeoutMs = limits_.minSessionTimeoutMs;
    timeoutMs = std::min(timeoutMs, limits_.maxSessionTimeoutMs);

    // The session id is public (it appears in diagnostics); the authentication token is a
    // secret that proves ownership, so it is random and never derived from the id.
    NodeId sessionId(1, nextSessionNumber_++);
    NodeId token(0, randomBytes(32));
    auto session =
        std::make_unique<Session>(sessionId, token, request.sessionName,
                                  std::chrono::milliseconds(static_cast<std::int64_t>(timeoutMs)),
                                  channelId, now, limits_.maxBrowseContinuationPoints);
    Session* raw = session.get();
    sessions_.emplace(token, std::move(session));
    if (wakeup_) wakeup_();
    return raw;
}

Session* SessionManager::find(const NodeId& authenticationToken) {
    auto it = sessions_.find(authenticationToken);
    return it == sessions_.end() ? nullptr : it->second.get();
}

Result<Session*> SessionManager::authorize(const NodeId& authenticationToken,
                                           std::uint32_t channelId, Clock::time_point now) {
    Session* s = find(authenticationToken);
    if (s == nullptr || s->isExpired(now)) return status::BadSessionIdInvalid;
    if (!s->isActivated()) return status::BadSessionNotActivated;
    if (s->channelId() != channelId) return status::BadSecureChannelIdInvalid;
    s->touch(now);
    return s;
}

void SessionManager::close(const NodeId& authenticationToken) {
    auto it = sessions_.find(authenticationToken);
    if (it == sessions_.end()) return;
    if (onClose_) onClose_(*it->second);
    sessions_.erase(it);
}

std::size_t SessionManager::expire(Clock::time_point now) {
    return std::erase_if(sessions_, [this, now](const auto& kv) {
        if (!kv.second->isExpired(now)) return false;
        if (onClose_) onClose_(*kv.second);
        return true;
    });
}

std::optional<SessionManager::Clock::time_point> SessionManager::nextExpiry() const {
    std::optional<Clock::time_point> first;
    for (const auto& [token, session] : sessions_) {
        const auto at = session->expiresAfter();
        if (!first || at < *first) first = at;
    }
    return first;
}

BrowseContinuationPoints& continuationPointsOf(ServiceContext& ctx) {
    return ctx.session->browseContinuationPoints();
}

bool SessionManager::contains(const NodeId& sessionId) const {
    for (const auto& [token, session] : sessions_) {
        if (session->sessionId() == sessionId) return true;
    }
    return false;
}

}  // namespace skillcell::ua
