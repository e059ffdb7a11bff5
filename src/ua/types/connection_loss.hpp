#pragma once
// Which status codes say that a server is out of reach rather than that it refused.
#include "ua/types/status_code.hpp"

namespace skillcell::ua {

/// Whether `s` says the connection to the server is gone or failed (closed, never made, timed
/// out, the channel or session lost): the server may be back after a restart, unlike a
/// refusal by a server that answered.
[[nodiscard]] constexpr bool isConnectionLoss(StatusCode s) {
    constexpr StatusCode kLost[] = {status::BadConnectionClosed,
                                    status::BadServerNotConnected,
                                    status::BadCommunicationError,
                                    status::BadNoCommunication,
                                    status::BadTimeout,
                                    status::BadRequestTimeout,
                                    status::BadSecureChannelClosed,
                                    status::BadSessionClosed,
                                    status::BadSessionIdInvalid,
                                    status::BadDisconnect,
                                    status::BadConnectionRejected};
    for (const auto lost : kLost) {
        if (s == lost) return true;
    }
    return false;
}

/// A connection loss, or a server that answered that it is not ready yet
/// (BadWaitingForInitialData: a restarted world waiting to hear where a robot is): both pass.
[[nodiscard]] constexpr bool isTransient(StatusCode s) {
    return isConnectionLoss(s) || s == status::BadWaitingForInitialData;
}

}  // namespace skillcell::ua
