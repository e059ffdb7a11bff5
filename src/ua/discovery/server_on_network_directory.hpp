#pragma once
// ServerOnNetworkDirectory: the records FindServersOnNetwork returns (OPC 10000-4, 5.4.3).
// Fed with the responder's "announced" / "gone" events; each announcement (and each change
// of one) gets the next recordId, so a client that pages with startingRecordId sees what
// is new since its last call. Pure logic.
#include <cstdint>
#include <map>
#include <string>

#include "ua/discovery/service_cache.hpp"
#include "ua/messages/discovery.hpp"

namespace skillcell::ua::lds {

class ServerOnNetworkDirectory {
public:
    explicit ServerOnNetworkDirectory(DateTime counterResetTime);

    void apply(const mdns::ServiceEvent& event);

    /// Records with recordId >= startingRecordId that have every capability of the filter
    /// (case-insensitive), in recordId order, at most maxRecordsToReturn (0: all).
    [[nodiscard]] std::vector<ServerOnNetwork> find(const FindServersOnNetworkRequest& req) const;
    [[nodiscard]] DateTime lastCounterResetTime() const { return counterResetTime_; }
    [[nodiscard]] std::size_t size() const { return byName_.size(); }

private:
    DateTime counterResetTime_;
    std::uint32_t nextRecordId_ = 1;
    std::map<std::string, ServerOnNetwork> byName_;  // folded mDNS name
};

}  // namespace skillcell::ua::lds
