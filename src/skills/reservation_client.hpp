#pragma once
// The client side of a component's reservation (reservation.hpp): what the MES calls on the
// component a step runs on, through the session it drives the skill with.
#include <asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ua/client/client.hpp"

namespace skillcell::skills {

/// Reserve(holder, takeover) on the component `client` is connected to: the fencing token.
/// BadResourceUnavailable while another holder has it; BadNodeIdUnknown or BadMethodInvalid
/// when the component has no reservation (one not built on skillcell's SkillServer).
asio::awaitable<ua::Result<std::uint64_t>> reserve(ua::Client& client, std::string holder,
                                                   bool takeover);
/// Use(token): binds the session of `client` to the current token (BadInvalidArgument when it
/// is not the current one, BadInvalidState when the component is free).
asio::awaitable<ua::StatusCode> use(ua::Client& client, std::uint64_t token);
/// Release(token); BadInvalidArgument when the token is no longer the current one.
asio::awaitable<ua::StatusCode> release(ua::Client& client, std::uint64_t token);
/// Who holds the component's reservation now (empty: free, or unknown).
asio::awaitable<std::string> reservationHolder(ua::Client& client);
/// Whether a status means "this component has no reservation to take".
[[nodiscard]] bool noReservation(ua::StatusCode status);

/// A hold on a component through one or more sessions to it (a client that opens a session
/// per skill binds each; a composite drives a robot's moves through one session).
struct Hold {
    /// The fencing token; none when the component has no reservation (not built on
    /// skillcell's SkillServer): it is driven without one.
    std::optional<std::uint64_t> token;
    /// Empty when held (or when there is nothing to hold); else why not, naming the holder:
    /// "reserved by <holder> (BadResourceUnavailable)".
    std::string refusal;
};
/// Reserves the component for `holder` through `sessions.front()` and binds every other
/// session to the token (Use). Refused: nothing stays reserved. While another holder has it,
/// asks again for up to `patience`: a holder that died keeps it until its sessions time out.
asio::awaitable<Hold> hold(std::vector<ua::Client*> sessions, std::string holder,
                           std::chrono::milliseconds patience = std::chrono::milliseconds(0));

}  // namespace skillcell::skills
