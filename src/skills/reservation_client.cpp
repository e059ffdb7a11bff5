#include "skills/reservation_client.hpp"

#include <asio/redirect_error.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <vector>

#include "skills/reservation.hpp"

namespace skillcell::skills {

asio::awaitable<ua::Result<std::uint64_t>> reserve(ua::Client& client, std::string holder,
                                                   bool takeover) {
    // Named locals: GCC 12 destroys temporaries of a co_await expression twice.
    std::vector<ua::Variant> in{ua::Variant(ua::String(std::move(holder))), ua::Variant(takeover)};
    const ua::NodeId object = reservationNode();
    const ua::NodeId method = reservationNode("Reserve");
    auto out = co_await client.call(object, method, std::move(in));
    if (!out) co_return out.status();
    const auto* token = out->empty() ? nullptr : (*out)[0].get<std::uint64_t>();
    if (token == nullptr) co_return ua::status::BadUnexpectedError;
    co_return *token;
}

namespace {

/// Use(token) or Release(token): the reservation's methods that take the token alone.
asio::awaitable<ua::StatusCode> callWithToken(ua::Client& client, const char* name,
                                              std::uint64_t token) {
    std::vector<ua::Variant> in{ua::Variant(token)};
    const ua::NodeId object = reservationNode();
    const ua::NodeId method = reservationNode(name);
    auto out = co_await client.call(object, method, std::move(in));
    co_return out ? ua::StatusCode(ua::status::Good) : out.status();
}

}  // namespace

asio::awaitable<ua::StatusCode> use(ua::Client& client, std::uint64_t token) {
    co_return co_await callWithToken(client, "Use", token);
}

asio::awaitable<ua::StatusCode> release(ua::Client& client, std::uint64_t token) {
    co_return co_await callWithToken(client, "Release", token);
}

asio::awaitable<std::string> reservationHolder(ua::Client& client) {
    const ua::NodeId node = reservationNode("Holder");
    auto value = co_await client.readValue(node);
    const auto* text = value ? value->get<ua::String>() : nullptr;
    co_return text != nullptr ? std::string(*text) : std::string();
}

bool noReservation(ua::StatusCode status) {
    return status == ua::status::BadNodeIdUnknown || status == ua::status::BadMethodInvalid;
}

asio::awaitable<Hold> hold(std::vector<ua::Client*> sessions, std::string holder,
                           std::chrono::milliseconds patience) {
    Hold out;
    if (sessions.empty()) co_return out;
    ua::Client& first = *sessions.front();
    auto token = co_await reserve(first, holder, /*takeover=*/false);
    // Held by another: asked again every 250 ms until `patience` is used up. Nothing tells
    // this client when a dead holder's sessions time out, so a bounded poll it is.
    const auto deadline = std::chrono::steady_clock::now() + patience;
    asio::steady_timer pause(first.executor());
    while (!token && token.status() == ua::status::BadResourceUnavailable &&
           std::chrono::steady_clock::now() + std::chrono::milliseconds(250) <= deadline) {
        pause.expires_after(std::chrono::milliseconds(250));
        std::error_code ec;
        co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ec));
        token = co_await reserve(first, holder, /*takeover=*/false);
    }
    if (!token) {
        if (noReservation(token.status())) co_return out;
        const std::string status(ua::statusName(token.status()));
        if (token.status() != ua::status::BadResourceUnavailable) {
            out.refusal = "its Reserve was refused (" + status + ")";
            co_return out;
        }
        const std::string other = co_await reservationHolder(first);
        out.refusal = "reserved by " + (other.empty() ? std::string("another holder") : other) +
                      " (" + status + ")";
        co_return out;
    }
    for (std::size_t i = 1; i < sessions.size(); ++i) {
        const ua::StatusCode bound = co_await use(*sessions[i], *token);
        if (bound.isBad()) {
            // Taken over between the two calls, or the session is gone: let go of all of it.
            (void)co_await release(first, *token);
            out.refusal = "cannot drive it through a second session: Use was refused (" +
                          std::string(ua::statusName(bound)) + ")";
            co_return out;
        }
    }
    out.token = *token;
    co_return out;
}

}  // namespace skillcell::skills
