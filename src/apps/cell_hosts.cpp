#include "cell_hosts.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

namespace skillcell::apps {

namespace {

constexpr const char* kBridge = "cell0";
constexpr const char* kSubnet = "198.18.0.";  // RFC 2544's benchmarking range, as the tests'
constexpr int kPrefix = 24;
constexpr std::size_t kMaxHosts = 250;  // .2 to .251

std::string errnoText() {
    return std::strerror(errno);  // NOLINT(concurrency-mt-unsafe): before any thread starts
}

process::UniqueFd openNamespace(const char* kind) {
    return process::UniqueFd(
        ::open((std::string("/proc/thread-self/ns/") + kind).c_str(), O_RDONLY | O_CLOEXEC));
}

/// Runs `ip ARGS...` (in `namespaces`, else ours); why it failed, or empty.
std::string ip(std::vector<std::string> args, const std::vector<int>& namespaces = {}) {
    args.insert(args.begin(), "ip");
    process::ProcessOptions options;
    options.namespaces = namespaces;
    auto run = process::runToCompletion(args, std::chrono::seconds(10), options);
    std::string command;
    for (const auto& a : args) command += (command.empty() ? "" : " ") + a;
    if (!run) return command + ": " + run.error();
    if (run->exitCode != 0) return command + ": " + run->err;
    return {};
}

}  // namespace

kb::Expected<CellHosts> CellHosts::create(const std::vector<std::string>& hosts) {
    CellHosts out;
    if (hosts.empty()) return out;
    if (hosts.size() > kMaxHosts) {
        return kb::Error{"a cell has at most " + std::to_string(kMaxHosts) + " hosts, not " +
                         std::to_string(hosts.size())};
    }
    auto failed = [](const std::string& why) {
        return kb::Error{"cannot make the cell's hosts: " + why};
    };
    // The cell's namespace gets a bridge, which carries its multicast from now on: the
    // components here announce and answer on it, and the hosts' links join it.
    for (auto args : std::vector<std::vector<std::string>>{
             // No IGMP/MLD snooping: with no querier on the segment it would hold back
             // IPv6 mDNS (ff02::fb) from ports whose reports it missed.
             {"link", "add", kBridge, "type", "bridge", "mcast_snooping", "0"},
             {"addr", "add", std::string(kSubnet) + "1/" + std::to_string(kPrefix), "dev", kBridge},
             {"link", "set", kBridge, "up"},
             {"route", "replace", "224.0.0.0/4", "dev", kBridge}}) {
        if (auto why = ip(std::move(args)); !why.empty()) return failed(why);
    }
    const process::UniqueFd cellNetwork = openNamespace("net");
    const process::UniqueFd cellUts = openNamespace("uts");
    if (!cellNetwork.valid() || !cellUts.valid())
        return failed("/proc/thread-self/ns: " + errnoText());
    const std::string self = "/proc/" + std::to_string(::getpid()) + "/fd/";
    for (std::size_t i = 0; i < hosts.size(); ++i) {
        Host h;
        h.name = hosts[i];
        h.address = kSubnet + std::to_string(i + 2);
        // A namespace is made by moving into it: this thread goes there and comes back.
        if (::unshare(CLONE_NEWNET | CLONE_NEWUTS) != 0) return failed("unshare: " + errnoText());
        h.network = openNamespace("net");
        h.uts = openNamespace("uts");
        const bool named = ::sethostname(h.name.data(), h.name.size()) == 0;
        const int err = errno;
        if (::setns(cellNetwork.get(), CLONE_NEWNET) != 0 ||
            ::setns(cellUts.get(), CLONE_NEWUTS) != 0) {
            return failed("cannot return to the cell's namespace: " + errnoText());
        }
        if (!h.network.valid() || !h.uts.valid())
            return failed("host " + h.name + ": " + errnoText());
        if (!named) return failed("host " + h.name + ": sethostname: " + std::strerror(err));
        const std::string link = linkName(h.name);
        const std::vector<int> inside = {h.network.get(), h.uts.get()};
        for (auto [args, where] : std::vector<std::pair<std::vector<std::string>, bool>>{
                 {{"link", "add", link, "type", "veth", "peer", "name", "eth0", "netns",
                   self + std::to_string(h.network.get())},
                  false},
                 {{"link", "set", link, "master", kBridge, "up"}, false},
                 {{"link", "set", "lo", "up"}, true},
                 {{"addr", "add", h.address + "/" + std::to_string(kPrefix), "dev", "eth0"}, true},
                 {{"link", "set", "eth0", "up"}, true},
                 {{"route", "add", "224.0.0.0/4", "dev", "eth0"}, true}}) {
            if (auto why = ip(args, where ? inside : std::vector<int>{}); !why.empty()) {
                return failed("host " + h.name + ": " + why);
            }
        }
        out.hosts_.push_back(std::move(h));
    }
    return out;
}

const CellHosts::Host* CellHosts::find(const std::string& host) const {
    const auto it =
        std::find_if(hosts_.begin(), hosts_.end(), [&](const Host& h) { return h.name == host; });
    return it == hosts_.end() ? nullptr : &*it;
}

std::string CellHosts::address(const std::string& host) const {
    if (hosts_.empty()) return "127.0.0.1";
    const Host* h = find(host);
    return h != nullptr ? h->address : std::string(kSubnet) + "1";
}

std::vector<int> CellHosts::namespaces(const std::string& host) const {
    const Host* h = find(host);
    return h != nullptr ? std::vector<int>{h->network.get(), h->uts.get()} : std::vector<int>{};
}

}  // namespace skillcell::apps
