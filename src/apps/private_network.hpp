#pragma once
// A private network namespace for a whole cell on one machine (`skillcell demo`): its only
// interface is a loopback that carries multicast, so the components find each other by mDNS
// and nothing they announce reaches the machine's real network. The components started
// afterwards inherit it.
#include <string>

namespace skillcell::apps {

/// True when the loopback is up with multicast and no other interface is: mDNS works here
/// and stays inside (a private network already, e.g. tests/netns/run_in_private_netns.sh).
[[nodiscard]] bool multicastOnlyOnLoopback();

/// Moves this process into a new network namespace (unshare(CLONE_NEWNET), which needs root)
/// and brings its loopback up with multicast and the 224.0.0.0/4 route on it. Call it before
/// any thread starts: a namespace is per thread, and only the caller moves. Empty on success,
/// else why it failed and what to do.
[[nodiscard]] std::string enterPrivateNetwork();

}  // namespace skillcell::apps
