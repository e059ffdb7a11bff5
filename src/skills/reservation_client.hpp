#pragma once
// The client side of a component's reservation (reservation.hpp): what the MES calls on the
// component a step runs on, through the session it drives the skill with.
#include <asio/awaitable.hpp>
#include <cstdint>
#include <string>

#include "ua/client/client.hpp"

namespace skillcell::skills {

/// Reserve(holder, takeover) on the component `client` is connected to: the fencing token.
/// BadResourceUnavailable while another holder has it; BadNodeIdUnknown or BadMethodInvalid
/// when the component has no reservation (one not built on skillcell's SkillServer).
asio::awaitable<ua::Result<std::uint64_t>> reserve(ua::Client& client, std::string holder,
                                                   bool takeover);
/// Release(token); BadInvalidArgument when the token is no longer the current one.
asio::awaitable<ua::StatusCode> release(ua::Client& client, std::uint64_t token);
/// Who holds the component's reservation now (empty: free, or unknown).
asio::awaitable<std::string> reservationHolder(ua::Client& client);
/// Whether a status means "this component has no reservation to take".
[[nodiscard]] bool noReservation(ua::StatusCode status);

}  // namespace skillcell::skills
