#include "skills/reservation_client.hpp"

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

asio::awaitable<ua::StatusCode> release(ua::Client& client, std::uint64_t token) {
    std::vector<ua::Variant> in{ua::Variant(token)};
    const ua::NodeId object = reservationNode();
    const ua::NodeId method = reservationNode("Release");
    auto out = co_await client.call(object, method, std::move(in));
    co_return out ? ua::StatusCode(ua::status::Good) : out.status();
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

}  // namespace skillcell::skills
