#include "ua/discovery/network_interfaces.hpp"

#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>

#include <algorithm>
#include <cstring>
#include <memory>

namespace skillcell::ua::mdns {

std::vector<NetworkInterface> listIpv4Interfaces() {
    std::vector<NetworkInterface> out;
    ifaddrs* list = nullptr;
    if (getifaddrs(&list) != 0) return out;
    const std::unique_ptr<ifaddrs, decltype(&freeifaddrs)> guard(list, &freeifaddrs);
    for (const ifaddrs* it = list; it != nullptr; it = it->ifa_next) {
        if (it->ifa_addr == nullptr || it->ifa_addr->sa_family != AF_INET) continue;
        NetworkInterface nic;
        nic.name = it->ifa_name;
        sockaddr_in sin{};
        std::memcpy(&sin, it->ifa_addr, sizeof sin);
        std::memcpy(nic.address.data(), &sin.sin_addr.s_addr, 4);
        nic.up = (it->ifa_flags & IFF_UP) != 0 && (it->ifa_flags & IFF_RUNNING) != 0;
        nic.loopback = (it->ifa_flags & IFF_LOOPBACK) != 0;
        nic.multicast = (it->ifa_flags & IFF_MULTICAST) != 0;
        nic.index = if_nametoindex(it->ifa_name);
        out.push_back(std::move(nic));
    }
    for (const ifaddrs* it = list; it != nullptr; it = it->ifa_next) {
        if (it->ifa_addr == nullptr || it->ifa_addr->sa_family != AF_INET6) continue;
        for (auto& nic : out) {
            if (nic.name == it->ifa_name) nic.hasIpv6 = true;
        }
    }
    return out;
}

std::vector<NetworkInterface> chooseMdnsInterfaces(const std::vector<NetworkInterface>& all,
                                                   const std::vector<std::string>& wanted) {
    std::vector<NetworkInterface> out;
    if (!wanted.empty()) {
        for (const auto& nic : all) {
            if (nic.multicast &&
                std::find(wanted.begin(), wanted.end(), nic.name) != wanted.end()) {
                out.push_back(nic);
            }
        }
        return out;
    }
    // A link that is down right now still counts: it may come back (a cable plugged in
    // again), and its address stays ours.
    for (const auto& nic : all) {
        if (nic.multicast && !nic.loopback) out.push_back(nic);
    }
    if (out.empty()) {
        for (const auto& nic : all) {
            if (nic.multicast && nic.loopback && nic.up) out.push_back(nic);
        }
    }
    return out;
}

}  // namespace skillcell::ua::mdns
