#include "skills/reservation.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "ua/address_space/instantiate.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::skills {
namespace {

// Tokens start from the clock (µs since 1970), so that a restarted server never grants a
// token it granted before it stopped.
std::uint64_t clockToken() {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                          std::chrono::system_clock::now().time_since_epoch())
                                          .count());
}

}  // namespace

ua::NodeId reservationNode(const char* child) {
    const std::string name = std::string("Reservation") + (*child != '\0' ? "/" : "") + child;
    return ua::NodeId(1, ua::String(name));
}

ua::Result<std::shared_ptr<Reservation>> Reservation::create(ua::Server& server) {
    ua::AddressSpace& as = server.addressSpace();
    const auto type = ua::skillsNodeId(as, ua::companion::kReservationType);
    if (!type) return ua::status::BadTypeDefinitionInvalid;
    ua::InstantiateOptions options;
    options.nodeId = reservationNode();
    auto id = ua::instantiate(as, *type, ua::NodeId(ua::ns0::ObjectsFolder),
                              ua::NodeId(ua::ns0::Organizes), ua::QualifiedName{1, "Reservation"},
                              options);
    if (!id) return id.status();
    auto r = std::make_shared<Reservation>(Token{}, server);
    std::weak_ptr<Reservation> weak = r;
    const auto reserve = as.setMethodCallback(
        reservationNode("Reserve"),
        [weak](const ua::Caller& caller, const ua::NodeId&, std::span<const ua::Variant> in,
               std::vector<ua::Variant>& out) -> ua::StatusCode {
            auto self = weak.lock();
            const auto* holder = ua::methodInput<ua::String>(in, 0);
            const auto* takeover = ua::methodInput<bool>(in, 1);
            if (!self) return ua::status::BadInvalidState;
            if (holder == nullptr || takeover == nullptr) return ua::status::BadInvalidArgument;
            std::uint64_t token = 0;
            const auto s = self->reserve(caller, *holder, *takeover, token);
            if (s.isGood()) out.emplace_back(token);
            return s;
        });
    const auto use = as.setMethodCallback(
        reservationNode("Use"),
        [weak](const ua::Caller& caller, const ua::NodeId&, std::span<const ua::Variant> in,
               std::vector<ua::Variant>&) -> ua::StatusCode {
            auto self = weak.lock();
            const auto* token = ua::methodInput<std::uint64_t>(in, 0);
            if (!self) return ua::status::BadInvalidState;
            if (token == nullptr) return ua::status::BadInvalidArgument;
            return self->use(caller, *token);
        });
    const auto release = as.setMethodCallback(
        reservationNode("Release"),
        [weak](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
               std::vector<ua::Variant>&) -> ua::StatusCode {
            auto self = weak.lock();
            const auto* token = ua::methodInput<std::uint64_t>(in, 0);
            if (!self) return ua::status::BadInvalidState;
            if (token == nullptr) return ua::status::BadInvalidArgument;
            return self->release(*token);
        });
    for (const auto s : {reserve, use, release}) {
        if (s.isBad()) return s;
    }
    r->publish();
    return r;
}

bool Reservation::permits(const ua::Caller& caller) const {
    // Application code (no session) acts for the component itself.
    return token_ == 0 || caller.sessionId.isNull() || sessions_.contains(caller.sessionId);
}

ua::StatusCode Reservation::reserve(const ua::Caller& caller, const std::string& holder,
                                    bool takeover, std::uint64_t& token) {
    if (holder.empty()) return ua::status::BadInvalidArgument;
    // The holder's lease: its sessions. When every session bound to the token has closed or
    // timed out (a composite killed mid-run, an MES gone for longer than its session
    // timeout), the reservation no longer keeps others out.
    const bool orphaned = !sessions_.empty() && std::none_of(sessions_.begin(), sessions_.end(),
                                                             [this](const ua::NodeId& s) {
                                                                 return server_.hasSession(s);
                                                             });
    if (token_ != 0 && holder != holder_ && !takeover && !orphaned) {
        spdlog::info("reservation: {} refused: {} holds it", holder, holder_);
        return ua::status::BadResourceUnavailable;
    }
    if (token_ != 0 && holder != holder_) {
        spdlog::warn("reservation: {} takes it over from {}{}", holder, holder_,
                     orphaned ? ", none of whose sessions is left" : "");
    }
    lastToken_ = std::max(lastToken_ + 1, clockToken());
    token_ = lastToken_;
    holder_ = holder;
    sessions_.clear();
    if (!caller.sessionId.isNull()) sessions_.insert(caller.sessionId);
    token = token_;
    publish();
    return ua::status::Good;
}

ua::StatusCode Reservation::use(const ua::Caller& caller, std::uint64_t token) {
    if (token_ == 0) return ua::status::BadInvalidState;         // nothing to use: free
    if (token != token_) return ua::status::BadInvalidArgument;  // stale or made up
    if (!caller.sessionId.isNull()) sessions_.insert(caller.sessionId);
    return ua::status::Good;
}

ua::StatusCode Reservation::release(std::uint64_t token) {
    if (token_ == 0 || token != token_) return ua::status::BadInvalidArgument;
    token_ = 0;
    holder_.clear();
    sessions_.clear();
    publish();
    return ua::status::Good;
}

void Reservation::publish() {
    ua::AddressSpace& as = server_.addressSpace();
    (void)as.setValue(reservationNode("Holder"), ua::Variant(ua::String(holder_)));
    (void)as.setValue(reservationNode("FencingToken"), ua::Variant(token_));
}

}  // namespace skillcell::skills
