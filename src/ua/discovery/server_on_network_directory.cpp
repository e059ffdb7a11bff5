#include "ua/discovery/server_on_network_directory.hpp"

#include <algorithm>

namespace skillcell::ua::lds {

ServerOnNetworkDirectory::ServerOnNetworkDirectory(DateTime counterResetTime)
    : counterResetTime_(counterResetTime) {}

void ServerOnNetworkDirectory::apply(const mdns::ServiceEvent& event) {
    const std::string key = mdns::foldCase(event.instance.name);
    if (event.kind == mdns::ServiceEvent::Kind::Gone) {
        byName_.erase(key);
        return;
    }
    ServerOnNetwork record;
    record.serverName = event.instance.name;
    record.discoveryUrl = event.instance.discoveryUrl();
    record.serverCapabilities = event.instance.capabilities;
    auto it = byName_.find(key);
    if (it != byName_.end() && it->second.discoveryUrl == record.discoveryUrl &&
        it->second.serverCapabilities == record.serverCapabilities) {
        return;  // nothing new
    }
    record.recordId = nextRecordId_++;
    byName_[key] = std::move(record);
}

std::vector<ServerOnNetwork> ServerOnNetworkDirectory::find(
    const FindServersOnNetworkRequest& req) const {
    std::vector<ServerOnNetwork> out;
    for (const auto& entry : byName_) {
        const ServerOnNetwork& r = entry.second;
        if (r.recordId < req.startingRecordId) continue;
        const bool hasAll = std::all_of(
            req.serverCapabilityFilter.begin(), req.serverCapabilityFilter.end(),
            [&](const String& want) {
                const std::string w = mdns::foldCase(want);
                return std::any_of(r.serverCapabilities.begin(), r.serverCapabilities.end(),
                                   [&](const String& c) { return mdns::foldCase(c) == w; });
            });
        if (hasAll) out.push_back(r);
    }
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.recordId < b.recordId; });
    if (req.maxRecordsToReturn != 0 && out.size() > req.maxRecordsToReturn) {
        out.resize(req.maxRecordsToReturn);
    }
    return out;
}

}  // namespace skillcell::ua::lds
