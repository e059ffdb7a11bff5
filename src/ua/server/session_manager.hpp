#pragma once
// SessionManager: creates, activates, finds, closes and expires sessions. Knows nothing of
// sockets; the Session service set and the connection call it.
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <unordered_map>

#include "ua/messages/session.hpp"
#include "ua/server/server_limits.hpp"
#include "ua/server/session.hpp"
#include "ua/types/result.hpp"

namespace skillcell::ua {

class SessionManager {
public:
    using Clock = Session::Clock;

    explicit SessionManager(const ServerLimits& limits);

    /// A new, not yet activated session bound to `channelId`. BadTooManySessions at the
    /// limit. The timeout is clamped to the server's limits.
    [[nodiscard]] Result<Session*> create(const CreateSessionRequest& request,
                                          std::uint32_t channelId, Clock::time_point now);
    /// The session an authentication token names, or nullptr.
    [[nodiscard]] Session* find(const NodeId& authenticationToken);
    /// Looks up and checks a session for a request that needs an activated session on
    /// `channelId`: BadSessionIdInvalid (unknown or closed), BadSessionNotActivated,
    /// BadSecureChannelIdInvalid (activated on another channel). Restarts its timeout.
    [[nodiscard]] Result<Session*> authorize(const NodeId& authenticationToken,
                                             std::uint32_t channelId, Clock::time_point now);
    void close(const NodeId& authenticationToken);
    /// Told about every session that goes (CloseSession or timeout) just before it is
    /// destroyed, so that state kept elsewhere (subscriptions) goes with it.
    void setOnClose(std::function<void(const Session&)> onClose) { onClose_ = std::move(onClose); }
    /// Closes the sessions whose timeout elapsed; returns how many.
    std::size_t expire(Clock::time_point now);
    /// When the first of the sessions times out unless it is used before; none without any.
    [[nodiscard]] std::optional<Clock::time_point> nextExpiry() const;
    /// Told when a session is created: what waits for nextExpiry() must look again.
    void setWakeup(std::function<void()> wakeup) { wakeup_ = std::move(wakeup); }
    /// A channel closed: its sessions stay (a client may reactivate them on a new channel)
    /// until they time out.
    [[nodiscard]] std::size_t size() const { return sessions_.size(); }
    /// True while the session with this SessionId (not its token) exists.
    [[nodiscard]] bool contains(const NodeId& sessionId) const;

    /// Random bytes for tokens and nonces, from the cryptographic generator.
    [[nodiscard]] ByteString randomBytes(std::size_t n);

private:
    const ServerLimits& limits_;
    std::unordered_map<NodeId, std::unique_ptr<Session>> sessions_;  // by auth token
    std::uint32_t nextSessionNumber_ = 1;
    std::function<void(const Session&)> onClose_;
    std::function<void()> wakeup_;
};

}  // namespace skillcell::ua
