#pragma once
// Reservation: who may drive a component's skills (the Skills model's ReservationType, at
// Objects/Reservation; docs/skills.md, "Reservation").
//
// Free, anyone may write parameters and call the skills' methods (within the skills' own
// rules). Reserved, only sessions bound to the current fencing token may: the session that
// called Reserve, and any that called Use with the token. Every grant issues a token greater
// than any before, across restarts of the server too (it starts from the clock), so a holder
// that lost the reservation (another took it over after a failover) is refused, whatever
// session it uses: Use and Release with its old token are Bad_InvalidArgument, writes and
// methods from its sessions Bad_UserAccessDenied.
//
// The holder's sessions are its lease: once every session bound to the token has closed or
// timed out, another holder's Reserve is granted without Takeover (a holder killed for good
// does not keep the component forever). A component reserved by application code (no
// session) keeps its reservation until released.
//
// Threading: the server's thread (the address space's).
#include <cstdint>
#include <memory>
#include <set>
#include <string>

#include "ua/server/server.hpp"

namespace skillcell::skills {

class Reservation {
public:
    /// Adds Objects/Reservation (ns=1;s=Reservation) and serves its methods.
    [[nodiscard]] static ua::Result<std::shared_ptr<Reservation>> create(ua::Server& server);

    /// Whether `caller` may write a parameter or call a skill's method now.
    [[nodiscard]] bool permits(const ua::Caller& caller) const;
    [[nodiscard]] const std::string& holder() const { return holder_; }
    [[nodiscard]] std::uint64_t token() const { return token_; }

    struct Token {
    private:
        friend class Reservation;
        Token() = default;
    };
    Reservation(Token, ua::Server& server) : server_(server) {}

    /// The methods (also for application code and tests).
    ua::StatusCode reserve(const ua::Caller& caller, const std::string& holder, bool takeover,
                           std::uint64_t& token);
    ua::StatusCode use(const ua::Caller& caller, std::uint64_t token);
    ua::StatusCode release(std::uint64_t token);

private:
    void publish();

    ua::Server& server_;
    std::string holder_;
    std::uint64_t token_ = 0;  // 0: free
    std::uint64_t lastToken_ = 0;
    std::set<ua::NodeId> sessions_;  // bound to token_
};

/// Objects/Reservation and its children (ns=1): "Reserve", "Use", "Release", "Holder",
/// "FencingToken"; empty: the object.
[[nodiscard]] ua::NodeId reservationNode(const char* child = "");

}  // namespace skillcell::skills
