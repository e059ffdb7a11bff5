#pragma once
// Session: one client's session (OPC 10000-4, 5.6) and the state the services keep per
// session. Owned by SessionManager; services see it through ServiceContext.
#include <chrono>
#include <cstdint>
#include <string>

#include "ua/server/browse_continuation_points.hpp"
#include "ua/server/user_identity.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/node_id.hpp"

namespace skillcell::ua {

class Session {
public:
    using Clock = std::chrono::steady_clock;

    Session(NodeId sessionId, NodeId authenticationToken, std::string name,
            std::chrono::milliseconds timeout, std::uint32_t channelId, Clock::time_point now,
            std::uint32_t maxContinuationPoints)
        : sessionId_(std::move(sessionId)),
          authenticationToken_(std::move(authenticationToken)),
          name_(std::move(name)),
          timeout_(timeout),
          channelId_(channelId),
          lastActivity_(now),
          continuationPoints_(maxContinuationPoints) {}

    [[nodiscard]] const NodeId& sessionId() const { return sessionId_; }
    [[nodiscard]] const NodeId& authenticationToken() const { return authenticationToken_; }
    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] std::chrono::milliseconds timeout() const { return timeout_; }
    [[nodiscard]] std::uint32_t channelId() const { return channelId_; }
    [[nodiscard]] bool isActivated() const { return activated_; }

    void activate(std::uint32_t channelId) {
        activated_ = true;
        channelId_ = channelId;
    }
    /// Every request on the session restarts its timeout.
    void touch(Clock::time_point now) { lastActivity_ = now; }
    /// The last instant at which the session is still alive, unless it is used again.
    [[nodiscard]] Clock::time_point expiresAfter() const { return lastActivity_ + timeout_; }
    [[nodiscard]] bool isExpired(Clock::time_point now) const {
        return now - lastActivity_ > timeout_;
    }
    [[nodiscard]] BrowseContinuationPoints& browseContinuationPoints() {
        return continuationPoints_;
    }

    /// Who the session acts for, set by ActivateSession.
    [[nodiscard]] const UserIdentity& identity() const { return identity_; }
    void setIdentity(UserIdentity identity) { identity_ = std::move(identity); }
    /// The last nonce the server gave the client: the next ActivateSession signs it.
    [[nodiscard]] const ByteString& serverNonce() const { return serverNonce_; }
    void setServerNonce(ByteString nonce) { serverNonce_ = std::move(nonce); }
    /// The client's application certificate from CreateSession (empty with None).
    [[nodiscard]] const ByteString& clientCertificate() const { return clientCertificate_; }
    void setClientCertificate(ByteString certificate) {
        clientCertificate_ = std::move(certificate);
    }

private:
    NodeId sessionId_;
    NodeId authenticationToken_;
    std::string name_;
    std::chrono::milliseconds timeout_;
    std::uint32_t channelId_;
    Clock::time_point lastActivity_;
    bool activated_ = false;
    BrowseContinuationPoints continuationPoints_;
    UserIdentity identity_;
    ByteString serverNonce_;
    ByteString clientCertificate_;
};

}  // namespace skillcell::ua
