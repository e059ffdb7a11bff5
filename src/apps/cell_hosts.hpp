#pragma once
// CellHosts: the hosts of a cell run on one machine. A cell in a private network namespace
// may put components on hosts of their own (a cell file's `host` key, `cell up --host`), as a
// plant puts its MES on a PC of its own: each host is a network namespace with a hostname of
// its own (a UTS namespace: mDNS names each host), joined to the cell's namespace by a veth
// pair whose cell end, v-HOST, is a port of the cell's bridge.
//
//   cell namespace: bridge cell0 198.18.0.1/24 (the multicast route), ports v-HOST...
//   host i:         eth0 198.18.0.(i+2)/24 (its multicast route), lo
//
// Taking a host's link down (`ip link set v-HOST down` in the cell's namespace) cuts that host
// off as a pulled cable does; the rest of the cell keeps its network. Everything lives in
// namespaces no other process names: it goes when the cell's processes end.
#include <string>
#include <vector>

#include "kb/expected.hpp"
#include "process/child_process.hpp"

namespace skillcell::apps {

class CellHosts {
public:
    /// No hosts: every component in the cell's own namespace, on the loopback.
    CellHosts() = default;

    /// Makes the bridge and `hosts` (names as cell::hostProblem allows them). Call it in the
    /// cell's private namespace, as root, before any thread starts (a namespace is per
    /// thread). Nothing is made for no hosts. The error says which step failed and why.
    [[nodiscard]] static kb::Expected<CellHosts> create(const std::vector<std::string>& hosts);

    /// The address the components of `host` serve on ("": the cell's own namespace):
    /// 127.0.0.1 in a cell without hosts, else the bridge's or the host's address.
    [[nodiscard]] std::string address(const std::string& host) const;
    /// The namespaces a component of `host` enters (CellProcess::start); empty for the
    /// cell's own.
    [[nodiscard]] std::vector<int> namespaces(const std::string& host) const;
    /// The cell's end of the host's link, in the cell's namespace.
    [[nodiscard]] static std::string linkName(const std::string& host) { return "v-" + host; }
    [[nodiscard]] bool empty() const { return hosts_.empty(); }

private:
    struct Host {
        std::string name;
        std::string address;
        process::UniqueFd network;
        process::UniqueFd uts;
    };
    /// The host named `host`, or nullptr (the cell's own namespace).
    [[nodiscard]] const Host* find(const std::string& host) const;
    std::vector<Host> hosts_;
};

}  // namespace skillcell::apps
