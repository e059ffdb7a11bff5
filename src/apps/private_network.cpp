#include "private_network.hpp"

#include <net/if.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "process/child_process.hpp"
#include "ua/discovery/network_interfaces.hpp"

namespace skillcell::apps {

bool multicastOnlyOnLoopback() {
    bool loopback = false;
    for (const auto& nic : ua::mdns::listIpv4Interfaces()) {
        if (!nic.up || !nic.multicast) continue;
        if (!nic.loopback) return false;
        loopback = true;
    }
    return loopback;
}

std::string enterPrivateNetwork() {
    if (::unshare(CLONE_NEWNET) != 0) {
        const int err = errno;
        return std::string("cannot create a private network namespace (") + std::strerror(err) +
               (err == EPERM ? "): run as root" : ")");
    }
    // A new namespace has a loopback that is down and has no multicast: raise both flags.
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return std::string("socket: ") + std::strerror(errno);
    ifreq request{};
    std::strncpy(request.ifr_name, "lo", IFNAMSIZ - 1);
    int rc = ::ioctl(fd, SIOCGIFFLAGS, &request);
    if (rc == 0) {
        request.ifr_flags = static_cast<short>(request.ifr_flags | IFF_UP | IFF_MULTICAST);
        rc = ::ioctl(fd, SIOCSIFFLAGS, &request);
    }
    const int err = errno;
    ::close(fd);
    if (rc != 0) return std::string("cannot bring the loopback up: ") + std::strerror(err);
    // Multicast needs a route; the kernel adds none for loopback. iproute2 says it best.
    auto route = process::runToCompletion({"ip", "route", "add", "224.0.0.0/4", "dev", "lo"},
                                          std::chrono::seconds(10));
    if (!route) return "cannot route multicast over the loopback: " + route.error();
    if (route->exitCode != 0) {
        return "cannot route multicast over the loopback: ip route: " + route->err;
    }
    return {};
}

}  // namespace skillcell::apps
