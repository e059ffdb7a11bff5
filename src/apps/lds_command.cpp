// `skillcell lds`: a stand-alone Local Discovery Server with the multicast extension
// (LDS-ME): servers register with it (RegisterServer, RegisterServer2), clients ask it for
// the registered servers (FindServers) and for every server mDNS sees (FindServersOnNetwork).
#include "cell/component_uris.hpp"
#include "commands.hpp"
#include "server_process.hpp"

namespace skillcell::apps {

Command addLdsCommand(CLI::App& app) {
    auto options = std::make_shared<ServerProcessOptions>();
    options->applicationUri = std::string(cell::kLdsUri);
    options->applicationName = "skillcell LDS";
    options->applicationType = ua::ApplicationType::DiscoveryServer;
    options->isLds = true;
    CLI::App* cmd = app.add_subcommand(
        "lds",
        "Run a Local Discovery Server with the multicast extension (LDS-ME): RegisterServer, "
        "RegisterServer2, FindServers, FindServersOnNetwork, announced by mDNS with the "
        "capability LDS. Prints 'READY <url>' on stdout when it accepts connections.");
    addServerProcessOptions(cmd, *options);
    addDiscoveryOptions(cmd, options->discovery, /*registers=*/false, /*isLds=*/true);
    return {cmd, [options] { return runServerProcess(*options, {}); }};
}

}  // namespace skillcell::apps
