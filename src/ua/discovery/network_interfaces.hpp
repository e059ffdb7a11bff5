#pragma once
// The host's IPv4 interfaces, and the ones mDNS should use.
#include <string>
#include <vector>

#include "ua/discovery/service_cache.hpp"

namespace skillcell::ua::mdns {

struct NetworkInterface {
    std::string name;
    unsigned index = 0;  // if_nametoindex
    Ipv4 address{};
    bool hasIpv6 = false;  // the interface also has an IPv6 address (mDNS on ff02::fb)
    bool up = false;
    bool loopback = false;
    bool multicast = false;
};

/// Every IPv4 interface address of the host (getifaddrs), with whether that interface also
/// has IPv6.
[[nodiscard]] std::vector<NetworkInterface> listIpv4Interfaces();

/// The interfaces to run mDNS on: those named in `wanted` that can multicast, or else every
/// up, multicast-capable interface except loopback, or loopback when it is the only one
/// (a private network namespace in tests). Empty when there is none.
[[nodiscard]] std::vector<NetworkInterface> chooseMdnsInterfaces(
    const std::vector<NetworkInterface>& all, const std::vector<std::string>& wanted);

}  // namespace skillcell::ua::mdns
