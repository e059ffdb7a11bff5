#include "ua/discovery/registered_server_table.hpp"

#include <algorithm>
#include <filesystem>

#include "ua/discovery/mdns_responder.hpp"

namespace skillcell::ua::lds {

namespace {

bool usableUrl(std::string_view url) {
    const auto scheme = url.find("://");
    if (scheme == std::string_view::npos || scheme == 0) return false;
    const std::string s = mdns::foldCase(url.substr(0, scheme));
    if (s != "opc.tcp" && s != "opc.https" && s != "https" && s != "opc.wss" && s != "http") {
        return false;
    }
    const auto host = url.substr(scheme + 3);
    return !host.empty() && host.front() != '/' && host.front() != ':';
}

bool semaphorePresent(const std::string& path) {
    std::error_code ec;
    return std::filesystem::exists(path, ec) && !ec;
}

}  // namespace

RegisteredServerTable::RegisteredServerTable(std::chrono::seconds timeout,
                                             RegistrationLimits limits)
    : timeout_(timeout), limits_(limits) {}

StatusCode RegisteredServerTable::validate(const RegisteredServer& s) const {
    if (s.serverUri.empty() || s.serverUri.size() > limits_.maxStringBytes) {
        return status::BadServerUriInvalid;
    }
    if (!s.isOnline) return status::Good;
    if (s.serverType == ApplicationType::Client) return status::BadInvalidArgument;
    if (static_cast<std::int32_t>(s.serverType) < 0 ||
        static_cast<std::int32_t>(s.serverType) > 3) {
        return status::BadInvalidArgument;
    }
    if (s.serverNames.size() > limits_.maxNames || s.discoveryUrls.size() > limits_.maxUrls ||
        s.productUri.size() > limits_.maxStringBytes ||
        s.gatewayServerUri.size() > limits_.maxStringBytes ||
        s.semaphoreFilePath.size() > limits_.maxStringBytes) {
        return status::BadInvalidArgument;
    }
    const bool named = std::any_of(s.serverNames.begin(), s.serverNames.end(),
                                   [](const LocalizedText& t) { return !t.text.empty(); });
    if (!named) return status::BadServerNameMissing;
    if (s.discoveryUrls.empty()) return status::BadDiscoveryUrlMissing;
    for (const auto& url : s.discoveryUrls) {
        if (url.size() > limits_.maxStringBytes || !usableUrl(url)) {
            return status::BadInvalidArgument;
        }
    }
    if (!s.semaphoreFilePath.empty() && !semaphorePresent(s.semaphoreFilePath)) {
        return status::BadSemaphoreFileMissing;
    }
    return status::Good;
}

Result<RegisteredServerTable::Change> RegisteredServerTable::apply(
    const RegisteredServer& server, std::optional<MdnsDiscoveryConfiguration> mdns,
    Clock::time_point now) {
    auto it = servers_.find(server.serverUri);
    if (!server.isOnline) {
        if (it == servers_.end()) return Change::NotFound;
        servers_.erase(it);
        return Change::Removed;
    }
    if (it == servers_.end()) {
        if (servers_.size() >= limits_.maxServers) return status::BadResourceUnavailable;
        servers_.emplace(server.serverUri, Registration{server, std::move(mdns), now});
        return Change::Added;
    }
    auto& r = it->second;
    r.renewed = now;
    const bool same = RegisteredServer::tie(r.server) == RegisteredServer::tie(server) &&
                      mdns.has_value() == r.mdns.has_value() &&
                      (!mdns || (mdns->mdnsServerName == r.mdns->mdnsServerName &&
                                 mdns->serverCapabilities == r.mdns->serverCapabilities));
    if (same) return Change::Renewed;
    r.server = server;
    r.mdns = std::move(mdns);
    return Change::Updated;
}

bool RegisteredServerTable::remove(const std::string& serverUri) {
    return servers_.erase(serverUri) > 0;
}

std::vector<Registration> RegisteredServerTable::expire(Clock::time_point now) {
    std::vector<Registration> gone;
    for (auto it = servers_.begin(); it != servers_.end();) {
        const auto& r = it->second;
        const bool timedOut = now - r.renewed > timeout_;
        const bool semaphoreGone =
            !r.server.semaphoreFilePath.empty() && !semaphorePresent(r.server.semaphoreFilePath);
        if (timedOut || semaphoreGone) {
            gone.push_back(r);
            it = servers_.erase(it);
        } else {
            ++it;
        }
    }
    return gone;
}

std::vector<ApplicationDescription> RegisteredServerTable::describe(
    const std::vector<String>& serverUris, const std::vector<String>& localeIds) const {
    std::vector<ApplicationDescription> out;
    for (const auto& [uri, r] : servers_) {
        if (!serverUris.empty() &&
            std::find(serverUris.begin(), serverUris.end(), uri) == serverUris.end()) {
            continue;
        }
        const auto& s = r.server;
        ApplicationDescription d;
        d.applicationUri = s.serverUri;
        d.productUri = s.productUri;
        d.applicationType = s.serverType;
        d.gatewayServerUri = s.gatewayServerUri;
        d.discoveryUrls = s.discoveryUrls;
        d.applicationName = s.serverNames.front();
        for (const auto& locale : localeIds) {
            auto named = std::find_if(s.serverNames.begin(), s.serverNames.end(),
                                      [&](const LocalizedText& t) { return t.locale == locale; });
            if (named != s.serverNames.end()) {
                d.applicationName = *named;
                break;
            }
        }
        out.push_back(std::move(d));
    }
    return out;
}

const Registration* RegisteredServerTable::find(const std::string& serverUri) const {
    auto it = servers_.find(serverUri);
    return it == servers_.end() ? nullptr : &it->second;
}

const Registration* RegisteredServerTable::findByMdnsName(std::string_view name) const {
    const std::string key = mdns::foldCase(name);
    for (const auto& [uri, r] : servers_) {
        if (mdns::foldCase(mdnsNameOf(r)) == key) return &r;
    }
    return nullptr;
}

std::string mdnsNameOf(const Registration& r) {
    if (r.mdns && !r.mdns->mdnsServerName.empty()) return r.mdns->mdnsServerName;
    std::string name;
    for (const auto& t : r.server.serverNames) {
        if (!t.text.empty()) {
            name = t.text;
            break;
        }
    }
    for (char& c : name) {
        if (c == '.' || static_cast<unsigned char>(c) < 0x20) c = '-';
    }
    if (name.size() > 63) name.resize(63);
    return name;
}

}  // namespace skillcell::ua::lds
